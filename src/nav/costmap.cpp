#include "barn/nav/costmap.hpp"

#include <algorithm>
#include <cmath>
#include <cstring>
#include <limits>

#include "barn/nav/grid_line.hpp"

namespace barn::nav {

void validate(const CostmapConfig& c, core::Errors& errors, const std::string& prefix) {
  errors.check(c.resolution > 0.0, prefix + ".resolution", "must be > 0");
  errors.check(c.width > 0.0 && c.width / std::max(c.resolution, 1e-9) <= 10000, prefix + ".width",
               "must be > 0 and at most 10000 cells");
  errors.check(c.height > 0.0 && c.height / std::max(c.resolution, 1e-9) <= 10000, prefix + ".height",
               "must be > 0 and at most 10000 cells");
  errors.check(c.obstacle_range > 0.0, prefix + ".obstacle_range", "must be > 0");
  errors.check(c.raytrace_range > 0.0, prefix + ".raytrace_range", "must be > 0");
  errors.check(c.inscribed_radius >= 0.0, prefix + ".inscribed_radius", "must be >= 0");
  errors.check(c.inflation_radius >= c.inscribed_radius, prefix + ".inflation_radius", "must be >= inscribed_radius");
  errors.check(c.cost_scaling_factor >= 0.0, prefix + ".cost_scaling_factor", "must be >= 0");
}

Costmap::Costmap(const CostmapConfig& config) : config_(config) {
  width_ = static_cast<int>(std::lround(config.width / config.resolution));
  height_ = static_cast<int>(std::lround(config.height / config.resolution));
  origin_ = {config.origin_x, config.origin_y};
  if (config.rolling) origin_ = {0.0, 0.0};  // placed by the first recentre()
  const std::uint8_t unseen = config.track_unknown ? kUnknownCost : kFreeCost;
  obstacle_.assign(static_cast<std::size_t>(width_) * static_cast<std::size_t>(height_), unseen);
  cost_.assign(obstacle_.size(), unseen);
  inflation_cells_ = static_cast<int>(std::ceil(config.inflation_radius / config.resolution));
  // InflationLayer's table, in cell units: a cell is inflated only within ceil(radius / res)
  // cells of its source, and the cost is taken at the cell distance times the resolution.
  const int r = inflation_cells_;
  const int side = 2 * r + 1;
  kernel_.assign(static_cast<std::size_t>(side) * static_cast<std::size_t>(side), kFreeCost);
  for (int dy = -r; dy <= r; ++dy)
    for (int dx = -r; dx <= r; ++dx) {
      const double cells = std::sqrt(static_cast<double>(dx * dx + dy * dy));
      kernel_[static_cast<std::size_t>((dy + r) * side + dx + r)] = cells > r ? kFreeCost : inflationCostAtCells(cells);
    }
  dirty_ = {width_, height_, 0, 0};
}

std::uint8_t Costmap::inflationCostAtCells(double cells) const {
  if (cells <= 0.0) return kLethalCost;
  const double distance = cells * config_.resolution;
  if (distance <= config_.inscribed_radius) return kInscribedCost;
  const double factor = std::exp(-config_.cost_scaling_factor * (distance - config_.inscribed_radius));
  return static_cast<std::uint8_t>(static_cast<double>(kInscribedCost - 1) * factor);
}

std::uint8_t Costmap::inflationCost(double distance) const {
  if (distance > config_.inflation_radius) return kFreeCost;
  return inflationCostAtCells(distance / config_.resolution);
}

bool Costmap::toCell(const Eigen::Vector2d& p, CellIndex& cell) const {
  const double fx = (p.x() - origin_.x()) / config_.resolution;
  const double fy = (p.y() - origin_.y()) / config_.resolution;
  if (fx < 0.0 || fy < 0.0) return false;
  cell = {static_cast<int>(fx), static_cast<int>(fy)};
  return inBounds(cell.x, cell.y);
}

Eigen::Vector2d Costmap::cellCentre(CellIndex cell) const {
  return origin_ + config_.resolution * Eigen::Vector2d(cell.x + 0.5, cell.y + 0.5);
}

std::uint8_t Costmap::costAt(const Eigen::Vector2d& p) const {
  CellIndex cell;
  return toCell(p, cell) ? cost(cell.x, cell.y) : kUnknownCost;
}

void Costmap::markDirty(int x, int y) {
  dirty_.x0 = std::min(dirty_.x0, x);
  dirty_.y0 = std::min(dirty_.y0, y);
  dirty_.x1 = std::max(dirty_.x1, x + 1);
  dirty_.y1 = std::max(dirty_.y1, y + 1);
}

void Costmap::commitDirty() {
  if (!dirty_.empty()) queueReinflation(dirty_);
  dirty_ = {width_, height_, 0, 0};
}

void Costmap::queueReinflation(CellBox box) {
  // A handful of boxes is cheaper to recompute one by one than their bounding box; beyond
  // that, one box bounds the work of keeping the list.
  constexpr std::size_t kMaxPending = 8;
  if (pending_.size() == kMaxPending) {
    for (const CellBox& b : pending_) box = {std::min(box.x0, b.x0), std::min(box.y0, b.y0), std::max(box.x1, b.x1), std::max(box.y1, b.y1)};
    pending_.clear();
  }
  pending_.push_back(box);
}

void Costmap::inflatePending() const {
  for (const CellBox& box : pending_) reinflate(box);
  pending_.clear();
}

void Costmap::setObstacle(int x, int y, std::uint8_t value) {
  std::uint8_t& cell = obstacle_[index(x, y)];
  if (cell == value) return;
  // Only a change to or from "obstacle" moves the inflation; unknown <-> free changes the cost
  // of that one cell.
  if (cell == kLethalCost || value == kLethalCost || cell == kUnknownCost || value == kUnknownCost) markDirty(x, y);
  cell = value;
  ++version_;
}

void Costmap::clearRay(CellIndex from, const Eigen::Vector2d& to) {
  // costmap_2d's ray trace: the end point is first pulled back onto the map along the ray
  // (onto the lower edges exactly, 1 mm inside the upper ones), then every cell of the
  // Bresenham line from the sensor's cell is freed, the end cell included, for at most
  // raytrace_range (the dominant-axis step count scaled down for longer rays).
  const double res = config_.resolution;
  const Eigen::Vector2d start = cellCentre(from);
  Eigen::Vector2d end = to;
  const Eigen::Vector2d lo = origin_;
  const Eigen::Vector2d hi = origin_ + res * Eigen::Vector2d(width_, height_);
  for (int axis = 0; axis < 2; ++axis) {
    const double d = end[axis] - start[axis];
    if (end[axis] < lo[axis] && d != 0.0) end = start + (end - start) * ((lo[axis] - start[axis]) / d);
    if (end[axis] > hi[axis] - 0.001 && d != 0.0) end = start + (end - start) * ((hi[axis] - 0.001 - start[axis]) / d);
  }
  CellIndex stop;
  if (!toCell(end, stop)) stop = {std::clamp(static_cast<int>(std::floor((end.x() - lo.x()) / res)), 0, width_ - 1),
                                  std::clamp(static_cast<int>(std::floor((end.y() - lo.y()) / res)), 0, height_ - 1)};
  const double max_cells = std::ceil(config_.raytrace_range / res);
  walkLine(from.x, from.y, stop.x, stop.y, rayStepLimit(from.x, from.y, stop.x, stop.y, max_cells), [&](int x, int y) {
    if (inBounds(x, y)) setObstacle(x, y, kFreeCost);
    return true;
  });
}

void Costmap::integrateScan(const core::LaserScan& scan, const core::Pose2& sensor_pose,
                            const Eigen::Vector2d& robot_position) {
  recentre(robot_position);
  const Eigen::Vector2d origin = sensor_pose.position();
  const double c = std::cos(sensor_pose.yaw);
  const double s = std::sin(sensor_pose.yaw);
  // laser_geometry keeps a beam only if range_min <= r < range_max: a beam without a return
  // (+inf, or range_max) neither marks nor clears, unless inf_is_valid turns it into a return
  // just short of range_max, which clears the raytrace range and marks nothing.
  const auto usable = [&](double range, double& kept) {
    if (std::isinf(range) && range > 0 && config_.inf_is_valid) range = scan.range_max - 1e-4;
    kept = range;
    return range >= scan.range_min && range < scan.range_max;
  };
  // Clearing first, then marking (costmap_2d's order), so a return inside another beam's
  // cleared ray stays an obstacle. Nothing is traced if the sensor is off the map.
  CellIndex sensor_cell;
  if (toCell(origin, sensor_cell)) {
    for (std::size_t i = 0; i < scan.ranges.size(); ++i) {
      double range = 0.0;
      if (!usable(scan.ranges[i], range)) continue;
      const double angle = scan.angle(i);
      const Eigen::Vector2d u(c * std::cos(angle) - s * std::sin(angle), s * std::cos(angle) + c * std::sin(angle));
      clearRay(sensor_cell, origin + range * u);
    }
  }
  for (std::size_t i = 0; i < scan.ranges.size(); ++i) {
    double range = 0.0;
    if (!usable(scan.ranges[i], range) || !(range < config_.obstacle_range)) continue;
    const double angle = scan.angle(i) + sensor_pose.yaw;
    CellIndex cell;
    if (toCell(origin + range * Eigen::Vector2d(std::cos(angle), std::sin(angle)), cell))
      setObstacle(cell.x, cell.y, kLethalCost);
  }
  commitDirty();
}

void Costmap::reinflate(CellBox changed) const {
  // Cells whose cost may change: the changed box grown by the inflation reach (and one more
  // cell). Obstacles that influence them: that box grown by the reach.
  const int r = inflation_cells_;
  const int tx0 = std::max(0, changed.x0 - r - 1), ty0 = std::max(0, changed.y0 - r - 1);
  const int tx1 = std::min(width_, changed.x1 + r + 1), ty1 = std::min(height_, changed.y1 + r + 1);
  if (tx1 <= tx0 || ty1 <= ty0) return;
  for (int y = ty0; y < ty1; ++y) {
    const std::size_t row = index(0, y);
    for (int x = tx0; x < tx1; ++x) {
      const std::uint8_t state = obstacle_[row + static_cast<std::size_t>(x)];
      cost_[row + static_cast<std::size_t>(x)] = state == kLethalCost || state == kUnknownCost ? state : kFreeCost;
    }
  }
  // Each obstacle stamps its kernel on the free cells of the target; a cell keeps the largest
  // stamp, the cost at its nearest obstacle.
  const int side = 2 * r + 1;
  const int ix0 = std::max(0, tx0 - r), iy0 = std::max(0, ty0 - r);
  const int ix1 = std::min(width_, tx1 + r), iy1 = std::min(height_, ty1 + r);
  for (int oy = iy0; oy < iy1; ++oy) {
    for (int ox = ix0; ox < ix1; ++ox) {
      if (obstacle_[index(ox, oy)] != kLethalCost) continue;
      const int y0 = std::max(ty0, oy - r), y1 = std::min(ty1, oy + r + 1);
      const int x0 = std::max(tx0, ox - r), x1 = std::min(tx1, ox + r + 1);
      for (int y = y0; y < y1; ++y) {
        const std::uint8_t* k = &kernel_[static_cast<std::size_t>((y - oy + r) * side + (x0 - ox + r))];
        const std::size_t row = index(0, y);
        for (int x = x0; x < x1; ++x, ++k) {
          std::uint8_t& c = cost_[row + static_cast<std::size_t>(x)];
          if (c < *k && obstacle_[row + static_cast<std::size_t>(x)] == kFreeCost) c = *k;
        }
      }
    }
  }
}

void Costmap::recentre(const Eigen::Vector2d& position) {
  if (!config_.rolling) return;
  const double res = config_.resolution;
  // The window's corner snapped to the odom grid, so cells keep their place when it moves.
  const Eigen::Vector2d wanted(std::floor((position.x() - config_.width / 2) / res) * res,
                               std::floor((position.y() - config_.height / 2) / res) * res);
  const int shift_x = static_cast<int>(std::lround((wanted.x() - origin_.x()) / res));
  const int shift_y = static_cast<int>(std::lround((wanted.y() - origin_.y()) / res));
  if (shift_x == 0 && shift_y == 0) return;
  commitDirty();
  // Cell (x, y) takes the old cell (x + shift_x, y + shift_y), in place: rows are visited in
  // the direction that reads each source row before it is overwritten.
  const std::uint8_t unseen = config_.track_unknown ? kUnknownCost : kFreeCost;
  const int keep_x0 = std::clamp(-shift_x, 0, width_), keep_x1 = std::clamp(width_ - shift_x, 0, width_);
  const auto shiftGrid = [&](std::vector<std::uint8_t>& grid) {
    for (int k = 0; k < height_; ++k) {
      const int y = shift_y >= 0 ? k : height_ - 1 - k;
      std::uint8_t* row = &grid[index(0, y)];
      const int old_y = y + shift_y;
      if (old_y < 0 || old_y >= height_ || keep_x1 <= keep_x0) {
        std::fill(row, row + width_, unseen);
        continue;
      }
      std::memmove(row + keep_x0, &grid[index(keep_x0 + shift_x, old_y)], static_cast<std::size_t>(keep_x1 - keep_x0));
      std::fill(row, row + keep_x0, unseen);
      std::fill(row + keep_x1, row + width_, unseen);
    }
  };
  shiftGrid(obstacle_);
  shiftGrid(cost_);
  origin_ = wanted;
  ++version_;
  // Regions still to re-inflate move with the cells.
  std::size_t kept = 0;
  for (const CellBox& b : pending_) {
    const CellBox m{std::max(0, b.x0 - shift_x), std::max(0, b.y0 - shift_y), std::min(width_, b.x1 - shift_x), std::min(height_, b.y1 - shift_y)};
    if (!m.empty()) pending_[kept++] = m;
  }
  pending_.resize(kept);
  // Costs near the edges that moved lost (or gained) obstacles beyond the old window.
  const int band = inflation_cells_ + 1;
  if (std::abs(shift_x) >= width_ || std::abs(shift_y) >= height_) {
    queueReinflation({0, 0, width_, height_});
    return;
  }
  if (shift_x > 0) queueReinflation({width_ - shift_x - band, 0, width_, height_});
  if (shift_x < 0) queueReinflation({0, 0, -shift_x + band, height_});
  if (shift_y > 0) queueReinflation({0, height_ - shift_y - band, width_, height_});
  if (shift_y < 0) queueReinflation({0, 0, width_, -shift_y + band});
}

std::vector<CellIndex> Costmap::polygonCells(const std::vector<Eigen::Vector2d>& polygon) const {
  // costmap_2d's convexFillCells: the Bresenham outline through the corners' cells, plus, in
  // every column, each cell between the lowest and the highest outline cell. Nothing if a
  // corner is off the map.
  std::vector<CellIndex> cells;
  if (polygon.size() < 3) return cells;
  std::vector<CellIndex> corners(polygon.size());
  for (std::size_t i = 0; i < polygon.size(); ++i)
    if (!toCell(polygon[i], corners[i])) return cells;
  for (std::size_t i = 0; i < corners.size(); ++i) {
    const CellIndex a = corners[i], b = corners[(i + 1) % corners.size()];
    walkLine(a.x, a.y, b.x, b.y, [&](int x, int y) {
      cells.push_back({x, y});
      return true;
    });
  }
  int min_x = cells.front().x, max_x = min_x;
  for (const CellIndex& cell : cells) {
    min_x = std::min(min_x, cell.x);
    max_x = std::max(max_x, cell.x);
  }
  std::vector<int> low(static_cast<std::size_t>(max_x - min_x + 1), std::numeric_limits<int>::max());
  std::vector<int> high(low.size(), std::numeric_limits<int>::min());
  for (const CellIndex& cell : cells) {
    const std::size_t column = static_cast<std::size_t>(cell.x - min_x);
    low[column] = std::min(low[column], cell.y);
    high[column] = std::max(high[column], cell.y);
  }
  for (std::size_t column = 0; column < low.size(); ++column)
    for (int y = low[column]; y < high[column]; ++y) cells.push_back({min_x + static_cast<int>(column), y});
  return cells;
}

void Costmap::clearPolygon(const std::vector<Eigen::Vector2d>& polygon) {
  for (const CellIndex& cell : polygonCells(polygon))
    if (obstacle_[index(cell.x, cell.y)] == kLethalCost) setObstacle(cell.x, cell.y, kFreeCost);
  commitDirty();
}

void Costmap::markObstacle(const Eigen::Vector2d& p) {
  CellIndex cell;
  if (!toCell(p, cell)) return;
  setObstacle(cell.x, cell.y, kLethalCost);
  commitDirty();
}

void Costmap::clearOutside(const Eigen::Vector2d& centre, double radius) {
  const std::uint8_t unseen = config_.track_unknown ? kUnknownCost : kFreeCost;
  for (int y = 0; y < height_; ++y)
    for (int x = 0; x < width_; ++x)
      if ((cellCentre({x, y}) - centre).norm() > radius && obstacle_[index(x, y)] == kLethalCost) setObstacle(x, y, unseen);
  dirty_ = {width_, height_, 0, 0};
  pending_.clear();
  queueReinflation({0, 0, width_, height_});
}

}  // namespace barn::nav
