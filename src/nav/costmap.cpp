#include "barn/nav/costmap.hpp"

#include <algorithm>
#include <cmath>
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
  const int max_sq = (inflation_cells_ + 1) * (inflation_cells_ + 1) * 2;
  cost_by_squared_cells_.resize(static_cast<std::size_t>(max_sq) + 1);
  // InflationLayer's table, in cell units: a cell is inflated only within ceil(radius / res)
  // cells of its source, and the cost is taken at the cell distance times the resolution.
  for (int sq = 0; sq <= max_sq; ++sq) {
    const double cells = std::sqrt(static_cast<double>(sq));
    cost_by_squared_cells_[static_cast<std::size_t>(sq)] =
        cells > inflation_cells_ ? kFreeCost : inflationCostAtCells(cells);
  }
  dirty_x0_ = width_;
  dirty_y0_ = height_;
  dirty_x1_ = dirty_y1_ = 0;
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
  return toCell(p, cell) ? cost_[index(cell.x, cell.y)] : kUnknownCost;
}

void Costmap::markDirty(int x, int y) {
  dirty_x0_ = std::min(dirty_x0_, x);
  dirty_y0_ = std::min(dirty_y0_, y);
  dirty_x1_ = std::max(dirty_x1_, x + 1);
  dirty_y1_ = std::max(dirty_y1_, y + 1);
}

void Costmap::setObstacle(int x, int y, std::uint8_t value) {
  std::uint8_t& cell = obstacle_[index(x, y)];
  if (cell == value) return;
  // Only a change to or from "obstacle" moves the inflation; unknown <-> free changes the cost
  // of that one cell.
  if (cell == kLethalCost || value == kLethalCost) markDirty(x, y);
  else if (cost_[index(x, y)] == kUnknownCost || value == kUnknownCost) markDirty(x, y);
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
  if (dirty_x1_ > dirty_x0_ && dirty_y1_ > dirty_y0_) reinflate(dirty_x0_, dirty_y0_, dirty_x1_, dirty_y1_);
  dirty_x0_ = width_;
  dirty_y0_ = height_;
  dirty_x1_ = dirty_y1_ = 0;
}

void Costmap::reinflate(int x0, int y0, int x1, int y1) {
  // Cells whose cost may change: the dirty box grown by the inflation reach. Obstacles that
  // influence them: that box grown once more.
  const int r = inflation_cells_ + 1;
  const int tx0 = std::max(0, x0 - r), ty0 = std::max(0, y0 - r);
  const int tx1 = std::min(width_, x1 + r), ty1 = std::min(height_, y1 + r);
  const int ix0 = std::max(0, tx0 - r), iy0 = std::max(0, ty0 - r);
  const int ix1 = std::min(width_, tx1 + r), iy1 = std::min(height_, ty1 + r);
  const int w = ix1 - ix0;
  const int h = iy1 - iy0;

  // Exact squared Euclidean distance transform (Felzenszwalb & Huttenlocher), in cells.
  constexpr double kFar = 1e20;
  edt_.assign(static_cast<std::size_t>(w) * static_cast<std::size_t>(h), kFar);
  for (int y = iy0; y < iy1; ++y)
    for (int x = ix0; x < ix1; ++x)
      if (obstacle_[index(x, y)] == kLethalCost) edt_[static_cast<std::size_t>((y - iy0) * w + (x - ix0))] = 0.0;
  const auto transform1d = [this](double* f, int n, int stride) {
    edt_row_.resize(static_cast<std::size_t>(n));
    edt_v_.resize(static_cast<std::size_t>(n));
    edt_z_.resize(static_cast<std::size_t>(n) + 1);
    for (int i = 0; i < n; ++i) edt_row_[static_cast<std::size_t>(i)] = f[static_cast<std::ptrdiff_t>(i) * stride];
    const double* g = edt_row_.data();
    // Lower envelope of the parabolas (q - p)^2 + g[p]: v holds their apexes, z the borders.
    int k = 0;
    edt_v_[0] = 0;
    edt_z_[0] = -kFar;
    edt_z_[1] = kFar;
    for (int q = 1; q < n; ++q) {
      const auto intersection = [&](int p) { return ((g[q] + q * q) - (g[p] + p * p)) / (2.0 * q - 2.0 * p); };
      double sq = intersection(edt_v_[static_cast<std::size_t>(k)]);
      while (sq <= edt_z_[static_cast<std::size_t>(k)]) {  // z[0] = -far stops this at k = 0
        --k;
        sq = intersection(edt_v_[static_cast<std::size_t>(k)]);
      }
      ++k;
      edt_v_[static_cast<std::size_t>(k)] = q;
      edt_z_[static_cast<std::size_t>(k)] = sq;
      edt_z_[static_cast<std::size_t>(k) + 1] = kFar;
    }
    k = 0;
    for (int q = 0; q < n; ++q) {
      while (edt_z_[static_cast<std::size_t>(k) + 1] < q) ++k;
      const int p = edt_v_[static_cast<std::size_t>(k)];
      f[static_cast<std::ptrdiff_t>(q) * stride] = (q - p) * (q - p) + g[p];
    }
  };
  for (int x = 0; x < w; ++x) transform1d(edt_.data() + x, h, w);
  for (int y = 0; y < h; ++y) transform1d(edt_.data() + static_cast<std::ptrdiff_t>(y) * w, w, 1);

  const int table_max = static_cast<int>(cost_by_squared_cells_.size()) - 1;
  for (int y = ty0; y < ty1; ++y) {
    for (int x = tx0; x < tx1; ++x) {
      const std::size_t i = index(x, y);
      const std::uint8_t state = obstacle_[i];
      if (state == kLethalCost) {
        cost_[i] = kLethalCost;
        continue;
      }
      if (state == kUnknownCost) {
        cost_[i] = kUnknownCost;
        continue;
      }
      const double sq = edt_[static_cast<std::size_t>((y - iy0) * w + (x - ix0))];
      cost_[i] = sq > table_max ? kFreeCost : cost_by_squared_cells_[static_cast<std::size_t>(sq)];
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
  const std::uint8_t unseen = config_.track_unknown ? kUnknownCost : kFreeCost;
  std::vector<std::uint8_t> obstacle(obstacle_.size(), unseen);
  std::vector<std::uint8_t> cost(cost_.size(), unseen);
  for (int y = 0; y < height_; ++y) {
    const int old_y = y + shift_y;
    if (old_y < 0 || old_y >= height_) continue;
    for (int x = 0; x < width_; ++x) {
      const int old_x = x + shift_x;
      if (old_x < 0 || old_x >= width_) continue;
      obstacle[index(x, y)] = obstacle_[index(old_x, old_y)];
      cost[index(x, y)] = cost_[index(old_x, old_y)];
    }
  }
  obstacle_.swap(obstacle);
  cost_.swap(cost);
  origin_ = wanted;
  ++version_;
  // Costs near the edges that moved lost (or gained) obstacles beyond the old window.
  const int band = inflation_cells_ + 1;
  if (std::abs(shift_x) >= width_ || std::abs(shift_y) >= height_) {
    reinflate(0, 0, width_, height_);
    return;
  }
  if (shift_x > 0) reinflate(width_ - shift_x - band, 0, width_, height_);
  if (shift_x < 0) reinflate(0, 0, -shift_x + band, height_);
  if (shift_y > 0) reinflate(0, height_ - shift_y - band, width_, height_);
  if (shift_y < 0) reinflate(0, 0, width_, -shift_y + band);
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
  if (dirty_x1_ > dirty_x0_ && dirty_y1_ > dirty_y0_) reinflate(dirty_x0_, dirty_y0_, dirty_x1_, dirty_y1_);
  dirty_x0_ = width_;
  dirty_y0_ = height_;
  dirty_x1_ = dirty_y1_ = 0;
}

void Costmap::markObstacle(const Eigen::Vector2d& p) {
  CellIndex cell;
  if (!toCell(p, cell)) return;
  setObstacle(cell.x, cell.y, kLethalCost);
  if (dirty_x1_ > dirty_x0_ && dirty_y1_ > dirty_y0_) reinflate(dirty_x0_, dirty_y0_, dirty_x1_, dirty_y1_);
  dirty_x0_ = width_;
  dirty_y0_ = height_;
  dirty_x1_ = dirty_y1_ = 0;
}

void Costmap::clearOutside(const Eigen::Vector2d& centre, double radius) {
  const std::uint8_t unseen = config_.track_unknown ? kUnknownCost : kFreeCost;
  for (int y = 0; y < height_; ++y)
    for (int x = 0; x < width_; ++x)
      if ((cellCentre({x, y}) - centre).norm() > radius && obstacle_[index(x, y)] == kLethalCost) setObstacle(x, y, unseen);
  reinflate(0, 0, width_, height_);
  dirty_x0_ = width_;
  dirty_y0_ = height_;
  dirty_x1_ = dirty_y1_ = 0;
}

}  // namespace barn::nav
