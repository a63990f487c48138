#pragma once
/// Integer line rasterisation on a costmap grid, the way costmap_2d walks cells: Bresenham along
/// the dominant axis, one cell per step, the error term starting at half the dominant length.
/// Ray-trace clearing, footprint clearing (convex fill) and the DWA footprint check all use it,
/// so they agree on which cells a segment touches.

#include <algorithm>
#include <cmath>
#include <cstddef>
#include <cstdlib>

namespace barn::nav {

/// Visits the cells from (x0, y0) to (x1, y1), both included, taking at most `max_steps`
/// steps along the dominant axis (the last cell visited is where the walk stopped). `visit`
/// returns false to stop early; the function returns false then, true otherwise.
template <class Visit>
bool walkLine(int x0, int y0, int x1, int y1, int max_steps, Visit visit) {
  const int dx = x1 - x0, dy = y1 - y0;
  const int abs_dx = std::abs(dx), abs_dy = std::abs(dy);
  const int step_x = dx > 0 ? 1 : -1, step_y = dy > 0 ? 1 : -1;
  const bool x_major = abs_dx >= abs_dy;
  const int major = x_major ? abs_dx : abs_dy, minor = x_major ? abs_dy : abs_dx;
  const int steps = std::min(major, std::max(0, max_steps));
  int error = major / 2;
  int x = x0, y = y0;
  for (int i = 0; i < steps; ++i) {
    if (!visit(x, y)) return false;
    if (x_major) x += step_x;
    else y += step_y;
    error += minor;
    if (error >= major) {
      if (x_major) y += step_y;
      else x += step_x;
      error -= major;
    }
  }
  return visit(x, y);
}

/// walkLine's cells as flat indices y * width + x, with no early stop. Both ends must be on the
/// grid: Bresenham never leaves the box spanned by its ends, so no cell needs a bounds check.
/// Ray-trace clearing and the DWA footprint check walk tens of thousands of cells per scan.
template <class Visit>
void walkLineFlat(int x0, int y0, int x1, int y1, int max_steps, std::ptrdiff_t width, Visit visit) {
  const int dx = x1 - x0, dy = y1 - y0;
  const int abs_dx = std::abs(dx), abs_dy = std::abs(dy);
  const std::ptrdiff_t step_x = dx > 0 ? 1 : -1, step_y = dy > 0 ? width : -width;
  const bool x_major = abs_dx >= abs_dy;
  const int major = x_major ? abs_dx : abs_dy, minor = x_major ? abs_dy : abs_dx;
  const std::ptrdiff_t major_step = x_major ? step_x : step_y, minor_step = x_major ? step_y : step_x;
  const int steps = std::min(major, std::max(0, max_steps));
  int error = major / 2;
  std::ptrdiff_t at = static_cast<std::ptrdiff_t>(y0) * width + x0;
  for (int i = 0; i < steps; ++i) {
    visit(at);
    at += major_step;
    error += minor;
    if (error >= major) {
      at += minor_step;
      error -= major;
    }
  }
  visit(at);
}

/// The whole segment (no length limit).
template <class Visit>
bool walkLine(int x0, int y0, int x1, int y1, Visit visit) {
  return walkLine(x0, y0, x1, y1, std::max(std::abs(x1 - x0), std::abs(y1 - y0)), visit);
}

/// The step limit costmap_2d puts on a ray of `max_cells` cells (Euclidean) from (x0, y0) to
/// (x1, y1): the dominant-axis length scaled by min(1, max_cells / length).
inline int rayStepLimit(int x0, int y0, int x1, int y1, double max_cells) {
  const int dx = x1 - x0, dy = y1 - y0;
  const double length = std::hypot(static_cast<double>(dx), static_cast<double>(dy));
  const double scale = length == 0.0 ? 1.0 : std::min(1.0, max_cells / length);
  return static_cast<int>(scale * std::max(std::abs(dx), std::abs(dy)));
}

}  // namespace barn::nav
