#pragma once
// Text in the PNG, PDF and SVG renderers (world pictures, charts): one fixed font file drawn by
// Cairo's FreeType backend, never looked up through fontconfig (why: font.cpp).

#include <string>

#include <cairo.h>

namespace barn::viz::detail {

/// The font every figure is drawn in: Debian's fonts-dejavu-core (tools/setup.sh installs it).
inline constexpr const char* kFontFile = "/usr/share/fonts/truetype/dejavu/DejaVuSans.ttf";

// DejaVu Sans' heights, as fractions of the font size (its glyphs 'H' and 'x' in font units of
// 2048 to the em): what centres a line of text on a point.
inline constexpr double kCapHeight = 1493.0 / 2048.0;  // [em] capitals and, without overshoot, digits
inline constexpr double kXHeight = 1120.0 / 2048.0;    // [em] lower-case letters without ascenders

/// A font file loaded with FreeType and handed to Cairo, no fontconfig involved; immutable.
class FontFace {
 public:
  /// InputError naming `file` (and the package that holds kFontFile) if it cannot be loaded.
  explicit FontFace(const std::string& file);
  ~FontFace();
  FontFace(const FontFace&) = delete;
  FontFace& operator=(const FontFace&) = delete;

  cairo_font_face_t* face() const { return face_; }
  /// Unhinted outlines and metrics, grey antialiasing: the same shapes at any transform.
  const cairo_font_options_t* options() const { return options_; }

 private:
  cairo_font_face_t* face_ = nullptr;
  cairo_font_options_t* options_ = nullptr;
};

/// Advance of `text` at font size `size` (the em, in the units of the drawing). [px]
/// InputError naming kFontFile when the font cannot be loaded.
double textWidth(const std::string& text, double size);

/// Fills `text` with its baseline starting at (x, baseline) in the current user space, in the
/// current source colour; leaves no current path. InputError as textWidth.
void drawText(cairo_t* cr, const std::string& text, double x, double baseline, double size);

}  // namespace barn::viz::detail
