// Figure text: DejaVu Sans from its file, through FreeType and Cairo, bypassing fontconfig.

#include "font.hpp"

#include <ft2build.h>
#include FT_FREETYPE_H
#include <cairo-ft.h>

#include "barn/core/errors.hpp"

namespace barn::viz::detail {
namespace {

// ---------------------------------------------------------------------------
// One font file, loaded with FreeType directly
//
// Cairo's toy text API (cairo_select_font_face) finds fonts through fontconfig. That makes a
// figure depend on which fonts the machine has installed and configured, and fontconfig's
// caches hold offset-encoded pointers that LeakSanitizer reports as leaks in every ASan test
// that renders. Loading one named file with FreeType and handing the face to Cairo
// (cairo_ft_font_face_create_for_ft_face) avoids both: fontconfig is never called, and a
// figure depends on that file alone (and on the FreeType and Cairo versions that draw it).
// Hinting is off, so an advance is the font's own, scaled, whatever the drawing's transform.
//
// The face is loaded once, on first use, and never changes afterwards; a C++ function-local
// static gives thread-safe initialisation, and a load that throws is tried again next time.

// The FreeType library and face behind a Cairo font face: Cairo may keep the face past our
// reference (its font caches), so it frees them itself when its last reference goes.
struct FreeTypeFace {
  FT_Library library;
  FT_Face face;
  static void release(void* data) {
    auto* owned = static_cast<FreeTypeFace*>(data);
    FT_Done_Face(owned->face);
    FT_Done_FreeType(owned->library);
    delete owned;
  }
};
const cairo_user_data_key_t kFreeTypeFaceKey{};

const FontFace& fontFace() {
  static const FontFace font(kFontFile);
  return font;
}

// Cairo refuses a string that is not UTF-8 (and then draws nothing more on the context): a
// malformed byte sequence becomes '?'.
std::string validUtf8(const std::string& text) {
  std::string out;
  out.reserve(text.size());
  for (std::size_t i = 0; i < text.size();) {
    const auto lead = static_cast<unsigned char>(text[i]);
    const std::size_t length = lead < 0x80 ? 1 : (lead >> 5) == 0x6 ? 2 : (lead >> 4) == 0xE ? 3 : (lead >> 3) == 0x1E ? 4 : 0;
    bool ok = length > 0 && i + length <= text.size() && (length != 2 || lead >= 0xC2) && (length != 4 || lead <= 0xF4);
    for (std::size_t k = 1; ok && k < length; ++k) ok = (static_cast<unsigned char>(text[i + k]) & 0xC0) == 0x80;
    if (ok && length == 3) {
      const auto second = static_cast<unsigned char>(text[i + 1]);
      ok = !(lead == 0xE0 && second < 0xA0) && !(lead == 0xED && second >= 0xA0);  // overlong; surrogates
    }
    if (ok && length == 4) {
      const auto second = static_cast<unsigned char>(text[i + 1]);
      ok = !(lead == 0xF0 && second < 0x90) && !(lead == 0xF4 && second >= 0x90);  // overlong; past U+10FFFF
    }
    if (ok && lead != 0) {
      out.append(text, i, length);
      i += length;
    } else {
      out += '?';
      ++i;
    }
  }
  return out;
}

}  // namespace

FontFace::FontFace(const std::string& file) {
  FT_Library library = nullptr;
  if (FT_Init_FreeType(&library) != 0) throw core::IoError(file + ": cannot start FreeType to load the figures' font");
  FT_Face face = nullptr;
  if (FT_New_Face(library, file.c_str(), 0, &face) != 0) {
    FT_Done_FreeType(library);
    throw core::InputError(file + ": cannot load the figures' font (" + kFontFile +
                           " is in Debian's fonts-dejavu-core; tools/setup.sh installs it)");
  }
  face_ = cairo_ft_font_face_create_for_ft_face(face, 0);
  auto* owned = new FreeTypeFace{library, face};
  if (cairo_font_face_set_user_data(face_, &kFreeTypeFaceKey, owned, &FreeTypeFace::release) != CAIRO_STATUS_SUCCESS) {
    FreeTypeFace::release(owned);
    cairo_font_face_destroy(face_);
    throw core::IoError(file + ": Cairo cannot take the figures' font");
  }
  options_ = cairo_font_options_create();
  cairo_font_options_set_hint_style(options_, CAIRO_HINT_STYLE_NONE);
  cairo_font_options_set_hint_metrics(options_, CAIRO_HINT_METRICS_OFF);
  cairo_font_options_set_antialias(options_, CAIRO_ANTIALIAS_GRAY);
}

FontFace::~FontFace() {
  cairo_font_options_destroy(options_);
  cairo_font_face_destroy(face_);
}

double textWidth(const std::string& text, double size) {
  const FontFace& font = fontFace();
  cairo_matrix_t font_matrix;
  cairo_matrix_init_scale(&font_matrix, size, size);
  cairo_matrix_t identity;
  cairo_matrix_init_identity(&identity);
  cairo_scaled_font_t* scaled = cairo_scaled_font_create(font.face(), &font_matrix, &identity, font.options());
  cairo_text_extents_t extents{};
  cairo_scaled_font_text_extents(scaled, validUtf8(text).c_str(), &extents);
  const bool ok = cairo_scaled_font_status(scaled) == CAIRO_STATUS_SUCCESS;
  cairo_scaled_font_destroy(scaled);
  if (!ok) throw core::IoError(std::string(kFontFile) + ": Cairo cannot measure text in it");
  return extents.x_advance;
}

void drawText(cairo_t* cr, const std::string& text, double x, double baseline, double size) {
  const FontFace& font = fontFace();
  cairo_save(cr);
  cairo_set_font_face(cr, font.face());
  cairo_set_font_options(cr, font.options());
  cairo_set_font_size(cr, size);
  cairo_new_path(cr);
  cairo_move_to(cr, x, baseline);
  cairo_show_text(cr, validUtf8(text).c_str());
  cairo_new_path(cr);
  cairo_restore(cr);
}

}  // namespace barn::viz::detail
