// global_planner/GlobalPlanner: makePlan and the two expansions (DijkstraExpansion,
// AStarExpansion) with the two potential calculators. The traceback and the orientation
// filter are in ros_global_planner_path.cpp. The arithmetic keeps ROS's types (float
// potentials, double literals in the quadratic, unsigned char step costs): the same
// potentials, bit for bit, on the same costs.
#include "barn/nav/ros_global_planner.hpp"

#include <algorithm>
#include <cmath>
#include <cstdlib>
#include <cstring>

namespace barn::nav {

namespace {
constexpr double kInvSqrt2 = 0.707106781;  // dijkstra.cpp INVSQRT2
constexpr int kPriorityBufSize = 10000;     // dijkstra.h PRIORITYBUFSIZE: pushes beyond are dropped
// DijkstraExpansion sets its threshold increment to 2 neutral_cost in its constructor, with
// the Expander default 50. The configured neutral_cost arrives through Expander::setNeutralCost,
// which is not virtual, so DijkstraExpansion's override that would update the increment is
// never called: the increment stays 100 whatever neutral_cost is.
constexpr float kPriorityIncrement = 100.0f;
constexpr std::uint8_t kOutlineCost = kLethalCost;  // outlineMap writes LETHAL_OBSTACLE

// float -> unsigned char as x86 converts it (through a 32-bit int, keeping the low byte): ROS
// passes float step costs above 255 to calculatePotential's unsigned char parameter.
std::uint8_t toUnsignedChar(float value) { return static_cast<std::uint8_t>(static_cast<unsigned>(static_cast<int>(value)) & 0xFFu); }
}  // namespace

void validate(const RosGlobalPlannerConfig& c, core::Errors& errors, const std::string& prefix) {
  core::validateFields(c, errors, prefix);
}

RosGlobalPlanner::RosGlobalPlanner(const RosGlobalPlannerConfig& config)
    : config_(config), lethal_(static_cast<float>(config.lethal_cost)), neutral_(static_cast<float>(config.neutral_cost)) {
  // DijkstraExpansion::getCost: c < lethal - 1 (or unknown with allow_unknown) costs
  // c factor + neutral, at most lethal - 1; anything else is lethal. In float, as ROS.
  const float factor = static_cast<float>(config.cost_factor);
  for (int c = 0; c < 256; ++c) {
    const float fc = static_cast<float>(c);
    float cost = lethal_;
    if (fc < static_cast<float>(config.lethal_cost - 1) || (config.allow_unknown && c == kUnknownCost)) {
      cost = fc * factor + neutral_;
      if (cost >= lethal_) cost = lethal_ - 1.0f;
    }
    cost_lut_[c] = cost;
    edge_lut_[c] = static_cast<float>(kInvSqrt2 * static_cast<double>(cost));
  }
}

void RosGlobalPlanner::resize(int nx, int ny) {
  if (nx == nx_ && ny == ny_) return;
  nx_ = nx;
  ny_ = ny;
  ns_ = nx * ny;
  pad_ = 3 * nx + 3;
  const std::size_t total = static_cast<std::size_t>(ns_ + 2 * pad_);
  cost_store_.assign(total, kLethalCost);
  pot_store_.assign(total, kPotHigh);
  gradx_store_.assign(total, 0.0f);
  grady_store_.assign(total, 0.0f);
  grad_cells_.clear();
  pending_.assign(static_cast<std::size_t>(ns_), 0);
  for (auto& b : buffers_) b.assign(kPriorityBufSize, 0);
  queue_.clear();
  queue_.reserve(static_cast<std::size_t>(ns_) + 4);
}

Plan RosGlobalPlanner::plan(const Costmap& costmap, const core::Pose2& start, const Eigen::Vector2d& goal, double goal_yaw) {
  const CostGrid grid{costmap.costs(), costmap.widthCells(), costmap.heightCells(), costmap.origin(), costmap.resolution()};
  return plan(grid, start, goal, goal_yaw);
}

Plan RosGlobalPlanner::plan(const CostGrid& grid, const core::Pose2& start, const Eigen::Vector2d& goal, double goal_yaw) {
  Plan result;
  expanded_ = 0;
  reached_ = false;
  const double res = grid.resolution;
  const Eigen::Vector2d origin = grid.origin;
  const double offset = config_.old_navfn_behavior ? 0.0 : 0.5;  // convert_offset_
  // costmap_2d::worldToMap: the cell, or false off the map.
  const auto toCell = [&](const Eigen::Vector2d& p, int& mx, int& my) {
    if (p.x() < origin.x() || p.y() < origin.y()) return false;
    mx = static_cast<int>((p.x() - origin.x()) / res);
    my = static_cast<int>((p.y() - origin.y()) / res);
    return mx < grid.nx && my < grid.ny;
  };
  int start_x_i = 0, start_y_i = 0, goal_x_i = 0, goal_y_i = 0;
  if (!toCell(start.position(), start_x_i, start_y_i)) return result;  // the robot is off the costmap
  if (!toCell(goal, goal_x_i, goal_y_i)) return result;                // the goal is off the costmap
  double start_x = start_x_i, start_y = start_y_i, goal_x = goal_x_i, goal_y = goal_y_i;
  if (!config_.old_navfn_behavior) {  // GlobalPlanner::worldToMap: fractional, half a cell down
    start_x = (start.x - origin.x()) / res - offset;
    start_y = (start.y - origin.y()) / res - offset;
    goal_x = (goal.x() - origin.x()) / res - offset;
    goal_y = (goal.y() - origin.y()) / res - offset;
  }

  resize(grid.nx, grid.ny);
  // Set at every plan, so that a copied or moved planner points into its own arrays.
  cost_ = cost_store_.data() + pad_;
  pot_ = pot_store_.data() + pad_;
  gradx_ = gradx_store_.data() + pad_;
  grady_ = grady_store_.data() + pad_;
  std::memcpy(cost_, grid.costs, static_cast<std::size_t>(ns_));
  cost_[start_x_i + nx_ * start_y_i] = kFreeCost;  // clearRobotCell
  if (config_.outline_map) {                        // outlineMap, after the robot's cell
    for (int x = 0; x < nx_; ++x) cost_[x] = cost_[x + nx_ * (ny_ - 1)] = kOutlineCost;
    for (int y = 0; y < ny_; ++y) cost_[nx_ * y] = cost_[nx_ - 1 + nx_ * y] = kOutlineCost;
  }

  const int cycles = nx_ * ny_ * 2;
  reached_ = config_.use_dijkstra ? expandDijkstra(start_x, start_y, goal_x, goal_y, cycles)
                                  : expandAStar(start_x, start_y, goal_x, goal_y, cycles);
  if (!config_.old_navfn_behavior) clearEndpoint(goal_x_i, goal_y_i, 2);
  if (!reached_) return result;  // "Failed to get a plan."
  const bool traced = config_.use_grid_path ? gridPath(start_x, start_y, goal_x, goal_y) : gradientPath(start_x, start_y, goal_x, goal_y);
  if (!traced || points_.empty()) return result;  // "NO PATH!": an empty plan

  // getPlanFromPotential: the points reversed (start -> goal), in world coordinates, identity
  // orientation; then makePlan appends the goal (getPlanFromPotential already did with
  // old_navfn_behavior, so the goal is there twice).
  result.path.reserve(points_.size() + 2);
  for (auto it = points_.rbegin(); it != points_.rend(); ++it)
    result.path.emplace_back(origin.x() + (static_cast<double>(it->x()) + offset) * res,
                             origin.y() + (static_cast<double>(it->y()) + offset) * res);
  result.yaw.assign(result.path.size(), 0.0);
  const int goal_copies = config_.old_navfn_behavior ? 2 : 1;
  for (int k = 0; k < goal_copies; ++k) {
    result.path.push_back(goal);
    result.yaw.push_back(goal_yaw);
  }
  applyOrientationFilter(static_cast<OrientationMode>(config_.orientation_mode), config_.orientation_window_size, start.yaw,
                         result.path, result.yaw);
  result.found = true;
  result.cost = std::llround(static_cast<double>(pot_[static_cast<int>(goal_x) + nx_ * static_cast<int>(goal_y)]));
  return result;
}

// ---------------------------------------------------------------------------------------------
// DijkstraExpansion

bool RosGlobalPlanner::expandDijkstra(double start_x, double start_y, double end_x, double end_y, int cycles) {
  std::fill(pot_store_.begin(), pot_store_.end(), kPotHigh);
  std::fill(pending_.begin(), pending_.end(), std::uint8_t{0});
  threshold_ = lethal_;
  cur_ = buffers_[0].data();
  next_ = buffers_[1].data();
  over_ = buffers_[2].data();
  cur_end_ = next_end_ = over_end_ = 0;
  const auto push_cur = [this](int n) {
    if (inMap(n) && !pending_[static_cast<std::size_t>(n)] && cost_lut_[cost_[n]] < lethal_ && cur_end_ < kPriorityBufSize) {
      cur_[cur_end_++] = n;
      pending_[static_cast<std::size_t>(n)] = 1;
    }
  };

  const int k = static_cast<int>(start_x) + nx_ * static_cast<int>(start_y);
  if (!config_.old_navfn_behavior) {
    // setPreciseStart: the start's fractions, rounded to 0.01 (floorf in float), weight the
    // 2 x 2 block at and beyond the start cell; the 8 cells around the block are queued.
    double dx = start_x - static_cast<int>(start_x);
    double dy = start_y - static_cast<int>(start_y);
    dx = std::floor(static_cast<float>(dx * 100 + 0.5)) / 100;
    dy = std::floor(static_cast<float>(dy * 100 + 0.5)) / 100;
    const double two_neutral = config_.neutral_cost * 2;
    pot_[k] = static_cast<float>(two_neutral * dx * dy);
    pot_[k + 1] = static_cast<float>(two_neutral * (1 - dx) * dy);
    pot_[k + nx_] = static_cast<float>(two_neutral * dx * (1 - dy));
    pot_[k + nx_ + 1] = static_cast<float>(two_neutral * (1 - dx) * (1 - dy));
    push_cur(k + 2);
    push_cur(k - 1);
    push_cur(k + nx_ - 1);
    push_cur(k + nx_ + 2);
    push_cur(k - nx_);
    push_cur(k - nx_ + 1);
    push_cur(k + nx_ * 2);
    push_cur(k + nx_ * 2 + 1);
  } else {
    pot_[k] = 0.0f;
    push_cur(k + 1);
    push_cur(k - 1);
    push_cur(k - nx_);
    push_cur(k + nx_);
  }

  const int goal_cell = static_cast<int>(end_x) + nx_ * static_cast<int>(end_y);
  int cycle = 0;
  for (; cycle < cycles; ++cycle) {
    if (cur_end_ == 0 && next_end_ == 0) return false;  // nothing left to expand
    for (int i = 0; i < cur_end_; ++i) pending_[static_cast<std::size_t>(cur_[i])] = 0;
    for (int i = 0; i < cur_end_; ++i) updateCell(cur_[i]);
    // The next buffer becomes the current one; when it is empty the threshold rises and the
    // overflow buffer becomes the current one.
    cur_end_ = next_end_;
    next_end_ = 0;
    std::swap(cur_, next_);
    if (cur_end_ == 0) {
      threshold_ += kPriorityIncrement;
      cur_end_ = over_end_;
      over_end_ = 0;
      std::swap(cur_, over_);
    }
    if (inMap(goal_cell) && pot_[goal_cell] < kPotHigh) break;  // the goal is reached
  }
  return cycle < cycles;
}

void RosGlobalPlanner::updateCell(int n) {
  ++expanded_;
  const float c = cost_lut_[cost_[n]];
  if (c >= lethal_) return;  // never propagate into obstacles
  const float pot = calculatePotential(n, static_cast<std::uint8_t>(c), -1.0f);
  if (!(pot < pot_[n])) return;
  const float le = edge_lut_[cost_[n - 1]];
  const float re = edge_lut_[cost_[n + 1]];
  const float ue = edge_lut_[cost_[n - nx_]];
  const float de = edge_lut_[cost_[n + nx_]];
  pot_[n] = pot;
  // Queue each neighbour whose potential exceeds pot + its cost / sqrt 2, into the next buffer
  // below the threshold, else into the overflow buffer; in ROS's order (left, right, up, down).
  int* buffer = pot < threshold_ ? next_ : over_;
  int& end = pot < threshold_ ? next_end_ : over_end_;
  const auto push = [&](int m, float edge) {
    if (pot_[m] > pot + edge && inMap(m) && !pending_[static_cast<std::size_t>(m)] && cost_lut_[cost_[m]] < lethal_ &&
        end < kPriorityBufSize) {
      buffer[end++] = m;
      pending_[static_cast<std::size_t>(m)] = 1;
    }
  };
  push(n - 1, le);
  push(n + 1, re);
  push(n - nx_, ue);
  push(n + nx_, de);
}

float RosGlobalPlanner::calculatePotential(int n, std::uint8_t cost, float prev_potential) const {
  if (config_.use_quadratic) {
    // QuadraticCalculator: NavFn's planar-wave update from the lowest horizontal and vertical
    // neighbours; prev_potential is not used.
    const float l = pot_[n - 1], r = pot_[n + 1], u = pot_[n - nx_], d = pot_[n + nx_];
    const float tc = l < r ? l : r;
    float ta = u < d ? u : d;
    const float hf = static_cast<float>(cost);
    float dc = tc - ta;
    if (dc < 0) {
      dc = -dc;
      ta = tc;
    }
    if (dc >= hf) return ta + hf;  // the front arrives from one side only
    const float q = dc / hf;
    const float v = static_cast<float>(-0.2301 * q * q + 0.5307 * q + 0.7040);
    return ta + hf * v;
  }
  // PotentialCalculator: the given potential (A*: the cell reached from), or the lowest of the
  // 4 neighbours, plus the cost.
  if (prev_potential < 0) {
    const float min_h = std::min(pot_[n - 1], pot_[n + 1]);
    const float min_v = std::min(pot_[n - nx_], pot_[n + nx_]);
    prev_potential = std::min(min_h, min_v);
  }
  return prev_potential + static_cast<float>(cost);
}

// ---------------------------------------------------------------------------------------------
// AStarExpansion

bool RosGlobalPlanner::expandAStar(double start_x, double start_y, double end_x, double end_y, int cycles) {
  const auto greater = [](const QueueEntry& a, const QueueEntry& b) { return a.cost > b.cost; };
  queue_.clear();
  const int start_i = static_cast<int>(start_x) + nx_ * static_cast<int>(start_y);
  queue_.push_back({start_i, 0.0f});
  std::fill(pot_store_.begin(), pot_store_.end(), kPotHigh);
  pot_[start_i] = 0.0f;
  const int goal_i = static_cast<int>(end_x) + nx_ * static_cast<int>(end_y);
  const int ex = static_cast<int>(end_x), ey = static_cast<int>(end_y);
  int cycle = 0;
  while (!queue_.empty() && cycle < cycles) {
    const QueueEntry top = queue_.front();
    std::pop_heap(queue_.begin(), queue_.end(), greater);
    queue_.pop_back();
    ++expanded_;
    const int i = top.i;
    if (i == goal_i) return true;
    addAStar(pot_[i], i + 1, ex, ey);
    addAStar(pot_[i], i - 1, ex, ey);
    addAStar(pot_[i], i + nx_, ex, ey);
    addAStar(pot_[i], i - nx_, ex, ey);
    ++cycle;
  }
  return false;
}

void RosGlobalPlanner::addAStar(float prev_potential, int next, int end_x, int end_y) {
  if (!inMap(next)) return;
  if (pot_[next] < kPotHigh) return;  // a cell gets its potential once
  const std::uint8_t c = cost_[next];
  if (c >= config_.lethal_cost && !(config_.allow_unknown && c == kUnknownCost)) return;
  // costs[next] + neutral_cost, an int, passed as an unsigned char: it wraps past 255.
  pot_[next] = calculatePotential(next, static_cast<std::uint8_t>(c + config_.neutral_cost), prev_potential);
  const int x = next % nx_, y = next / nx_;
  const float distance = static_cast<float>(std::abs(end_x - x) + std::abs(end_y - y));
  queue_.push_back({next, pot_[next] + distance * neutral_});
  std::push_heap(queue_.begin(), queue_.end(), [](const QueueEntry& a, const QueueEntry& b) { return a.cost > b.cost; });
}

// ---------------------------------------------------------------------------------------------
// Expander::clearEndpoint

void RosGlobalPlanner::clearEndpoint(int gx, int gy, int s) {
  // The (2s + 1)^2 cells around the goal's cell (x offset outer, y inner) that have no
  // potential get calculatePotential's from their neighbours, with step cost costmap cost +
  // neutral_cost (a float, converted to unsigned char). Cells off the array are skipped (ROS
  // reads and writes past the array there).
  const int start_cell = gx + nx_ * gy;
  for (int i = -s; i <= s; ++i) {
    for (int j = -s; j <= s; ++j) {
      const int n = start_cell + i + nx_ * j;
      if (!inMap(n) || pot_[n] < kPotHigh) continue;
      const float c = static_cast<float>(cost_[n] + config_.neutral_cost);
      pot_[n] = calculatePotential(n, toUnsignedChar(c), -1.0f);
    }
  }
}

}  // namespace barn::nav
