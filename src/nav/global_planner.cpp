#include <atomic>
#include <cstdio>
#include "barn/nav/global_planner.hpp"

#include <algorithm>
#include <cmath>
#include <limits>

namespace barn::nav {

namespace {
constexpr std::int64_t kUnreached = std::numeric_limits<std::int64_t>::max();
constexpr int kSteps[8][2] = {{1, 0}, {-1, 0}, {0, 1}, {0, -1}, {1, 1}, {1, -1}, {-1, 1}, {-1, -1}};
}  // namespace

void validate(const PlannerConfig& c, core::Errors& errors, const std::string& prefix) {
  errors.check(c.rate > 0.0, prefix + ".rate", "must be > 0");
  errors.check(c.neutral_cost > 0.0 && c.neutral_cost <= 1000.0, prefix + ".neutral_cost", "must be in (0, 1000]");
  errors.check(c.cost_factor >= 0.0 && c.cost_factor <= 100.0, prefix + ".cost_factor", "must be in [0, 100]");
  errors.check(c.smoothing_window >= 0, prefix + ".smoothing_window", "must be >= 0");
  errors.check(c.algorithm == "navfn" || c.algorithm == "dijkstra", prefix + ".algorithm", "must be navfn or dijkstra");
}

GlobalPlanner::GlobalPlanner(const PlannerConfig& config)
    : config_(config), use_navfn_(config.algorithm == "navfn"), navfn_(config.allow_unknown, config.neutral_cost, config.cost_factor) {
  straight_cost_.resize(256);
  diagonal_cost_.resize(256);
  for (int c = 0; c < 256; ++c) {
    double enter = config.neutral_cost + config.cost_factor * c;
    bool passable = c < kInscribedCost;
    if (c == kUnknownCost) {
      passable = config.allow_unknown;
      enter = config.neutral_cost;
    }
    straight_cost_[static_cast<std::size_t>(c)] = passable ? static_cast<int>(std::lround(10.0 * enter)) : -1;
    diagonal_cost_[static_cast<std::size_t>(c)] = passable ? static_cast<int>(std::lround(10.0 * enter * std::sqrt(2.0))) : -1;
  }
}

int GlobalPlanner::stepCost(std::uint8_t c, bool diagonal) const {
  return diagonal ? diagonal_cost_[c] : straight_cost_[c];
}

void GlobalPlanner::computeField(const Costmap& costmap, CellIndex goal, CellIndex start) {
  // The field lives on the map padded by one impassable cell on every side, so neighbours
  // need no bounds checks and a cell is one flat index.
  const int w = costmap.widthCells() + 2;
  const int h = costmap.heightCells() + 2;
  const std::size_t n = static_cast<std::size_t>(w) * static_cast<std::size_t>(h);
  field_.assign(n, kUnreached);
  settled_.assign(n, 0);
  padded_cost_.assign(n, kLethalCost);
  const std::uint8_t* costs = costmap.costs();
  for (int y = 0; y < costmap.heightCells(); ++y)
    std::copy_n(costs + static_cast<std::ptrdiff_t>(y) * costmap.widthCells(), costmap.widthCells(),
                padded_cost_.begin() + static_cast<std::ptrdiff_t>(y + 1) * w + 1);
  const std::uint8_t* cost = padded_cost_.data();
  const int* straight_cost = straight_cost_.data();
  const int* diagonal_cost = diagonal_cost_.data();
  const auto passable = [&](int i) { return straight_cost[cost[i]] >= 0; };
  const auto start_index = static_cast<std::size_t>(paddedIndex(start, w));
  int offset[8];
  for (int k = 0; k < 8; ++k) offset[k] = kSteps[k][1] * w + kSteps[k][0];

  // A* toward the start: cells are settled in order of f = g + h, with h the octile distance
  // to the start priced at the cheapest step costs. h is consistent (a step changes it by at
  // most that step's cheapest cost), so a settled cell's g is final, as in Dijkstra, while the
  // search stays in the band between goal and start instead of the disc around the goal.
  const int start_x = start.x + 1;
  const int start_y = start.y + 1;
  const int h_straight = straight_cost_[0];
  const int h_diagonal = diagonal_cost_[0];
  heuristic_.resize(n);
  for (int y = 0; y < h; ++y) {
    const int dy = std::abs(y - start_y);
    int* row = heuristic_.data() + static_cast<std::ptrdiff_t>(y) * w;
    for (int x = 0; x < w; ++x) {
      const int dx = std::abs(x - start_x);
      row[x] = h_straight * std::abs(dx - dy) + h_diagonal * std::min(dx, dy);
    }
  }
  const int* heuristic = heuristic_.data();

  // Dial's algorithm on f: a ring of buckets, one per integer f modulo (largest f increase
  // + 1), and a bitmap of the non-empty ones so the scan jumps over the (many) empty values.
  const int ring = diagonal_cost_[kInscribedCost - 1] + h_diagonal + 1;
  buckets_.resize(static_cast<std::size_t>(ring));
  for (auto& b : buckets_) b.clear();
  std::vector<std::vector<int>>& buckets = buckets_;
  std::vector<std::uint64_t>& occupied = occupied_buckets_;
  occupied.assign(static_cast<std::size_t>(ring + 63) / 64, 0);
  // A cell at `ahead` (< ring) past the current key, whose slot is `slot`.
  const auto push = [&](int slot, int ahead, int cell) {
    int target = slot + ahead;
    if (target >= ring) target -= ring;
    buckets[static_cast<std::size_t>(target)].push_back(cell);
    occupied[static_cast<std::size_t>(target) / 64] |= std::uint64_t{1} << (target % 64);
  };
  // The first non-empty slot at or after `slot`, cyclically (some slot is non-empty).
  const auto nextOccupied = [&](int slot) {
    std::size_t word = static_cast<std::size_t>(slot) / 64;
    std::uint64_t bits = occupied[word] & (~std::uint64_t{0} << (slot % 64));
    while (bits == 0) {
      word = (word + 1) % occupied.size();
      bits = occupied[word];
    }
    return static_cast<int>(word * 64 + static_cast<std::size_t>(__builtin_ctzll(bits)));
  };
  const int goal_index = paddedIndex(goal, w);
  field_[static_cast<std::size_t>(goal_index)] = 0;
  push(0, 0, goal_index);
  std::size_t pending = 1;
  std::size_t expanded = 0;
  std::int64_t d = heuristic[goal_index];  // the key of the bucket being scanned
  int slot = 0;
  // Stop once every cell with f up to the start's g is settled (h is 0 at the start): then
  // the start's g is final, and so is every cell its descent may step to or compare with,
  // since along that descent f never exceeds the start's (see plan()).
  while (pending > 0) {
    const int next = nextOccupied(slot);
    const std::int64_t next_key = d + (next - slot + ring) % ring;
    if (next_key > field_[start_index]) break;
    d = next_key;
    slot = next;
    std::vector<int>& bucket = buckets[static_cast<std::size_t>(slot)];
    // Entries are appended to this bucket while it is scanned when a step leaves f unchanged
    // (a free step straight toward the start); the loop re-reads the size for them.
    for (std::size_t k = 0; k < bucket.size(); ++k) {
      const int i = bucket[k];
      --pending;
      if (settled_[static_cast<std::size_t>(i)]) continue;  // stale entry
      const int h_here = heuristic[i];
      const std::int64_t g = field_[static_cast<std::size_t>(i)];
      if (g + h_here != d) continue;  // stale entry
      settled_[static_cast<std::size_t>(i)] = 1;
      ++expanded;
      // Reverse search: a neighbour p reaches this cell by entering it.
      const std::uint8_t here = cost[i];
      for (int dir = 0; dir < 8; ++dir) {
        const int p = i + offset[dir];
        const bool diagonal = dir >= 4;
        if (diagonal && (!passable(i + kSteps[dir][0]) || !passable(i + kSteps[dir][1] * w))) continue;  // no corner cutting
        const int step = diagonal ? diagonal_cost[here] : straight_cost[here];
        const std::int64_t candidate = g + step;
        if (candidate >= field_[static_cast<std::size_t>(p)]) continue;
        field_[static_cast<std::size_t>(p)] = candidate;
        // An impassable neighbour gets a cost (a start may sit there) but is never expanded:
        // nothing can pass through it. (The padding is impassable too.)
        if (!passable(p)) continue;
        push(slot, step + heuristic[p] - h_here, p);
        ++pending;
      }
    }
    bucket.clear();
    occupied[static_cast<std::size_t>(slot) / 64] &= ~(std::uint64_t{1} << (slot % 64));
  }
  // A start that cannot be entered is never expanded; its g is final now all the same.
  if (field_[start_index] != kUnreached) settled_[start_index] = 1;
  last_expanded_ = expanded;
}

bool GlobalPlanner::descend(int start_index, int goal_index, int w) {
  // Every cell compared is settled: a neighbour n of a cell p on the descent ties only if
  // g(n) + step = g(p), so its f = g(n) + h(n) <= g(p) + h(p); along the descent f does not
  // grow beyond the start's, and computeField settled every cell up to that.
  const std::uint8_t* cost = padded_cost_.data();
  const auto passable = [&](int i) { return straight_cost_[cost[i]] >= 0; };
  const Eigen::Vector2d goal_xy(goal_index % w, goal_index / w);
  descent_.clear();
  for (int i = start_index;;) {
    descent_.push_back(i);
    if (i == goal_index) return true;
    const Eigen::Vector2d to_goal_dir = (goal_xy - Eigen::Vector2d(i % w, i / w)).normalized();
    int best = -1;
    std::int64_t best_cost = kUnreached;
    std::int64_t best_to_goal = kUnreached;
    double best_alignment = -2.0;
    for (int dir = 0; dir < 8; ++dir) {
      const int nb = i + kSteps[dir][1] * w + kSteps[dir][0];
      const bool diagonal = dir >= 4;
      if (!passable(nb)) continue;
      if (diagonal && (!passable(i + kSteps[dir][0]) || !passable(i + kSteps[dir][1] * w))) continue;
      const std::int64_t to_goal = field_[static_cast<std::size_t>(nb)];
      if (to_goal == kUnreached || !settled_[static_cast<std::size_t>(nb)]) continue;
      const std::int64_t through = to_goal + stepCost(cost[nb], diagonal);
      const double alignment = Eigen::Vector2d(kSteps[dir][0], kSteps[dir][1]).normalized().dot(to_goal_dir);
      if (through < best_cost || (through == best_cost && (to_goal < best_to_goal ||
                                                          (to_goal == best_to_goal && alignment > best_alignment)))) {
        best_cost = through;
        best_to_goal = to_goal;
        best_alignment = alignment;
        best = nb;
      }
    }
    if (best < 0) return false;  // cannot happen for a reached start; no path rather than a loop
    i = best;
  }
}

Plan GlobalPlanner::planNavFn(const Costmap& costmap, const Eigen::Vector2d& start, const Eigen::Vector2d& goal) {
  Plan result;
  CellIndex s, g;
  if (!costmap.toCell(start, s) || !costmap.toCell(goal, g)) return result;  // off the map (tolerance 0)
  navfn_.setCostmap(costmap);
  const bool reached = navfn_.propagate(s, g);
  last_expanded_ = navfn_.lastUpdates();
  if (!reached) return result;
  // getPlanFromPotential: calcPath(4 nx). ROS's global costmap is square (800 x 800), ours is
  // a tall corridor (6 x 15 m = 120 x 300 cells) whose length is along y, so the longer side
  // stands for nx: 4 x 300 half-cell steps = 30 m of path.
  const int max_steps = 4 * std::max(navfn_.width(), navfn_.height());
  // A failed descent leaves NavFn's partial path (from the goal, not reaching the robot) in
  // ROS; here it is no plan, so move_base's behaviour of keeping the last path applies.
  if (!navfn_.extractPath(g, max_steps, navfn_points_)) return result;
  result.found = true;
  result.cost = std::llround(static_cast<double>(navfn_.potential(g.x, g.y)));
  result.path.reserve(navfn_points_.size() + 1);
  // NavfnROS::mapToWorld is origin + index * resolution WITHOUT the half-cell offset: every
  // point sits half a cell (-0.025 m at 0.05 m) below and left of where the potential put it.
  // Kept on purpose, as the Gazebo runs had it.
  const Eigen::Vector2d origin = costmap.origin();
  const double res = costmap.resolution();
  for (auto it = navfn_points_.rbegin(); it != navfn_points_.rend(); ++it)
    result.path.push_back(origin + res * it->cast<double>());
  result.path.push_back(goal);  // makePlan appends the requested goal pose
  return result;
}

Plan GlobalPlanner::plan(const Costmap& costmap, const Eigen::Vector2d& start, const Eigen::Vector2d& goal) {
  if (use_navfn_) return planNavFn(costmap, start, goal);
  Plan result;
  CellIndex s, g;
  if (!costmap.toCell(start, s) || !costmap.toCell(goal, g)) return result;
  if (straight_cost_[costmap.cost(g.x, g.y)] < 0) return result;
  const int w = costmap.widthCells() + 2;
  const auto start_index = static_cast<std::size_t>(paddedIndex(s, w));
  if (field_map_ != &costmap || field_version_ != costmap.version() || !(field_goal_ == g) ||
      field_.size() != static_cast<std::size_t>(w) * static_cast<std::size_t>(costmap.heightCells() + 2) ||
      !settled_[start_index]) {
    computeField(costmap, g, s);
    field_map_ = &costmap;
    field_version_ = costmap.version();
    field_goal_ = g;
  }
  if (field_[start_index] == kUnreached) return result;
  result.found = true;
  result.cost = field_[start_index];
  if (!descend(static_cast<int>(start_index), paddedIndex(g, w), w)) return {};
  for (const int i : descent_) result.path.push_back(costmap.cellCentre({i % w - 1, i / w - 1}));
  if (config_.smoothing_window > 1 && result.path.size() > 2) {
    // Moving average over the cell path, end points kept: removes the 45-degree staircase.
    const std::vector<Eigen::Vector2d> raw = result.path;
    const int half = config_.smoothing_window / 2;
    const int last = static_cast<int>(raw.size()) - 1;
    for (int i = 1; i < last; ++i) {
      Eigen::Vector2d sum = Eigen::Vector2d::Zero();
      int count = 0;
      for (int k = std::max(0, i - half); k <= std::min(last, i + half); ++k, ++count) sum += raw[static_cast<std::size_t>(k)];
      result.path[static_cast<std::size_t>(i)] = sum / count;
    }
  }
  return result;
}

}  // namespace barn::nav
