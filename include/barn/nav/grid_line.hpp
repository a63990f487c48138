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

namespace detail {

/// A walk's shape: which axis dominates, the lengths along both, the steps taken.
struct LineShape {
  bool x_major = true;
  int major = 0, minor = 0, steps = 0;
  int step_x = 1, step_y = 1;
};

inline LineShape lineShape(int x0, int y0, int x1, int y1, int max_steps) {
  const int dx = x1 - x0, dy = y1 - y0;
  LineShape s;
  s.step_x = dx > 0 ? 1 : -1;
  s.step_y = dy > 0 ? 1 : -1;
  s.x_major = std::abs(dx) >= std::abs(dy);
  s.major = s.x_major ? std::abs(dx) : std::abs(dy);
  s.minor = s.x_major ? std::abs(dy) : std::abs(dx);
  s.steps = std::min(s.major, std::max(0, max_steps));
  return s;
}

struct GridPosition {
  int x = 0, y = 0;
  GridPosition& operator+=(GridPosition d) {
    x += d.x;
    y += d.y;
    return *this;
  }
};

/// The one Bresenham walk, whatever a cell's position is (a cell pair or a flat index): the
/// position moves by `major_step` every step and by `minor_step` when the error term, which
/// starts at half the dominant length, reaches it.
template <class Position, class Visit>
bool bresenham(Position at, Position major_step, Position minor_step, const LineShape& s, Visit visit) {
  int error = s.major / 2;
  for (int i = 0; i < s.steps; ++i) {
    if (!visit(at)) return false;
    at += major_step;
    error += s.minor;
    if (error >= s.major) {
      at += minor_step;
      error -= s.major;
    }
  }
  return visit(at);
}

}  // namespace detail

/// Visits the cells from (x0, y0) to (x1, y1), both included, taking at most `max_steps`
/// steps along the dominant axis (the last cell visited is where the walk stopped). `visit`
/// returns false to stop early; the function returns false then, true otherwise.
template <class Visit>
bool walkLine(int x0, int y0, int x1, int y1, int max_steps, Visit visit) {
  const detail::LineShape s = detail::lineShape(x0, y0, x1, y1, max_steps);
  const detail::GridPosition along_x{s.step_x, 0}, along_y{0, s.step_y};
  return detail::bresenham(detail::GridPosition{x0, y0}, s.x_major ? along_x : along_y, s.x_major ? along_y : along_x, s,
                           [&](detail::GridPosition p) { return visit(p.x, p.y); });
}

/// walkLine's cells as flat indices y * width + x, with no early stop. Both ends must be on the
/// grid: Bresenham never leaves the box spanned by its ends, so no cell needs a bounds check.
/// Ray-trace clearing and the DWA footprint check walk tens of thousands of cells per scan.
template <class Visit>
void walkLineFlat(int x0, int y0, int x1, int y1, int max_steps, std::ptrdiff_t width, Visit visit) {
  const detail::LineShape s = detail::lineShape(x0, y0, x1, y1, max_steps);
  const std::ptrdiff_t along_x = s.step_x, along_y = s.step_y * width;
  detail::bresenham(static_cast<std::ptrdiff_t>(y0) * width + x0, s.x_major ? along_x : along_y,
                    s.x_major ? along_y : along_x, s, [&](std::ptrdiff_t at) {
                      visit(at);
                      return true;
                    });
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
  // Most rays are shorter than the limit: then the scale is exactly 1, known without the
  // square root (both squares are exact for any ray on a map).
  const double squared = static_cast<double>(dx) * dx + static_cast<double>(dy) * dy;
  if (squared < max_cells * max_cells) return std::max(std::abs(dx), std::abs(dy));
  const double length = std::hypot(static_cast<double>(dx), static_cast<double>(dy));
  const double scale = length == 0.0 ? 1.0 : std::min(1.0, max_cells / length);
  return static_cast<int>(scale * std::max(std::abs(dx), std::abs(dy)));
}

}  // namespace barn::nav
