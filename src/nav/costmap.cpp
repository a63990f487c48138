#include "barn/nav/costmap.hpp"

#include <algorithm>
#include <cmath>
#include <cstring>
#include <limits>
#include <stdexcept>

#include "barn/nav/grid_line.hpp"

namespace barn::nav {

namespace {
// No obstacle within the reach, as a squared distance in cells (Costmap::nearest_).
constexpr std::uint32_t kNoObstacle = std::numeric_limits<std::uint32_t>::max();

// Byte loops in blocks of 16 through non-aliasing pointers: the shape GCC's -O2 vectoriser
// (its "very cheap" cost model: no alias checks, no remainder loop) turns into 16-byte
// instructions; the few cells left over go one by one.

/// dst[i] = max(dst[i], src[i]) for i < n.
void raiseTo(std::uint8_t* __restrict dst, const std::uint8_t* __restrict src, int n) {
  int i = 0;
  for (; i + 16 <= n; i += 16)
    for (int k = 0; k < 16; ++k) dst[i + k] = std::max(dst[i + k], src[i + k]);
  for (; i < n; ++i) dst[i] = std::max(dst[i], src[i]);
}

/// dst[i] = min(dst[i], src[i]) for i < n (4 per 16-byte block).
void lowerTo(std::uint32_t* __restrict dst, const std::uint32_t* __restrict src, int n) {
  int i = 0;
  for (; i + 4 <= n; i += 4)
    for (int k = 0; k < 4; ++k) dst[i + k] = std::min(dst[i + k], src[i + k]);
  for (; i < n; ++i) dst[i] = std::min(dst[i], src[i]);
}

/// An obstacle lies `at` (squared cells, kNoObstacle past its reach) from a cell whose nearest
/// obstacle was `nearest` away: it was that nearest obstacle (or tied with it). Branch-free, so
/// that anyWasNearest vectorises.
bool wasNearest(std::uint32_t at, std::uint32_t nearest) {
  return (at != kNoObstacle) & (nearest == at);
}

/// True if wasNearest(at[i], nearest[i]) for some i < n.
bool anyWasNearest(const std::uint32_t* __restrict at, const std::uint32_t* __restrict nearest, int n) {
  std::uint32_t any = 0;
  int i = 0;
  for (; i + 4 <= n; i += 4)
    for (int k = 0; k < 4; ++k) any |= static_cast<std::uint32_t>(wasNearest(at[i + k], nearest[i + k]));
  for (; i < n; ++i) any |= static_cast<std::uint32_t>(wasNearest(at[i], nearest[i]));
  return any != 0;
}
}  // namespace

void validate(const CostmapConfig& c, core::Errors& errors, const std::string& prefix) {
  core::validateFields(c, errors, prefix);
  errors.check(c.width > 0.0 && c.width / std::max(c.resolution, 1e-9) <= 10000, prefix + ".width",
               "must be > 0 and at most 10000 cells");
  errors.check(c.height > 0.0 && c.height / std::max(c.resolution, 1e-9) <= 10000, prefix + ".height",
               "must be > 0 and at most 10000 cells");
}

Costmap::Costmap(const CostmapConfig& config, double inscribed_radius)
    : config_(config), inscribed_radius_(inscribed_radius) {
  width_ = static_cast<int>(std::lround(config.width / config.resolution));
  height_ = static_cast<int>(std::lround(config.height / config.resolution));
  origin_ = {config.origin_x, config.origin_y};
  if (config.rolling) origin_ = {0.0, 0.0};  // placed by the first recentre()
  const std::uint8_t unseen = config.track_unknown ? kUnknownCost : kFreeCost;
  obstacle_.assign(static_cast<std::size_t>(width_) * static_cast<std::size_t>(height_), unseen);
  cost_.assign(obstacle_.size(), unseen);
  nearest_.assign(obstacle_.size(), kNoObstacle);
  inflated_state_ = obstacle_;
  inflation_cells_ = inflationReach();
}

int Costmap::inflationReach() const {
  // costmap_2d cuts at ceil(inflation_radius / resolution) cells, but the cost is an integer
  // that falls with distance and is 0 long before a wide radius (BARN's global 5 m at cost
  // scaling 3: past 2.1 m). Obstacles farther than the last nonzero cost change nothing, so the
  // reach stops there: the same costs, for a fraction of the work.
  const int cut = static_cast<int>(std::ceil(config_.inflation_radius / config_.resolution));
  for (long long squared = static_cast<long long>(cut) * cut; squared > 0; --squared) {
    const double cells = std::sqrt(static_cast<double>(squared));
    if (inflationCostAtCells(cells) > kFreeCost)
      return std::min(cut, static_cast<int>(std::ceil(cells)));
  }
  return 0;
}

void Costmap::buildKernel() {
  // InflationLayer's table, in cell units: a cell is inflated only within ceil(radius / res)
  // cells of its source, and the cost is taken at the cell distance times the resolution.
  const int r = inflation_cells_;
  const int side = 2 * r + 1;
  const std::size_t cells_in_box = static_cast<std::size_t>(side) * static_cast<std::size_t>(side);
  kernel_.assign(cells_in_box, kFreeCost);
  kernel_distance_.assign(cells_in_box, kNoObstacle);
  for (int dy = -r; dy <= r; ++dy)
    for (int dx = -r; dx <= r; ++dx) {
      const auto squared = static_cast<std::uint32_t>(dx * dx + dy * dy);
      const double cells = std::sqrt(static_cast<double>(squared));
      const std::uint8_t cost = cells > r ? kFreeCost : inflationCostAtCells(cells);
      const auto k = static_cast<std::size_t>((dy + r) * side + dx + r);
      kernel_[k] = cost;
      if (cost > kFreeCost) kernel_distance_[k] = squared;
      if (cost > kFreeCost && squared > 0) offsets_by_distance_.push_back({dx, dy, dy * width_ + dx, squared, cost});
    }
  std::stable_sort(offsets_by_distance_.begin(), offsets_by_distance_.end(),
                   [](const KernelOffset& a, const KernelOffset& b) { return a.squared < b.squared; });
  // first_offset_from_[d]: the first offset at least sqrt(d) cells away (the end past the last).
  const std::uint32_t farthest = offsets_by_distance_.empty() ? 0 : offsets_by_distance_.back().squared;
  first_offset_from_.assign(farthest + 2, offsets_by_distance_.size());
  for (std::size_t k = offsets_by_distance_.size(); k-- > 0;)
    for (std::uint32_t d = offsets_by_distance_[k].squared; d > (k > 0 ? offsets_by_distance_[k - 1].squared : 0); --d)
      first_offset_from_[d] = k;
  if (!offsets_by_distance_.empty()) first_offset_from_[0] = 0;
}

std::uint8_t Costmap::inflationCostAtCells(double cells) const {
  if (cells <= 0.0) return kLethalCost;
  const double distance = cells * config_.resolution;
  if (distance <= inscribed_radius_) return kInscribedCost;
  const double factor = std::exp(-config_.cost_scaling_factor * (distance - inscribed_radius_));
  return static_cast<std::uint8_t>(static_cast<double>(kInscribedCost - 1) * factor);
}

std::uint8_t Costmap::inflationCost(double distance) const {
  if (distance > config_.inflation_radius) return kFreeCost;
  return inflationCostAtCells(distance / config_.resolution);
}

Eigen::Vector2d Costmap::cellCentre(CellIndex cell) const {
  return origin_ + config_.resolution * Eigen::Vector2d(cell.x + 0.5, cell.y + 0.5);
}

std::uint8_t Costmap::costAt(const Eigen::Vector2d& p) const {
  CellIndex cell;
  return toCell(p, cell) ? cost(cell.x, cell.y) : kUnknownCost;
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
  stale_ = true;
}

void Costmap::foldCellChangesIntoBox() {
  CellBox box{width_, height_, 0, 0};
  for (const CellIndex& c : changed_)
    if (obstacle_[index(c.x, c.y)] != inflated_state_[index(c.x, c.y)])
      box = {std::min(box.x0, c.x), std::min(box.y0, c.y), std::max(box.x1, c.x + 1), std::max(box.y1, c.y + 1)};
  changed_.clear();
  if (!box.empty()) queueReinflation(box);
}

void Costmap::requireUpdated() const {
  if (stale_) throw std::logic_error("Costmap read with changes not folded in: call update() first");
}

void Costmap::update() {
  if (!stale_) return;
  if (kernel_.empty()) buildKernel();
  bool changed = false;
  // Regions first: recomputed in full, their cells are up to date.
  for (const CellBox& box : pending_) {
    reinflate(box, inflation_cells_ + 1);
    for (int y = std::max(0, box.y0); y < std::min(height_, box.y1); ++y)
      for (int x = std::max(0, box.x0); x < std::min(width_, box.x1); ++x) inflated_state_[index(x, y)] = obstacle_[index(x, y)];
    changed = true;
  }
  pending_.clear();
  // Then single cells, by what changed since their costs were last computed (a cell cleared
  // and marked again by the same scan did not change). A cell that stopped being an obstacle
  // may lower the costs within the reach that it set: they are recomputed from the obstacles
  // around them, each once (windows overlap along an obstacle's edge). A new obstacle only raises costs: its
  // kernel is stamped. Free <-> unknown changes only the cell itself.
  const int r = inflation_cells_;
  if (++recompute_round_ == 0) {  // wrapped: forget old marks
    std::fill(recomputed_in_round_.begin(), recomputed_in_round_.end(), 0);
    recompute_round_ = 1;
  }
  recomputed_in_round_.resize(obstacle_.size(), 0);
  const auto recomputeOnce = [&](int x, int y) {
    std::uint32_t& mark = recomputed_in_round_[index(x, y)];
    if (mark == recompute_round_) return;
    mark = recompute_round_;
    recomputeCell(x, y);
  };
  for (const CellIndex& c : changed_) {
    const std::size_t i = index(c.x, c.y);
    if (obstacle_[i] == inflated_state_[i] || obstacle_[i] == kLethalCost) continue;
    if (inflated_state_[i] != kLethalCost) {
      recomputeOnce(c.x, c.y);
      continue;
    }
    // Only cells whose nearest obstacle this was (or tied with it) can cost less now; the
    // others owe their cost to a nearer obstacle that is still there.
    recomputeOnce(c.x, c.y);
    const int side = 2 * r + 1;
    const int x0 = std::max(0, c.x - r), x1 = std::min(width_ - 1, c.x + r);
    for (int y = std::max(0, c.y - r); y <= std::min(height_ - 1, c.y + r); ++y) {
      const std::uint32_t* at = &kernel_distance_[static_cast<std::size_t>((y - c.y + r) * side + (x0 - c.x + r))];
      const std::uint32_t* nearest = &nearest_[index(x0, y)];
      const int n = x1 - x0 + 1;
      // Most rows hold no such cell: a branch-free pass finds the ones that do.
      if (!anyWasNearest(at, nearest, n)) continue;
      for (int k = 0; k < n; ++k)
        if (wasNearest(at[k], nearest[k])) recomputeOnce(x0 + k, y);
    }
  }
  for (const CellIndex& c : changed_) {
    const std::size_t i = index(c.x, c.y);
    if (obstacle_[i] == inflated_state_[i] || obstacle_[i] != kLethalCost) continue;
    cost_[i] = kLethalCost;
    nearest_[i] = 0;
    stampObstacle(c.x, c.y, {0, 0, width_, height_});
  }
  for (const CellIndex& c : changed_) {
    const std::size_t i = index(c.x, c.y);
    if (obstacle_[i] == inflated_state_[i]) continue;
    inflated_state_[i] = obstacle_[i];
    changed = true;
  }
  changed_.clear();
  stale_ = false;
  if (changed) ++version_;
}

void Costmap::changeObstacle(int x, int y, std::uint8_t value) {
  std::uint8_t& cell = obstacle_[index(x, y)];
  // Listed at its first change since its costs were computed (again if it returns to that
  // state and changes once more; the list is read against the state).
  if (cell == inflated_state_[index(x, y)]) changed_.push_back({x, y});
  cell = value;
  stale_ = true;
  // Past a few hundred changes one region is cheaper to re-inflate; this also bounds the list
  // of a map nobody reads.
  constexpr std::size_t kMaxChanged = 512;
  if (changed_.size() > kMaxChanged) foldCellChangesIntoBox();
}

CellIndex Costmap::rayStopCell(CellIndex from, const Eigen::Vector2d& to) const {
  // costmap_2d's ray trace pulls the end point back onto the map along the ray: onto the
  // lower edges exactly, 1 mm inside the upper ones.
  const double res = config_.resolution;
  const Eigen::Vector2d lo = origin_;
  const Eigen::Vector2d hi = origin_ + res * Eigen::Vector2d(width_, height_);
  CellIndex stop;
  // Most returns lie on the map, where nothing is pulled back.
  if (to.x() >= lo.x() && to.y() >= lo.y() && to.x() <= hi.x() - 0.001 && to.y() <= hi.y() - 0.001 && toCell(to, stop))
    return stop;
  const Eigen::Vector2d start = cellCentre(from);
  Eigen::Vector2d end = to;
  for (int axis = 0; axis < 2; ++axis) {
    const double d = end[axis] - start[axis];
    if (end[axis] < lo[axis] && d != 0.0) end = start + (end - start) * ((lo[axis] - start[axis]) / d);
    if (end[axis] > hi[axis] - 0.001 && d != 0.0) end = start + (end - start) * ((hi[axis] - 0.001 - start[axis]) / d);
  }
  if (!toCell(end, stop)) stop = {std::clamp(static_cast<int>(std::floor((end.x() - lo.x()) / res)), 0, width_ - 1),
                                  std::clamp(static_cast<int>(std::floor((end.y() - lo.y()) / res)), 0, height_ - 1)};
  return stop;
}

void Costmap::clearLine(CellIndex from, CellIndex stop, double max_cells) {
  // Every cell of the Bresenham line from the sensor's cell is freed, the end cell included,
  // for at most max_cells (raytrace_range; the dominant-axis step count scaled down for longer
  // rays).
  // Both ends are on the map, so every cell between them is; most are free already.
  walkLineFlat(from.x, from.y, stop.x, stop.y, rayStepLimit(from.x, from.y, stop.x, stop.y, max_cells), width_,
               [&](std::ptrdiff_t at) {
                 if (obstacle_[static_cast<std::size_t>(at)] != kFreeCost)
                   changeObstacle(static_cast<int>(at % width_), static_cast<int>(at / width_), kFreeCost);
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
  // The beams' directions in the sensor frame are the same every scan; each scan rotates them
  // by the sensor's yaw, as laser_geometry projects a scan with its cached cosines and sines.
  // Each usable return's end point is computed once, for the clearing and the marking below.
  beams_.update(scan);
  returns_.clear();
  for (std::size_t i = 0; i < scan.ranges.size(); ++i) {
    double range = 0.0;
    if (!usable(scan.ranges[i], range)) continue;
    const Eigen::Vector2d direction(c * beams_.cos(i) - s * beams_.sin(i), s * beams_.cos(i) + c * beams_.sin(i));
    returns_.push_back({origin + range * direction, range < config_.obstacle_range});
  }
  // Clearing first, then marking (costmap_2d's order), so a return inside another beam's
  // cleared ray stays an obstacle. Nothing is traced if the sensor is off the map, or if the
  // observation source does not clear (`clearing: false`: marks then stay until the footprint
  // covers them or the window scrolls past).
  // The traced line depends on its two end cells alone and freeing is idempotent, so a beam
  // ending in the cell the last traced beam ended in (neighbouring beams mostly do: they are
  // under 2 cm apart at 3 m) frees nothing new and is skipped.
  CellIndex sensor_cell;
  if (config_.clearing && toCell(origin, sensor_cell)) {
    const double max_cells = std::ceil(config_.raytrace_range / config_.resolution);
    CellIndex last_stop{-1, -1};
    for (const Return& r : returns_) {
      const CellIndex stop = rayStopCell(sensor_cell, r.end);
      if (stop == last_stop) continue;
      clearLine(sensor_cell, stop, max_cells);
      last_stop = stop;
    }
  }
  for (const Return& r : returns_) {
    CellIndex cell;
    if (r.marks && toCell(r.end, cell)) setObstacle(cell.x, cell.y, kLethalCost);
  }
}

void Costmap::stampObstacle(int ox, int oy, CellBox target) {
  const int r = inflation_cells_;
  const int side = 2 * r + 1;
  const int y0 = std::max(target.y0, oy - r), y1 = std::min(target.y1, oy + r + 1);
  const int x0 = std::max(target.x0, ox - r), x1 = std::min(target.x1, ox + r + 1);
  // Only free cells take a stamp, and every other cell already costs at least any stamp
  // (lethal 254 and unknown 255; a new obstacle not yet stamped is set to lethal after), so a
  // plain maximum does it.
  for (int y = y0; y < y1; ++y) {
    const auto k = static_cast<std::size_t>((y - oy + r) * side + (x0 - ox + r));
    raiseTo(&cost_[index(x0, y)], &kernel_[k], x1 - x0);
    lowerTo(&nearest_[index(x0, y)], &kernel_distance_[k], x1 - x0);
  }
}

void Costmap::recomputeCell(int x, int y) {
  const std::size_t i = index(x, y);
  const std::uint8_t state = obstacle_[i];
  if (state != kFreeCost) {
    cost_[i] = state;
    nearest_[i] = 0;  // not a free cell: no cost to explain, and 0 bounds any distance from below
    return;
  }
  // The nearest obstacle decides: offsets are visited nearest first. The cell's nearest
  // obstacle in the state it was computed for was nearest_ away, so offsets nearer than that
  // can only hold obstacles new since then, and update stamps those afterwards.
  const int r = inflation_cells_;
  const std::uint32_t from = std::min<std::uint32_t>(nearest_[i], static_cast<std::uint32_t>(first_offset_from_.size() - 1));
  const auto first = offsets_by_distance_.begin() + static_cast<std::ptrdiff_t>(first_offset_from_[from]);
  const auto last = offsets_by_distance_.end();
  const auto found = [&](const KernelOffset& o) {
    cost_[i] = o.cost;
    nearest_[i] = o.squared;
  };
  if (x >= r && y >= r && x + r < width_ && y + r < height_) {  // the whole kernel on the map
    const std::uint8_t* here = &obstacle_[i];
    for (auto o = first; o != last; ++o)
      if (here[o->flat] == kLethalCost) return found(*o);
  } else {
    for (auto o = first; o != last; ++o) {
      const int ox = x + o->dx, oy = y + o->dy;
      if (inBounds(ox, oy) && obstacle_[index(ox, oy)] == kLethalCost) return found(*o);
    }
  }
  cost_[i] = kFreeCost;
  nearest_[i] = kNoObstacle;
}

void Costmap::reinflate(CellBox changed, int grow) {
  // Cells recomputed: the changed box grown by `grow`. Obstacles that influence them: that
  // box grown by the inflation reach.
  const int r = inflation_cells_;
  const CellBox target{std::max(0, changed.x0 - grow), std::max(0, changed.y0 - grow), std::min(width_, changed.x1 + grow),
                       std::min(height_, changed.y1 + grow)};
  if (target.empty()) return;
  for (int y = target.y0; y < target.y1; ++y) {
    const std::size_t row = index(0, y);
    for (int x = target.x0; x < target.x1; ++x) {
      const std::uint8_t state = obstacle_[row + static_cast<std::size_t>(x)];
      cost_[row + static_cast<std::size_t>(x)] = state == kLethalCost || state == kUnknownCost ? state : kFreeCost;
      nearest_[row + static_cast<std::size_t>(x)] = state == kLethalCost ? 0 : kNoObstacle;
    }
  }
  // Each obstacle stamps its kernel on the free cells of the target; a cell keeps the largest
  // stamp, the cost at its nearest obstacle.
  const int ix0 = std::max(0, target.x0 - r), iy0 = std::max(0, target.y0 - r);
  const int ix1 = std::min(width_, target.x1 + r), iy1 = std::min(height_, target.y1 + r);
  for (int oy = iy0; oy < iy1; ++oy)
    for (int ox = ix0; ox < ix1; ++ox)
      if (obstacle_[index(ox, oy)] == kLethalCost) stampObstacle(ox, oy, target);
}

Eigen::Vector2d Costmap::windowOriginFor(const Eigen::Vector2d& origin, const Eigen::Vector2d& position) const {
  if (!config_.rolling) return origin;
  // costmap_2d's updateOrigin: the corner the robot asks for is half the window from
  // `position`; the window moves toward it by whole cells, rounded toward zero, so cells keep their
  // place and the window stays put until the robot is a full cell from where it would put it.
  // (The small margin only keeps a move of exactly k cells from rounding to k - 1.)
  const double res = config_.resolution;
  const auto cells = [&](double wanted, double now) {
    const double d = (wanted - now) / res;
    return static_cast<int>(d + (d >= 0.0 ? 1e-9 : -1e-9));
  };
  return {origin.x() + res * cells(position.x() - config_.width / 2, origin.x()),
          origin.y() + res * cells(position.y() - config_.height / 2, origin.y())};
}

void Costmap::recentre(const Eigen::Vector2d& position) {
  if (!config_.rolling) return;
  const double res = config_.resolution;
  const Eigen::Vector2d wanted = windowOriginFor(origin_, position);
  const int shift_x = static_cast<int>(std::lround((wanted.x() - origin_.x()) / res));
  const int shift_y = static_cast<int>(std::lround((wanted.y() - origin_.y()) / res));
  if (shift_x == 0 && shift_y == 0) return;
  // Cell (x, y) takes the old cell (x + shift_x, y + shift_y), in place: rows are visited in
  // the direction that reads each source row before it is overwritten.
  const std::uint8_t unseen = config_.track_unknown ? kUnknownCost : kFreeCost;
  const int keep_x0 = std::clamp(-shift_x, 0, width_), keep_x1 = std::clamp(width_ - shift_x, 0, width_);
  const auto shiftGrid = [&]<class Cell>(std::vector<Cell>& grid, Cell fill) {
    for (int k = 0; k < height_; ++k) {
      const int y = shift_y >= 0 ? k : height_ - 1 - k;
      Cell* row = &grid[index(0, y)];
      const int old_y = y + shift_y;
      if (old_y < 0 || old_y >= height_ || keep_x1 <= keep_x0) {
        std::fill(row, row + width_, fill);
        continue;
      }
      std::memmove(row + keep_x0, &grid[index(keep_x0 + shift_x, old_y)], sizeof(Cell) * static_cast<std::size_t>(keep_x1 - keep_x0));
      std::fill(row, row + keep_x0, fill);
      std::fill(row + keep_x1, row + width_, fill);
    }
  };
  shiftGrid(obstacle_, unseen);
  shiftGrid(cost_, unseen);
  shiftGrid(inflated_state_, unseen);
  shiftGrid(nearest_, kNoObstacle);
  origin_ = wanted;
  ++version_;
  // Regions still to re-inflate move with the cells.
  std::size_t kept = 0;
  for (const CellBox& b : pending_) {
    const CellBox m{std::max(0, b.x0 - shift_x), std::max(0, b.y0 - shift_y), std::min(width_, b.x1 - shift_x), std::min(height_, b.y1 - shift_y)};
    if (!m.empty()) pending_[kept++] = m;
  }
  pending_.resize(kept);
  kept = 0;
  for (const CellIndex& c : changed_)
    if (inBounds(c.x - shift_x, c.y - shift_y)) changed_[kept++] = {c.x - shift_x, c.y - shift_y};
  changed_.resize(kept);
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
}

void Costmap::markObstacle(const Eigen::Vector2d& p) {
  CellIndex cell;
  if (!toCell(p, cell)) return;
  setObstacle(cell.x, cell.y, kLethalCost);
}

void Costmap::setInflation(double inflation_radius, double cost_scaling_factor) {
  if (inflation_radius == config_.inflation_radius && cost_scaling_factor == config_.cost_scaling_factor) return;
  config_.inflation_radius = inflation_radius;
  config_.cost_scaling_factor = cost_scaling_factor;
  inflation_cells_ = inflationReach();
  // The kernel is rebuilt at the next inflation, and the whole map re-inflated with it
  // (InflationLayer's need_reinflation_): the single-cell changes are part of that.
  kernel_.clear();
  kernel_distance_.clear();
  offsets_by_distance_.clear();
  first_offset_from_.clear();
  changed_.clear();
  pending_.clear();
  queueReinflation({0, 0, width_, height_});
}

void Costmap::setRanges(double obstacle_range, double raytrace_range) {
  config_.obstacle_range = obstacle_range;
  config_.raytrace_range = raytrace_range;
}

void Costmap::reset() {
  // No obstacle is left, so no cell is inflated: every cost is the unseen value.
  const std::uint8_t unseen = config_.track_unknown ? kUnknownCost : kFreeCost;
  std::fill(obstacle_.begin(), obstacle_.end(), unseen);
  std::fill(cost_.begin(), cost_.end(), unseen);
  std::fill(nearest_.begin(), nearest_.end(), kNoObstacle);
  inflated_state_ = obstacle_;
  changed_.clear();
  pending_.clear();
  stale_ = false;
  ++version_;
}

void Costmap::clearOutside(const Eigen::Vector2d& centre, double radius) {
  const std::uint8_t unseen = config_.track_unknown ? kUnknownCost : kFreeCost;
  for (int y = 0; y < height_; ++y)
    for (int x = 0; x < width_; ++x)
      if ((cellCentre({x, y}) - centre).norm() > radius && obstacle_[index(x, y)] == kLethalCost) setObstacle(x, y, unseen);
  changed_.clear();
  pending_.clear();
  queueReinflation({0, 0, width_, height_});
}

}  // namespace barn::nav
