#pragma once
// Drawing helpers shared by the renderers (world pictures, trajectory overlays, plots):
// Cairo ownership, colours, number formatting, the one output path (PNG, PDF or SVG by
// extension), and the layers of a BARN world picture in the world frame. Private to barn_viz; the layout rules are documented in
// barn/viz/world_render.hpp and barn/viz/plots.hpp.

#include <cairo.h>

#include <charconv>
#include <filesystem>
#include <memory>
#include <optional>
#include <string>
#include <vector>

#include <Eigen/Core>

#include "barn/core/grid.hpp"
#include "barn/core/protocol.hpp"
#include "barn/core/world.hpp"
#include "barn/viz/image_format.hpp"
#include "font.hpp"

namespace barn::viz::detail {

// ---------------------------------------------------------------------------
// Colours, Cairo objects, output

struct Rgb {
  double r;  // [0, 1]
  double g;  // [0, 1]
  double b;  // [0, 1]
};

inline constexpr Rgb kCellColour{0.86, 0.86, 0.86};
inline constexpr Rgb kObstacleColour{0.648, 0.192, 0.192};
inline constexpr Rgb kWallColour{0.152, 0.379, 0.720};
inline constexpr Rgb kPathColour{0.10, 0.60, 0.25};
inline constexpr Rgb kInkColour{0.10, 0.10, 0.10};  // start, goal, text, scale bar

/// Cairo refuses image surfaces larger than this on either side. [px]
inline constexpr int kMaxImageSide = 32767;

void setColour(cairo_t* cr, const Rgb& c);

struct SurfaceDeleter {
  void operator()(cairo_surface_t* surface) const { cairo_surface_destroy(surface); }
};
struct ContextDeleter {
  void operator()(cairo_t* cr) const { cairo_destroy(cr); }
};
using SurfacePtr = std::unique_ptr<cairo_surface_t, SurfaceDeleter>;
using ContextPtr = std::unique_ptr<cairo_t, ContextDeleter>;

/// A Cairo surface and its context; every object is released on all paths.
struct Canvas {
  SurfacePtr surface;
  ContextPtr context;
  cairo_t* cr() const { return context.get(); }
};

/// Removes a file that was not finished (an exception between creating and finishing an image).
struct RemoveUnfinished {
  void operator()(std::filesystem::path* path) const;
};

/// A canvas writing to `path` in the format of its extension (imageFormatFor): an ARGB32 image
/// for PNG, a vector surface (1 unit = 1 pt) for PDF and SVG; white. Every figure is drawn
/// through one. The file appears only when finishImage succeeds: it is drawn into
/// "<path>.partial" and renamed, and a canvas dropped unfinished removes that temporary.
struct OutputCanvas {
  // Declared first, so it is released last: after the surface has closed the temporary.
  std::unique_ptr<std::filesystem::path, RemoveUnfinished> unfinished;
  Canvas canvas;
  ImageFormat format = ImageFormat::Png;
  std::filesystem::path path;
  std::filesystem::path temporary;
  cairo_t* cr() const { return canvas.cr(); }
};
/// Throws core::InputError "<path>: ..." for an unknown extension, an image side outside
/// 1 ... kMaxImageSide px, or a file that cannot be created.
OutputCanvas createOutputCanvas(int width, int height, const std::filesystem::path& path);
/// Checks for drawing errors (std::runtime_error), writes or finishes the file and moves it
/// into place; core::InputError "<path>: cannot write ..." if it cannot be written.
void finishImage(OutputCanvas& output);

/// `value` in the given format; to_chars, not printf, so the process locale cannot turn the
/// decimal point into a comma.
std::string formatNumber(double value, std::chars_format format, int precision);

// ---------------------------------------------------------------------------
// Text placement and ticks (device pixels)

/// The baseline that centres digits and capitals (kCapHeight of the font size tall) on `y`.
inline double centredBaseline(double y, double size) { return y + 0.5 * kCapHeight * size; }
/// The baseline that centres lower-case letters (kXHeight of the font size tall) on `y`.
inline double xCentredBaseline(double y, double size) { return y + 0.5 * kXHeight * size; }

void drawCentred(cairo_t* cr, const std::string& text, double centre_x, double baseline, double size);
void drawRightAligned(cairo_t* cr, const std::string& text, double right_x, double baseline, double size);
/// Text reading bottom to top, centred on (x, centre_y), with its baseline at x (capitals
/// reach kCapHeight of the size left of it, descenders about a quarter right).
void drawVertical(cairo_t* cr, const std::string& text, double baseline_x, double centre_y, double size);

/// Tick spacing of 1, 2 or 5 x 10^k giving at most about `target` intervals over `span` (> 0).
double niceStep(double span, int target);

/// A tick value with the decimals its step needs, "-0" written as "0".
std::string tickText(double value, double step);

/// Adds a closed circle to the current path without joining it to the previous point.
void addCircle(cairo_t* cr, const Eigen::Vector2d& centre, double radius);
/// Adds (does not stroke) an interval bar: a vertical line at x from y0 to y1 and, if
/// cap_half_width > 0, a cap of that half width at each end.
void addIntervalBar(cairo_t* cr, double x, double y0, double y1, double cap_half_width);

// ---------------------------------------------------------------------------
// World pictures (see barn/viz/world_render.hpp for the layout)

/// Corridor box: outer edges of the containment walls and the last field column. [m]
inline constexpr double kCorridorMinX = -4.5;  // [m]
inline constexpr double kCorridorMaxX = 0.0;   // [m]
inline constexpr double kCorridorMinY = 0.0;   // [m]
inline constexpr double kCorridorMaxY = 9.6;   // [m]
inline constexpr double kWorldMargin = 0.6;    // [m] on every side; holds the title and scale bar

/// The world-frame rectangle shown in the image, before the margin is added. [m]
struct ViewBox {
  double min_x;  // [m]
  double max_x;  // [m]
  double min_y;  // [m]
  double max_y;  // [m]
};

/// Corridor plus goal disc, so a protocol with a farther goal still fits in the picture.
ViewBox viewBox(const core::Protocol& protocol);

/// Image size of a world picture: the view box plus the margins, plus `extra_width` metres on
/// the right. Throws core::InputError naming `where` if pixels_per_metre is not positive or a
/// side is outside 1 ... kMaxImageSide px.
struct ImageSize {
  int width;   // [px]
  int height;  // [px]
};
ImageSize worldImageSize(const ViewBox& view, double pixels_per_metre, double extra_width,
                         const std::string& where);

/// World metres to pixels with y flipped, so the robot drives up the page.
cairo_matrix_t worldToPixels(const ViewBox& view, double pixels_per_metre);

/// How the A* reference path is drawn.
struct PathStyle {
  Rgb colour = kPathColour;
  double width = 0.03;        // [m] line width
  double dot_radius = 0.035;  // [m] dot on each path cell; 0 = no dots
};

// Layers, drawn in world coordinates (metres, y up; see worldToPixels).
void drawOccupiedCells(cairo_t* cr, const core::Grid& grid);
void drawCylinders(cairo_t* cr, const core::Grid& grid, bool show_containment);
void drawPath(cairo_t* cr, const std::vector<core::Cell>& path, const core::Protocol& protocol,
              const PathStyle& style);
void drawStartPose(cairo_t* cr, const core::Protocol& protocol);
void drawGoal(cairo_t* cr, const core::Protocol& protocol);
/// The world as every picture of it shows it (renderWorld, renderTrajectories), in world
/// coordinates: occupied cells, cylinders (with their containment rings if asked), the A* path
/// in `path`'s style (none if empty), the goal and the start pose.
void drawWorldLayer(cairo_t* cr, const core::WorldSpec& world, const core::Protocol& protocol, bool show_containment,
                    const std::optional<PathStyle>& path);

/// "world <id>  fill <pct>  smooth <n>  OT <s> s".
std::string worldTitle(const core::WorldSpec& world, const core::Protocol& protocol);

/// Title in the top margin (device pixels), shrunk to fit between the side margins of a
/// `width_px` wide picture.
void drawWorldTitle(cairo_t* cr, const std::string& title, double pixels_per_metre,
                    double width_px);

/// A 1 m scale bar starting at (left_px, baseline_px), device pixels.
void drawScaleBar(cairo_t* cr, double left_px, double baseline_px, double pixels_per_metre);

/// The frame of a world picture, in device pixels: worldTitle in the top margin, fitted to
/// `title_width_px`, and the scale bar in the bottom margin, left-aligned with the view box.
void drawWorldFrame(cairo_t* cr, const core::WorldSpec& world, const core::Protocol& protocol, const ViewBox& view,
                    double pixels_per_metre, double title_width_px);

}  // namespace barn::viz::detail
