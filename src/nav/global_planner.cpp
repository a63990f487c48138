#include "barn/nav/global_planner.hpp"

#include <algorithm>
#include <cmath>
#include <limits>

namespace barn::nav {

std::span<const std::string_view> enumNames(PlannerAlgorithm) {
  static constexpr std::string_view kNames[] = {"navfn", "dijkstra", "global_planner"};
  return kNames;
}

void validate(const PlannerConfig& c, core::Errors& errors, const std::string& prefix) {
  core::validateFields(c, errors, prefix);
  validate(c.global_planner, errors, prefix + ".global_planner");
}

GlobalPlanner::GlobalPlanner(const PlannerConfig& config)
    : config_(config), navfn_(config.allow_unknown, config.neutral_cost, config.cost_factor),
      field_(config.neutral_cost, config.cost_factor, config.allow_unknown), ros_planner_(config.global_planner) {}

std::size_t GlobalPlanner::lastExpanded() const {
  switch (config_.algorithm) {
    case PlannerAlgorithm::NavFn: return last_expanded_;
    case PlannerAlgorithm::Dijkstra: return field_.lastExpanded();
    case PlannerAlgorithm::GlobalPlanner: return ros_planner_.lastExpanded();
  }
  return 0;
}

Plan GlobalPlanner::planNavFn(const Costmap& costmap, const Eigen::Vector2d& start, const Eigen::Vector2d& goal, double goal_yaw) {
  Plan result;
  CellIndex s, g;
  if (!costmap.toCell(start, s) || !costmap.toCell(goal, g)) return result;  // off the map (tolerance 0)
  const NavFnInputs inputs{&costmap, costmap.version(), s, g, goal, goal_yaw};
  if (inputs == last_navfn_inputs_) return last_navfn_plan_;
  last_navfn_inputs_ = inputs;
  last_navfn_plan_ = computeNavFnPlan(costmap, s, g, goal, goal_yaw);
  return last_navfn_plan_;
}

Plan GlobalPlanner::computeNavFnPlan(const Costmap& costmap, CellIndex s, CellIndex g, const Eigen::Vector2d& goal,
                                     double goal_yaw) {
  Plan result;
  navfn_.setCostmap(costmap);
  navfn_.propagate(s, g);
  last_expanded_ = navfn_.lastUpdates();
  if (!navfn_.propagated()) return result;
  // NavfnROS::makePlan: the point of a grid around the goal (one cell apart, out to the
  // tolerance; the goal alone at tolerance 0) that has a potential and is nearest the goal.
  Eigen::Vector2d end = goal;
  CellIndex end_cell;
  bool legal = false;
  double best = std::numeric_limits<double>::max();
  const double tolerance = config_.tolerance;
  for (double y = goal.y() - tolerance; y <= goal.y() + tolerance; y += costmap.resolution())
    for (double x = goal.x() - tolerance; x <= goal.x() + tolerance; x += costmap.resolution()) {
      CellIndex cell;
      if (!costmap.toCell(x, y, cell) || navfn_.potential(cell.x, cell.y) >= NavFn::kPotHigh) continue;
      const double squared = (x - goal.x()) * (x - goal.x()) + (y - goal.y()) * (y - goal.y());
      if (squared < best) {
        best = squared;
        end = {x, y};
        end_cell = cell;
        legal = true;
      }
    }
  if (!legal) return result;
  g = end_cell;
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
  // NavfnROS gives every pose of the descent the identity orientation, then makePlan appends
  // the requested goal pose, with its own.
  result.yaw.assign(result.path.size(), 0.0);
  result.path.push_back(end);
  result.yaw.push_back(goal_yaw);
  return result;
}

Plan GlobalPlanner::plan(const Costmap& costmap, const Eigen::Vector2d& start, const Eigen::Vector2d& goal, double start_yaw,
                         double goal_yaw) {
  if (config_.algorithm == PlannerAlgorithm::NavFn) return planNavFn(costmap, start, goal, goal_yaw);
  if (config_.algorithm == PlannerAlgorithm::GlobalPlanner)
    return ros_planner_.plan(costmap, core::Pose2{start.x(), start.y(), start_yaw}, goal, goal_yaw);
  Plan result;
  CellIndex s, g;
  if (!costmap.toCell(start, s) || !costmap.toCell(goal, g)) return result;
  if (!field_.update(costmap, s, g)) return result;
  result.found = true;
  result.cost = field_.pathCost();
  for (const CellIndex& cell : field_.path()) result.path.push_back(costmap.cellCentre(cell));
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
  result.yaw.assign(result.path.size(), 0.0);  // no orientation
  return result;
}

}  // namespace barn::nav
