#include "barn/viz/world_render.hpp"

#include <cairo.h>

#include <algorithm>
#include <cmath>
#include <charconv>
#include <cstring>
#include <memory>
#include <numbers>
#include <stdexcept>
#include <string>
#include <system_error>
#include <vector>

#include <Eigen/Core>

#include "barn/core/errors.hpp"
#include "barn/core/grid.hpp"
#include "barn/core/world_geometry.hpp"
#include "stroke_font.hpp"

namespace barn::viz {
namespace {

using detail::drawText;
using detail::textWidth;

// ---------------------------------------------------------------------------
// Layout and style

// Corridor box: outer edges of the containment walls (x = -0.075 and -4.425, back wall at
// y = 0.075) and of the last field column (5.175 + 0.15 * 29 = 9.525), each plus one
// cylinder radius. Kept in step with the header comment, which tests rely on.
constexpr double kCorridorMinX = -4.5;  // [m]
constexpr double kCorridorMaxX = 0.0;   // [m]
constexpr double kCorridorMinY = 0.0;   // [m]
constexpr double kCorridorMaxY = 9.6;   // [m]
constexpr double kMargin = 0.6;         // [m] on every side; holds the title and the scale bar

// Cairo refuses image surfaces larger than this on either side.
constexpr int kMaxImageSide = 32767;  // [px]

// The Jackal footprint as BARN uses it for the start pose.
constexpr double kRobotLength = 0.508;  // [m] along the heading
constexpr double kRobotWidth = 0.430;   // [m]

constexpr double kOutlineWidth = 0.025;   // [m]
constexpr double kPathWidth = 0.03;       // [m]
constexpr double kPathDotRadius = 0.035;  // [m]
constexpr double kTitleHeight = 0.2;      // [m] font size of the title
constexpr double kLabelHeight = 0.16;     // [m] font size of the scale-bar label

struct Rgb {
  double r;  // [0, 1]
  double g;  // [0, 1]
  double b;  // [0, 1]
};
constexpr Rgb kCellColour{0.86, 0.86, 0.86};
constexpr Rgb kObstacleColour{0.648, 0.192, 0.192};
constexpr Rgb kWallColour{0.152, 0.379, 0.720};
constexpr Rgb kPathColour{0.10, 0.60, 0.25};
constexpr Rgb kInkColour{0.10, 0.10, 0.10};  // start, goal, text, scale bar

// ---------------------------------------------------------------------------
// Cairo ownership: every object is released on all paths, exceptions included.

struct SurfaceDeleter {
  void operator()(cairo_surface_t* surface) const { cairo_surface_destroy(surface); }
};
struct ContextDeleter {
  void operator()(cairo_t* cr) const { cairo_destroy(cr); }
};
using SurfacePtr = std::unique_ptr<cairo_surface_t, SurfaceDeleter>;
using ContextPtr = std::unique_ptr<cairo_t, ContextDeleter>;

/// The world-frame rectangle shown in the image, before the margin is added. [m]
struct ViewBox {
  double min_x;  // [m]
  double max_x;  // [m]
  double min_y;  // [m]
  double max_y;  // [m]
};

/// Corridor plus goal disc, so a protocol with a farther goal still fits in the picture.
ViewBox viewBox(const core::Protocol& protocol) {
  const Eigen::Vector2d goal = protocol.goal();
  const double r = protocol.success_radius;
  return {std::min(kCorridorMinX, goal.x() - r), std::max(kCorridorMaxX, goal.x() + r),
          std::min(kCorridorMinY, goal.y() - r), std::max(kCorridorMaxY, goal.y() + r)};
}

void setColour(cairo_t* cr, const Rgb& c) { cairo_set_source_rgb(cr, c.r, c.g, c.b); }

/// Adds a closed circle to the current path without joining it to the previous point.
void addCircle(cairo_t* cr, const Eigen::Vector2d& centre, double radius) {
  cairo_new_sub_path(cr);
  cairo_arc(cr, centre.x(), centre.y(), radius, 0.0, 2.0 * std::numbers::pi);
  cairo_close_path(cr);
}

// ---------------------------------------------------------------------------
// Layers (all in world coordinates, metres, y up)

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

void drawPath(cairo_t* cr, const std::vector<core::Cell>& path, const core::Protocol& protocol) {
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
  setColour(cr, kPathColour);
  cairo_set_line_width(cr, kPathWidth);
  cairo_set_line_join(cr, CAIRO_LINE_JOIN_ROUND);
  cairo_set_line_cap(cr, CAIRO_LINE_CAP_ROUND);
  cairo_stroke(cr);
  for (const core::Cell& cell : path) addCircle(cr, core::cellCentre(cell), kPathDotRadius);
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
  cairo_rectangle(cr, -0.5 * kRobotLength, -0.5 * kRobotWidth, kRobotLength, kRobotWidth);
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

/// `value` in the given format; to_chars, not printf, so the process locale cannot turn the
/// decimal point into a comma.
std::string formatNumber(double value, std::chars_format format, int precision) {
  char buffer[400];  // fixed notation of 1e308 needs 309 digits
  const std::to_chars_result result =
      std::to_chars(buffer, buffer + sizeof buffer, value, format, precision);
  if (result.ec != std::errc{}) return "?";
  return std::string(buffer, result.ptr);
}

std::string titleText(const core::WorldSpec& world, const core::Protocol& protocol) {
  const double ot = core::optimalTime(world.path, protocol);  // [s]
  return "world " + std::to_string(world.id) + "  fill " +
         formatNumber(world.fill_pct, std::chars_format::general, 3) + "  smooth " +
         std::to_string(world.smooth_iter) + "  OT " +
         formatNumber(ot, std::chars_format::fixed, 2) + " s";
}

// ---------------------------------------------------------------------------
// Annotations (device coordinates, so text is not mirrored by the y-up world matrix)

void drawTitle(cairo_t* cr, const std::string& title, double ppm, int width_px) {
  const double margin_px = kMargin * ppm;
  // A long id or fill value must not run off the right edge: shrink to fit instead.
  double size = kTitleHeight * ppm;
  const double room = width_px - 2.0 * margin_px;
  const double width = textWidth(title, size);
  if (width > room) size *= room / width;
  setColour(cr, kInkColour);
  drawText(cr, title, margin_px, 0.6 * margin_px, size);
}

void drawScaleBar(cairo_t* cr, double left_px, double baseline_px, double ppm) {
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
  // Label centred on the bar: the x-height is 4/8 of the font size.
  const double size = kLabelHeight * ppm;
  drawText(cr, "1 m", left_px + 1.12 * ppm, baseline_px + 0.25 * size, size);
}

}  // namespace

// ---------------------------------------------------------------------------

void renderWorldPng(const core::WorldSpec& world, const core::Protocol& protocol,
                    const std::filesystem::path& png_path, const RenderOptions& options) {
  const std::string where = png_path.string();
  const double ppm = options.pixels_per_metre;
  if (!std::isfinite(ppm) || ppm <= 0.0) {
    throw core::InputError(where + ": pixels_per_metre must be positive (got " +
                           formatNumber(ppm, std::chars_format::general, 6) + ")");
  }
  const ViewBox view = viewBox(protocol);
  // Checked in floating point before rounding: lround of an out-of-range value is unspecified,
  // and a NaN protocol field would otherwise slip through as a garbage size.
  const double width = (view.max_x - view.min_x + 2.0 * kMargin) * ppm;    // [px]
  const double height = (view.max_y - view.min_y + 2.0 * kMargin) * ppm;  // [px]
  const auto in_range = [](double side) { return side >= 0.5 && side < kMaxImageSide + 0.5; };
  if (!in_range(width) || !in_range(height)) {
    throw core::InputError(where + ": image of " +
                           formatNumber(width, std::chars_format::fixed, 0) + " x " +
                           formatNumber(height, std::chars_format::fixed, 0) +
                           " px is out of range (1 ... " + std::to_string(kMaxImageSide) +
                           " px a side); check pixels_per_metre and the protocol's goal");
  }
  const int width_px = static_cast<int>(std::lround(width));
  const int height_px = static_cast<int>(std::lround(height));

  SurfacePtr surface(cairo_image_surface_create(CAIRO_FORMAT_ARGB32, width_px, height_px));
  ContextPtr context(cairo_create(surface.get()));
  cairo_t* cr = context.get();
  if (cairo_status(cr) != CAIRO_STATUS_SUCCESS) {
    throw std::runtime_error(where + ": cannot create a Cairo image: " +
                             cairo_status_to_string(cairo_status(cr)));
  }

  cairo_set_source_rgb(cr, 1.0, 1.0, 1.0);
  cairo_paint(cr);

  // World metres to pixels with y flipped, so the robot drives up the page.
  cairo_matrix_t world_to_px;
  cairo_matrix_init(&world_to_px, ppm, 0.0, 0.0, -ppm, (kMargin - view.min_x) * ppm,
                    (view.max_y + kMargin) * ppm);
  cairo_save(cr);
  cairo_set_matrix(cr, &world_to_px);
  drawOccupiedCells(cr, world.grid);
  drawCylinders(cr, world.grid, options.show_containment);
  if (options.show_path) drawPath(cr, world.path, protocol);
  drawGoal(cr, protocol);
  drawStartPose(cr, protocol);
  cairo_restore(cr);

  drawTitle(cr, titleText(world, protocol), ppm, width_px);
  // The scale bar sits in the bottom margin, left-aligned with the view box.
  drawScaleBar(cr, kMargin * ppm, (view.max_y - view.min_y + 1.5 * kMargin) * ppm, ppm);

  if (cairo_status(cr) != CAIRO_STATUS_SUCCESS) {
    throw std::runtime_error(where + ": drawing failed: " +
                             cairo_status_to_string(cairo_status(cr)));
  }
  cairo_surface_flush(surface.get());
  const cairo_status_t status = cairo_surface_write_to_png(surface.get(), where.c_str());
  if (status != CAIRO_STATUS_SUCCESS) {
    throw core::InputError(where + ": cannot write PNG: " + cairo_status_to_string(status));
  }
}

}  // namespace barn::viz
