#include "drawing.hpp"

#include <cairo-pdf.h>
#include <cairo-svg.h>

#include <algorithm>
#include <cctype>
#include <cmath>
#include <numbers>
#include <stdexcept>
#include <system_error>

#include "barn/core/errors.hpp"
#include "barn/core/robot_config.hpp"
#include "barn/core/world_geometry.hpp"
#include "font.hpp"

namespace barn::viz::detail {
namespace {

constexpr double kOutlineWidth = 0.025;  // [m]
constexpr double kTitleHeight = 0.2;     // [m] font size of the title
constexpr double kLabelHeight = 0.16;    // [m] font size of the scale-bar label

Canvas imageCanvas(int width, int height, const std::string& where) {
  Canvas canvas;
  canvas.surface.reset(cairo_image_surface_create(CAIRO_FORMAT_ARGB32, width, height));
  canvas.context.reset(cairo_create(canvas.surface.get()));
  if (cairo_status(canvas.cr()) != CAIRO_STATUS_SUCCESS) {
    throw std::runtime_error(where + ": cannot create a Cairo image: " +
                             cairo_status_to_string(cairo_status(canvas.cr())));
  }
  return canvas;
}

}  // namespace

// ---------------------------------------------------------------------------
// Colours, Cairo objects, output

void setColour(cairo_t* cr, const Rgb& c) { cairo_set_source_rgb(cr, c.r, c.g, c.b); }

void RemoveUnfinished::operator()(std::filesystem::path* path) const {
  std::error_code ignored;
  std::filesystem::remove(*path, ignored);
  delete path;
}

OutputCanvas createOutputCanvas(int width, int height, const std::filesystem::path& path) {
  const std::string where = path.string();
  OutputCanvas output;
  output.format = imageFormatFor(path);
  if (width < 1 || height < 1 || width > kMaxImageSide || height > kMaxImageSide) {
    throw core::InputError(where + ": image of " + std::to_string(width) + " x " + std::to_string(height) +
                           " px is out of range (1 ... " + std::to_string(kMaxImageSide) + " px a side)");
  }
  output.path = path;
  output.temporary = path;
  output.temporary += ".partial";
  if (output.format == ImageFormat::Png) {
    output.canvas = imageCanvas(width, height, where);
  } else {
    // A vector surface writes its file as it goes, so the temporary exists from here on.
    output.unfinished.reset(new std::filesystem::path(output.temporary));
    const std::string file = output.temporary.string();
    cairo_surface_t* surface = output.format == ImageFormat::Pdf
                                   ? cairo_pdf_surface_create(file.c_str(), width, height)
                                   : cairo_svg_surface_create(file.c_str(), width, height);
    output.canvas.surface.reset(surface);
    if (cairo_surface_status(surface) != CAIRO_STATUS_SUCCESS) {
      throw core::IoError(where + ": cannot write: " + cairo_status_to_string(cairo_surface_status(surface)));
    }
    output.canvas.context.reset(cairo_create(surface));
  }
  cairo_t* cr = output.cr();
  cairo_set_source_rgb(cr, 1.0, 1.0, 1.0);
  cairo_paint(cr);
  return output;
}

void finishImage(OutputCanvas& output) {
  const std::string where = output.path.string();
  cairo_t* cr = output.cr();
  if (cairo_status(cr) != CAIRO_STATUS_SUCCESS)
    throw std::runtime_error(where + ": drawing failed: " + cairo_status_to_string(cairo_status(cr)));
  cairo_surface_t* surface = output.canvas.surface.get();
  cairo_status_t status = CAIRO_STATUS_SUCCESS;
  if (output.format == ImageFormat::Png) {
    output.unfinished.reset(new std::filesystem::path(output.temporary));
    cairo_surface_flush(surface);
    status = cairo_surface_write_to_png(surface, output.temporary.string().c_str());
  } else {
    output.canvas.context.reset();
    cairo_surface_finish(surface);
    status = cairo_surface_status(surface);
  }
  if (status != CAIRO_STATUS_SUCCESS) throw core::IoError(where + ": cannot write: " + cairo_status_to_string(status));
  std::error_code ec;
  std::filesystem::rename(output.temporary, output.path, ec);
  if (ec) throw core::IoError(where + ": cannot write: " + ec.message());
  delete output.unfinished.release();  // renamed: no temporary left to remove
}

std::string formatNumber(double value, std::chars_format format, int precision) {
  char buffer[400];  // fixed notation of 1e308 needs 309 digits
  const std::to_chars_result result =
      std::to_chars(buffer, buffer + sizeof buffer, value, format, precision);
  if (result.ec != std::errc{}) return "?";
  return std::string(buffer, result.ptr);
}

void drawCentred(cairo_t* cr, const std::string& text, double centre_x, double baseline, double size) {
  drawText(cr, text, centre_x - 0.5 * textWidth(text, size), baseline, size);
}

void drawRightAligned(cairo_t* cr, const std::string& text, double right_x, double baseline, double size) {
  drawText(cr, text, right_x - textWidth(text, size), baseline, size);
}

void drawVertical(cairo_t* cr, const std::string& text, double baseline_x, double centre_y, double size) {
  cairo_save(cr);
  cairo_translate(cr, baseline_x, centre_y + 0.5 * textWidth(text, size));
  cairo_rotate(cr, -0.5 * std::numbers::pi);
  drawText(cr, text, 0.0, 0.0, size);
  cairo_restore(cr);
}

double niceStep(double span, int target) {
  const double raw = span / target;
  const double power = std::pow(10.0, std::floor(std::log10(raw)));
  for (double m : {1.0, 2.0, 5.0}) {
    if (m * power >= raw * (1.0 - 1e-9)) return m * power;
  }
  return 10.0 * power;
}

std::string tickText(double value, double step) {
  const int decimals = std::max(0, static_cast<int>(-std::floor(std::log10(step) + 1e-9)));
  return formatNumber(std::abs(value) < 1e-9 * step ? 0.0 : value, std::chars_format::fixed, decimals);
}

void addCircle(cairo_t* cr, const Eigen::Vector2d& centre, double radius) {
  cairo_new_sub_path(cr);
  cairo_arc(cr, centre.x(), centre.y(), radius, 0.0, 2.0 * std::numbers::pi);
  cairo_close_path(cr);
}

// ---------------------------------------------------------------------------
// World pictures

ViewBox viewBox(const core::Protocol& protocol) {
  const Eigen::Vector2d goal = protocol.goal();
  const double r = protocol.success_radius;
  return {std::min(kCorridorMinX, goal.x() - r), std::max(kCorridorMaxX, goal.x() + r),
          std::min(kCorridorMinY, goal.y() - r), std::max(kCorridorMaxY, goal.y() + r)};
}

ImageSize worldImageSize(const ViewBox& view, double pixels_per_metre, double extra_width,
                         const std::string& where) {
  const double ppm = pixels_per_metre;
  if (!std::isfinite(ppm) || ppm <= 0.0) {
    throw core::InputError(where + ": pixels_per_metre must be positive (got " +
                           formatNumber(ppm, std::chars_format::general, 6) + ")");
  }
  // Checked in floating point before rounding: lround of an out-of-range value is unspecified,
  // and a NaN protocol field would otherwise slip through as a garbage size.
  const double width = (view.max_x - view.min_x + 2.0 * kWorldMargin + extra_width) * ppm;
  const double height = (view.max_y - view.min_y + 2.0 * kWorldMargin) * ppm;
  const auto in_range = [](double side) { return side >= 0.5 && side < kMaxImageSide + 0.5; };
  if (!in_range(width) || !in_range(height)) {
    throw core::InputError(where + ": image of " +
                           formatNumber(width, std::chars_format::fixed, 0) + " x " +
                           formatNumber(height, std::chars_format::fixed, 0) +
                           " px is out of range (1 ... " + std::to_string(kMaxImageSide) +
                           " px a side); check pixels_per_metre and the protocol's goal");
  }
  return {static_cast<int>(std::lround(width)), static_cast<int>(std::lround(height))};
}

cairo_matrix_t worldToPixels(const ViewBox& view, double pixels_per_metre) {
  const double ppm = pixels_per_metre;
  cairo_matrix_t matrix;
  cairo_matrix_init(&matrix, ppm, 0.0, 0.0, -ppm, (kWorldMargin - view.min_x) * ppm,
                    (view.max_y + kWorldMargin) * ppm);
  return matrix;
}

void drawOccupiedCells(cairo_t* cr, const core::Grid& grid) {
  // One path for all squares, so neighbouring cells merge without anti-aliasing seams.
  const double half = 0.5 * core::kBarnCellSize;
  for (int r = 0; r < grid.rows(); ++r) {
    for (int c = 0; c < grid.cols(); ++c) {
      if (!grid.at(r, c)) continue;
      const Eigen::Vector2d centre = core::cellCentre({r, c});
      cairo_rectangle(cr, centre.x() - half, centre.y() - half, core::kBarnCellSize,
                      core::kBarnCellSize);
    }
  }
  setColour(cr, kCellColour);
  cairo_fill(cr);
}

void drawCylinders(cairo_t* cr, const core::Grid& grid, bool show_containment) {
  // Grid rows 0 and 29 are the corridor's side walls, so they take the wall colour; the row is
  // taken from the grid rather than guessed back from the cylinder's x.
  std::vector<Eigen::Vector2d> walls;
  std::vector<Eigen::Vector2d> obstacles;
  if (show_containment) walls = core::containmentCylinders();
  for (int r = 0; r < grid.rows(); ++r) {
    const bool side_wall = r == 0 || r == grid.rows() - 1;
    for (int c = 0; c < grid.cols(); ++c) {
      if (!core::hasCylinder(grid, {r, c})) continue;
      (side_wall ? walls : obstacles).push_back(core::cellCentre({r, c}));
    }
  }
  for (const Eigen::Vector2d& centre : walls) addCircle(cr, centre, core::kCylinderRadius);
  setColour(cr, kWallColour);
  cairo_fill(cr);
  for (const Eigen::Vector2d& centre : obstacles) addCircle(cr, centre, core::kCylinderRadius);
  setColour(cr, kObstacleColour);
  cairo_fill(cr);
}

void drawPath(cairo_t* cr, const std::vector<core::Cell>& path, const core::Protocol& protocol,
              const PathStyle& style) {
  // The A* cells at their true centres, between the start pose and the goal. run.py measures
  // OT on the same cells shifted by (-0.15, -0.10) m, which would draw the path one cell off
  // the obstacles it avoids; the length difference is a few centimetres.
  const Eigen::Vector2d start = protocol.start();
  const Eigen::Vector2d goal = protocol.goal();
  cairo_move_to(cr, start.x(), start.y());
  for (const core::Cell& cell : path) {
    const Eigen::Vector2d p = core::cellCentre(cell);
    cairo_line_to(cr, p.x(), p.y());
  }
  cairo_line_to(cr, goal.x(), goal.y());
  setColour(cr, style.colour);
  cairo_set_line_width(cr, style.width);
  cairo_set_line_join(cr, CAIRO_LINE_JOIN_ROUND);
  cairo_set_line_cap(cr, CAIRO_LINE_CAP_ROUND);
  cairo_stroke(cr);
  if (style.dot_radius <= 0.0) return;
  for (const core::Cell& cell : path) addCircle(cr, core::cellCentre(cell), style.dot_radius);
  cairo_fill(cr);
}

void drawStartPose(cairo_t* cr, const core::Protocol& protocol) {
  const Eigen::Vector2d start = protocol.start();
  const double arrow_length = 0.45;  // [m] from the robot centre, past the front bumper
  const double head_length = 0.12;   // [m]
  const double head_half_width = 0.07;  // [m]

  cairo_save(cr);
  cairo_translate(cr, start.x(), start.y());
  cairo_rotate(cr, protocol.start_yaw);  // y points up, so this is the world's CCW yaw
  setColour(cr, kInkColour);
  // The Jackal's planning footprint (core::RobotConfig's defaults: a world is drawn without a
  // sim config).
  const core::RobotConfig jackal;
  cairo_rectangle(cr, -0.5 * jackal.footprint_length, -0.5 * jackal.footprint_width, jackal.footprint_length,
                  jackal.footprint_width);
  cairo_move_to(cr, 0.0, 0.0);
  cairo_line_to(cr, arrow_length - head_length, 0.0);
  cairo_set_line_width(cr, kOutlineWidth);
  cairo_set_line_join(cr, CAIRO_LINE_JOIN_MITER);
  cairo_set_line_cap(cr, CAIRO_LINE_CAP_BUTT);
  cairo_stroke(cr);
  cairo_move_to(cr, arrow_length, 0.0);
  cairo_line_to(cr, arrow_length - head_length, head_half_width);
  cairo_line_to(cr, arrow_length - head_length, -head_half_width);
  cairo_close_path(cr);
  cairo_fill(cr);
  cairo_arc(cr, 0.0, 0.0, 0.03, 0.0, 2.0 * std::numbers::pi);
  cairo_fill(cr);
  cairo_restore(cr);
}

void drawGoal(cairo_t* cr, const core::Protocol& protocol) {
  const Eigen::Vector2d goal = protocol.goal();
  const double cross = 0.12;  // [m] half-size of the cross arms
  const double dashes[] = {0.12, 0.08};  // [m] on, off

  setColour(cr, kInkColour);
  cairo_set_line_width(cr, kOutlineWidth);
  cairo_set_line_cap(cr, CAIRO_LINE_CAP_BUTT);
  cairo_set_dash(cr, dashes, 2, 0.0);
  cairo_new_path(cr);
  cairo_arc(cr, goal.x(), goal.y(), protocol.success_radius, 0.0, 2.0 * std::numbers::pi);
  cairo_stroke(cr);
  cairo_set_dash(cr, nullptr, 0, 0.0);
  cairo_move_to(cr, goal.x() - cross, goal.y() - cross);
  cairo_line_to(cr, goal.x() + cross, goal.y() + cross);
  cairo_move_to(cr, goal.x() - cross, goal.y() + cross);
  cairo_line_to(cr, goal.x() + cross, goal.y() - cross);
  cairo_stroke(cr);
}

std::string worldTitle(const core::WorldSpec& world, const core::Protocol& protocol) {
  const double ot = core::optimalTime(world.path, protocol);  // [s]
  return "world " + std::to_string(world.id) + "  fill " +
         formatNumber(world.fill_pct, std::chars_format::general, 3) + "  smooth " +
         std::to_string(world.smooth_iter) + "  OT " +
         formatNumber(ot, std::chars_format::fixed, 2) + " s";
}

// Annotations are drawn in device coordinates, so text is not mirrored by the y-up matrix.

void drawWorldTitle(cairo_t* cr, const std::string& title, double pixels_per_metre,
                    double width_px) {
  const double ppm = pixels_per_metre;
  const double margin_px = kWorldMargin * ppm;
  // A long id or fill value must not run off the right edge: shrink to fit instead.
  double size = kTitleHeight * ppm;
  const double room = width_px - 2.0 * margin_px;
  const double width = textWidth(title, size);
  if (width > room) size *= room / width;
  setColour(cr, kInkColour);
  drawText(cr, title, margin_px, 0.6 * margin_px, size);
}

void drawScaleBar(cairo_t* cr, double left_px, double baseline_px, double pixels_per_metre) {
  const double ppm = pixels_per_metre;
  const double tick_px = 0.06 * ppm;
  setColour(cr, kInkColour);
  cairo_set_line_width(cr, kOutlineWidth * ppm);
  cairo_set_line_cap(cr, CAIRO_LINE_CAP_BUTT);
  cairo_move_to(cr, left_px, baseline_px);
  cairo_line_to(cr, left_px + ppm, baseline_px);  // 1 m
  cairo_move_to(cr, left_px, baseline_px - tick_px);
  cairo_line_to(cr, left_px, baseline_px + tick_px);
  cairo_move_to(cr, left_px + ppm, baseline_px - tick_px);
  cairo_line_to(cr, left_px + ppm, baseline_px + tick_px);
  cairo_stroke(cr);
  // Label centred on the bar by its lower-case letter.
  const double size = kLabelHeight * ppm;
  drawText(cr, "1 m", left_px + 1.12 * ppm, xCentredBaseline(baseline_px, size), size);
}

void addIntervalBar(cairo_t* cr, double x, double y0, double y1, double cap_half_width) {
  cairo_move_to(cr, x, y0);
  cairo_line_to(cr, x, y1);
  if (cap_half_width <= 0.0) return;
  for (const double y : {y0, y1}) {
    cairo_move_to(cr, x - cap_half_width, y);
    cairo_line_to(cr, x + cap_half_width, y);
  }
}

void drawWorldLayer(cairo_t* cr, const core::WorldSpec& world, const core::Protocol& protocol, bool show_containment,
                    const std::optional<PathStyle>& path) {
  drawOccupiedCells(cr, world.grid);
  drawCylinders(cr, world.grid, show_containment);
  if (path) drawPath(cr, world.path, protocol, *path);
  drawGoal(cr, protocol);
  drawStartPose(cr, protocol);
}

void drawWorldFrame(cairo_t* cr, const core::WorldSpec& world, const core::Protocol& protocol, const ViewBox& view,
                    double pixels_per_metre, double title_width_px) {
  drawWorldTitle(cr, worldTitle(world, protocol), pixels_per_metre, title_width_px);
  drawScaleBar(cr, kWorldMargin * pixels_per_metre, (view.max_y - view.min_y + 1.5 * kWorldMargin) * pixels_per_metre,
               pixels_per_metre);
}

}  // namespace barn::viz::detail

namespace barn::viz {

ImageFormat imageFormatFor(const std::filesystem::path& path) {
  std::string extension = path.extension().string();
  for (char& ch : extension) ch = static_cast<char>(std::tolower(static_cast<unsigned char>(ch)));
  if (extension == ".png") return ImageFormat::Png;
  if (extension == ".pdf") return ImageFormat::Pdf;
  if (extension == ".svg") return ImageFormat::Svg;
  throw core::InputError(path.string() + ": unknown image type '" + extension + "' (expected .png, .pdf or .svg)");
}

}  // namespace barn::viz
