#include "barn/controllers/in2bot_map.hpp"

#include <algorithm>
#include <cmath>
#include <limits>
#include <queue>

#include "barn/nav/grid_line.hpp"

namespace barn::controllers {

void validate(const In2botMapConfig& c, core::Errors& errors, const std::string& prefix) {
  core::validateFields(c, errors, prefix);
  errors.check(c.size_x > 0.0 && c.size_y > 0.0, prefix + ".size_x", "the grid's sizes must be > 0");
  if (c.resolution > 0.0)
    errors.check(c.size_x / c.resolution * (c.size_y / c.resolution) <= 4e6, prefix + ".resolution",
                 "gives more than 4 million cells");
  errors.check(c.usable_range > 0.0 && c.usable_range <= c.max_range, prefix + ".usable_range",
               "must be in (0, max_range]");
}

void validate(const In2botEsdfConfig& c, core::Errors& errors, const std::string& prefix) {
  core::validateFields(c, errors, prefix);
}

void validate(const In2botPlannerConfig& c, core::Errors& errors, const std::string& prefix) {
  core::validateFields(c, errors, prefix);
  errors.check(c.vehicle_width >= 0.0 && c.vehicle_length >= 0.0, prefix + ".vehicle_width",
               "the vehicle's sizes must be >= 0");
}

// ---------------------------------------------------------------------------------------------
// The count grid
// ---------------------------------------------------------------------------------------------

ScanCountGrid::ScanCountGrid(const In2botMapConfig& config)
    : config_(config),
      width_(static_cast<int>(std::lround(config.size_x / config.resolution))),
      height_(static_cast<int>(std::lround(config.size_y / config.resolution))) {
  clear();
}

void ScanCountGrid::clear() {
  visits_.assign(static_cast<std::size_t>(width_) * height_, 0);
  hits_.assign(visits_.size(), 0);
}

GridCell ScanCountGrid::cellOf(const Eigen::Vector2d& p) const {
  return {static_cast<int>(std::floor((p.x() - config_.origin_x) / config_.resolution)),
          static_cast<int>(std::floor((p.y() - config_.origin_y) / config_.resolution))};
}

void ScanCountGrid::integrate(const core::LaserScan& scan, const core::Pose2& sensor_pose) {
  const GridCell from = cellOf(sensor_pose.position());
  for (std::size_t i = 0; i < scan.ranges.size(); ++i) {
    double r = scan.ranges[i];
    if (std::isinf(r)) r = config_.inf_range;  // the team's scan preprocessor
    if (std::isnan(r) || r > config_.max_range || r == 0.0) continue;
    const bool clipped = r > config_.usable_range;
    const double d = clipped ? config_.usable_range : r;
    const double angle = sensor_pose.yaw + scan.angle(i);
    const GridCell to = cellOf(sensor_pose.position() + d * Eigen::Vector2d(std::cos(angle), std::sin(angle)));
    nav::walkLine(from.x, from.y, to.x, to.y, [&](int x, int y) {
      if (x < 0 || y < 0 || x >= width_ || y >= height_) return true;
      const std::size_t k = static_cast<std::size_t>(y) * width_ + x;
      const bool end = x == to.x && y == to.y;
      if (!end) {
        ++visits_[k];
      } else if (!clipped) {
        ++visits_[k];
        ++hits_[k];
      }
      return true;
    });
  }
}

std::vector<std::int8_t> ScanCountGrid::occupancy() const {
  std::vector<std::int8_t> map(visits_.size(), kUnknownCell);
  for (std::size_t k = 0; k < map.size(); ++k) {
    if (visits_[k] == 0) continue;
    map[k] = static_cast<double>(hits_[k]) / static_cast<double>(visits_[k]) > config_.occupied_ratio ? kOccupiedCell
                                                                                                      : kFreeCell;
  }
  return map;
}

// ---------------------------------------------------------------------------------------------
// Distance-field costs
// ---------------------------------------------------------------------------------------------

std::optional<std::pair<int, int>> containmentWalls(const std::vector<std::int8_t>& occupancy, int width, int height,
                                                   const In2botEsdfConfig& config) {
  // x1, x2 and the "inside a wall run" flag carry over from row to row, as in the team's loop.
  int x1 = 0, x2 = 0;
  bool in_wall = false;
  for (int row = config.wall_row; row < height; ++row) {
    for (int x = 0; x < width; ++x) {
      const std::int8_t occ = occupancy[static_cast<std::size_t>(row) * width + x];
      if (occ > 0 && !in_wall) {
        x1 = x;
        in_wall = true;
      } else if (occ < 0 && in_wall) {
        x2 = x;
        in_wall = false;
      }
    }
    if (x1 < config.wall_column && x2 > config.wall_column) return std::make_pair(x1, x2);
  }
  return std::nullopt;
}

namespace {

// The 1-D squared distance transform (lower envelope of parabolas) of `f` (n values, +inf
// where nothing is), written to `out`.
void distanceTransform1D(const double* f, double* out, int n, std::vector<int>& v, std::vector<double>& z) {
  constexpr double kInf = std::numeric_limits<double>::infinity();
  v.resize(static_cast<std::size_t>(n));
  z.resize(static_cast<std::size_t>(n) + 1);
  int k = -1;
  for (int q = 0; q < n; ++q) {
    if (f[q] == kInf) continue;
    double s = -kInf;
    while (k >= 0) {
      const int p = v[k];
      s = ((f[q] + double(q) * q) - (f[p] + double(p) * p)) / (2.0 * (q - p));
      if (s > z[k]) break;
      --k;
    }
    ++k;
    v[k] = q;
    z[k] = k == 0 ? -kInf : s;
    z[k + 1] = kInf;
  }
  if (k < 0) {  // nothing on this line
    std::fill(out, out + n, kInf);
    return;
  }
  int j = 0;
  for (int q = 0; q < n; ++q) {
    while (z[j + 1] < q) ++j;
    const double dq = q - v[j];
    out[q] = dq * dq + f[v[j]];
  }
}

}  // namespace

std::vector<std::int8_t> esdfCosts(const std::vector<std::int8_t>& occupancy, int width, int height,
                                   double resolution, const In2botEsdfConfig& config) {
  constexpr double kInf = std::numeric_limits<double>::infinity();
  const std::size_t cells = static_cast<std::size_t>(width) * height;
  std::optional<std::pair<int, int>> walls;
  if (config.wall_rule) walls = containmentWalls(occupancy, width, height, config);
  const auto obstacle = [&](int x, int y) {
    return occupancy[static_cast<std::size_t>(y) * width + x] == kOccupiedCell ||
           (walls && (x < walls->first || x > walls->second));
  };

  // Squared distances in cells, exact integers: along x per row, then the lower envelope along
  // y per column (on a transposed copy, so the pass reads contiguous memory).
  std::vector<double> along_x(cells);  // transposed: [x * height + y]
  std::vector<int> v;
  std::vector<double> z;
  // Along a row the squared distance is that to the nearest obstacle of the row: two sweeps.
  std::vector<int> nearest(static_cast<std::size_t>(width));
  for (int y = 0; y < height; ++y) {
    int last = -1;
    for (int x = 0; x < width; ++x) {
      if (obstacle(x, y)) last = x;
      nearest[static_cast<std::size_t>(x)] = last < 0 ? -1 : x - last;
    }
    last = -1;
    for (int x = width - 1; x >= 0; --x) {
      if (obstacle(x, y)) last = x;
      int& d = nearest[static_cast<std::size_t>(x)];
      if (last >= 0 && (d < 0 || last - x < d)) d = last - x;
      along_x[static_cast<std::size_t>(x) * height + y] = d < 0 ? kInf : static_cast<double>(d) * d;
    }
  }
  std::vector<double> d2(cells);  // transposed too
  for (int x = 0; x < width; ++x)
    distanceTransform1D(&along_x[static_cast<std::size_t>(x) * height], &d2[static_cast<std::size_t>(x) * height],
                        height, v, z);

  // The team's arithmetic is float (the grid's float resolution, a float D_MAX):
  // (1 - min(sqrt(d2) res, D_MAX) / D_MAX) * 100, truncated. Tabulated by the integer d2 up
  // to past D_MAX, beyond which it is 0.
  const float res = static_cast<float>(resolution);
  const float d_max = static_cast<float>(config.max_distance);
  const auto reach = static_cast<std::size_t>(std::ceil(config.max_distance / resolution)) + 2;
  std::vector<std::int8_t> by_d2(reach * reach);
  for (std::size_t i = 0; i < by_d2.size(); ++i) {
    const float d = std::min(std::sqrt(static_cast<float>(i)) * res, d_max);
    by_d2[i] = static_cast<std::int8_t>((1 - d / d_max) * 100);
  }
  std::vector<std::int8_t> costs(cells);
  for (int y = 0; y < height; ++y)
    for (int x = 0; x < width; ++x) {
      const std::size_t k = static_cast<std::size_t>(y) * width + x;
      const double dd = d2[static_cast<std::size_t>(x) * height + y];
      std::int8_t value = 100;
      if (dd != 0.0) value = dd < static_cast<double>(by_d2.size()) ? by_d2[static_cast<std::size_t>(dd)] : 0;
      if (occupancy[k] == kUnknownCell) {
        const double decayed = std::clamp(static_cast<double>(value) * config.unknown_decay, 0.0, 100.0);
        value = static_cast<std::int8_t>(decayed);
      }
      costs[k] = value;
    }
  return costs;
}

// ---------------------------------------------------------------------------------------------
// A* and the path check
// ---------------------------------------------------------------------------------------------

namespace {

// Which cells may be expanded: the whole footprint box on the grid and below the threshold,
// counted with a summed-area table of the blocked cells.
std::vector<bool> boxFreeCells(const std::vector<std::int8_t>& costs, int width, int height, int rx, int ry,
                               int threshold) {
  const int w1 = width + 1;
  std::vector<int> sum(static_cast<std::size_t>(w1) * (height + 1), 0);
  for (int y = 0; y < height; ++y)
    for (int x = 0; x < width; ++x) {
      const int blocked = costs[static_cast<std::size_t>(y) * width + x] >= threshold ? 1 : 0;
      sum[static_cast<std::size_t>(y + 1) * w1 + x + 1] = blocked + sum[static_cast<std::size_t>(y) * w1 + x + 1] +
                                                          sum[static_cast<std::size_t>(y + 1) * w1 + x] -
                                                          sum[static_cast<std::size_t>(y) * w1 + x];
    }
  std::vector<bool> free(static_cast<std::size_t>(width) * height, false);
  for (int y = ry; y < height - ry; ++y)
    for (int x = rx; x < width - rx; ++x) {
      const int x0 = x - rx, x1 = x + rx + 1, y0 = y - ry, y1 = y + ry + 1;
      const int blocked = sum[static_cast<std::size_t>(y1) * w1 + x1] - sum[static_cast<std::size_t>(y0) * w1 + x1] -
                          sum[static_cast<std::size_t>(y1) * w1 + x0] + sum[static_cast<std::size_t>(y0) * w1 + x0];
      free[static_cast<std::size_t>(y) * width + x] = blocked == 0;
    }
  return free;
}

bool validCell(const std::vector<std::int8_t>& costs, int width, int height, int x, int y, int threshold) {
  return x >= 0 && y >= 0 && x < width && y < height && costs[static_cast<std::size_t>(y) * width + x] < threshold;
}

}  // namespace

std::vector<GridCell> planGridPath(const std::vector<std::int8_t>& costs, int width, int height, GridCell start,
                                   GridCell goal, double resolution, const In2botPlannerConfig& config) {
  const int rx = static_cast<int>(std::ceil(config.vehicle_width / (2.0 * resolution))) + config.footprint_padding;
  const int ry = static_cast<int>(std::ceil(config.vehicle_length / (2.0 * resolution))) + config.footprint_padding;
  const std::vector<bool> box_free = boxFreeCells(costs, width, height, rx, ry, config.cost_threshold);
  const auto inside = [&](int x, int y) { return x >= 0 && y >= 0 && x < width && y < height; };
  const auto index = [&](int x, int y) { return static_cast<std::size_t>(y) * width + x; };

  // A goal whose box is not clear: the first clear cell on the square rings around it.
  if (!(inside(goal.x, goal.y) && box_free[index(goal.x, goal.y)])) {
    bool found = false;
    for (int r = 1; r <= config.goal_search_radius && !found; ++r)
      for (int dx = -r; dx <= r && !found; ++dx)
        for (int dy = -r; dy <= r && !found; ++dy) {
          if (std::abs(dx) != r && std::abs(dy) != r) continue;
          const int x = goal.x + dx, y = goal.y + dy;
          if (inside(x, y) && box_free[index(x, y)]) {
            goal = {x, y};
            found = true;
          }
        }
    if (!found) return {};
  }
  if (!validCell(costs, width, height, start.x, start.y, config.cost_threshold) ||
      !validCell(costs, width, height, goal.x, goal.y, config.cost_threshold))
    return {};

  struct Entry {
    double f, h;
    std::uint64_t order;
    std::size_t cell;
    bool operator>(const Entry& o) const {
      if (f != o.f) return f > o.f;
      if (h != o.h) return h > o.h;
      return order > o.order;
    }
  };
  const auto heuristic = [&](int x, int y) {
    const double dx = std::abs(x - goal.x), dy = std::abs(y - goal.y);
    return std::sqrt(dx * dx + dy * dy);
  };
  const std::size_t cells = static_cast<std::size_t>(width) * height;
  constexpr std::size_t kNone = std::numeric_limits<std::size_t>::max();
  std::vector<double> g(cells, std::numeric_limits<double>::infinity());
  std::vector<std::size_t> parent(cells, kNone);
  std::vector<bool> seen(cells, false), closed(cells, false);
  std::priority_queue<Entry, std::vector<Entry>, std::greater<Entry>> open;
  std::uint64_t pushes = 0;
  const std::size_t start_k = index(start.x, start.y), goal_k = index(goal.x, goal.y);
  g[start_k] = 0.0;
  seen[start_k] = true;
  open.push({heuristic(start.x, start.y), heuristic(start.x, start.y), pushes++, start_k});

  // The team's neighbour order: the four axis moves, then the diagonals.
  constexpr int kMoves[8][2] = {{0, 1}, {1, 0}, {0, -1}, {-1, 0}, {1, 1}, {1, -1}, {-1, 1}, {-1, -1}};
  for (std::size_t popped = 0; !open.empty() && popped < cells; ++popped) {
    const Entry current = open.top();
    open.pop();
    if (closed[current.cell]) continue;
    closed[current.cell] = true;
    if (current.cell == goal_k) {
      std::vector<GridCell> path;
      for (std::size_t k = goal_k; k != kNone; k = parent[k])
        path.push_back({static_cast<int>(k % static_cast<std::size_t>(width)),
                        static_cast<int>(k / static_cast<std::size_t>(width))});
      std::reverse(path.begin(), path.end());
      return path;
    }
    const int cx = static_cast<int>(current.cell % static_cast<std::size_t>(width));
    const int cy = static_cast<int>(current.cell / static_cast<std::size_t>(width));
    for (const auto& move : kMoves) {
      const int nx = cx + move[0], ny = cy + move[1];
      if (!inside(nx, ny)) continue;
      const std::size_t n = index(nx, ny);
      if (!box_free[n] || closed[n]) continue;
      const double base = move[0] != 0 && move[1] != 0 ? 1.414 : 1.0;
      const double cell_cost = std::max(0.0, costs[n] / 100.0);
      const double tentative = g[current.cell] + base * (1.0 + cell_cost);
      if (seen[n] && !(tentative < g[n])) continue;
      seen[n] = true;
      g[n] = tentative;
      parent[n] = current.cell;
      const double h = heuristic(nx, ny);
      open.push({tentative + h, h, pushes++, n});
    }
  }
  return {};
}

bool pathCollides(const std::vector<GridCell>& path, const std::vector<std::int8_t>& costs, int width, int height,
                  double resolution, const In2botPlannerConfig& config) {
  if (path.empty()) return true;
  // The team adds the padding (cells) to the half sizes in metres.
  const double half_width = config.vehicle_width / 2.0 + config.footprint_padding;
  const double half_length = config.vehicle_length / 2.0 + config.footprint_padding;
  const double corners[4][2] = {
      {half_length, half_width}, {half_length, -half_width}, {-half_length, half_width}, {-half_length, -half_width}};
  for (std::size_t i = 0; i < path.size(); ++i) {
    double yaw = 0.0;
    if (i + 1 < path.size())
      yaw = std::atan2(static_cast<double>(path[i + 1].y - path[i].y), static_cast<double>(path[i + 1].x - path[i].x));
    else if (i > 0)
      yaw = std::atan2(static_cast<double>(path[i].y - path[i - 1].y), static_cast<double>(path[i].x - path[i - 1].x));
    const double c = std::cos(yaw), s = std::sin(yaw);
    for (const auto& corner : corners) {
      const double x = corner[0] * c - corner[1] * s;
      const double y = corner[0] * s + corner[1] * c;
      const int cx = path[i].x + static_cast<int>(std::round(x / resolution));
      const int cy = path[i].y + static_cast<int>(std::round(y / resolution));
      if (!validCell(costs, width, height, cx, cy, config.cost_threshold)) return true;
    }
  }
  return false;
}

}  // namespace barn::controllers
