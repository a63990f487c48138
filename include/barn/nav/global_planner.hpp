#pragma once
/// The global planner, one of three algorithms (planner.algorithm):
///  - navfn: ROS NavFn as move_base runs it (navfn.hpp): a potential field grown from the
///    robot with NavFn's interpolated 4-neighbour update, and a path by gradient descent, so
///    paths are not quantised to 45 degrees. Recomputed in full at every plan.
///  - dijkstra (default): the 8-connected cell search below. Its paths follow cells
///    (45-degree steps) and, at a fork around an obstacle cluster, can flip between two
///    near-equal routes from one plan to the next.
///  - global_planner: ROS global_planner/GlobalPlanner (ros_global_planner.hpp), with its own
///    parameters under their ROS names in the nested block planner.global_planner.
/// allow_unknown, neutral_cost and cost_factor are NavFn's (COST_NEUTRAL, COST_FACTOR) for
/// navfn and dijkstra; smoothing_window applies to dijkstra only. docs/global_planners.md
/// describes all three.
///
/// dijkstra: the 8-connected cell search of nav::GoalField (goal_field.hpp): a cost-to-goal
/// field kept up to date incrementally and its steepest descent from the start.

#include <cstdint>
#include <span>
#include <string>
#include <string_view>
#include <vector>

#include <Eigen/Core>

#include "barn/core/config.hpp"
#include "barn/core/errors.hpp"
#include "barn/nav/costmap.hpp"
#include "barn/nav/goal_field.hpp"
#include "barn/nav/navfn.hpp"
#include "barn/nav/plan.hpp"
#include "barn/nav/ros_global_planner.hpp"

namespace barn::nav {

enum class PlannerAlgorithm {
  NavFn,          // "navfn": ROS NavFn
  Dijkstra,       // "dijkstra": barnbench's 8-connected cell search
  GlobalPlanner,  // "global_planner": ROS global_planner/GlobalPlanner
};
std::span<const std::string_view> enumNames(PlannerAlgorithm);

struct PlannerConfig {
  double rate = 20.0;
  bool allow_unknown = false;
  double neutral_cost = 50.0;
  double cost_factor = 0.8;
  int smoothing_window = 0;
  // NavfnROS default_tolerance (navfn only; ROS default, and BARN's, 0): when the goal
  // cannot be reached, plan to the reachable point of a square grid of this half-width around
  // it, one cell apart, that is nearest to the goal.
  double tolerance = 0.0;
  PlannerAlgorithm algorithm = PlannerAlgorithm::Dijkstra;
  RosGlobalPlannerConfig global_planner;

  template <class V> void visit(V& v) {
    v("algorithm", algorithm, {.doc = "our choice (see the header comment)"});
    v("rate", rate, {.unit = "Hz", .range = core::kPositive, .doc = "replanning rate (BARN's move_base configs: 20)"});
    v("allow_unknown", allow_unknown, {.doc = "NavFn allow_unknown (navfn, dijkstra)"});
    v("neutral_cost", neutral_cost,
      {.range = core::openClosed(0.0, 1000.0), .doc = "cost of entering a free cell (navfn, dijkstra)"});
    v("cost_factor", cost_factor,
      {.range = core::closed(0.0, 100.0), .doc = "weight of the costmap cost (navfn, dijkstra)"});
    v("smoothing_window", smoothing_window,
      {.range = core::kNonNegative, .doc = "cells of moving-average smoothing (0 = raw cell path; dijkstra only)"});
    v("tolerance", tolerance, {.unit = "m", .range = core::closed(0.0, 10.0)});
    v("global_planner", global_planner, {.doc = "algorithm global_planner only, ROS names and defaults"});
  }
};

void validate(const PlannerConfig& config, core::Errors& errors, const std::string& prefix);

class GlobalPlanner {
 public:
  explicit GlobalPlanner(const PlannerConfig& config);
  /// A plan from the robot at `start` (heading `start_yaw`) to the goal pose (odom frame).
  /// The yaws matter only for global_planner's orientation filter and the goal pose's yaw.
  Plan plan(const Costmap& costmap, const Eigen::Vector2d& start, const Eigen::Vector2d& goal, double start_yaw = 0.0,
            double goal_yaw = 0.0);

  /// Integer cost of stepping into a cell of costmap cost `c` (straight or diagonal step);
  /// negative if the cell cannot be entered (dijkstra).
  int stepCost(std::uint8_t c, bool diagonal) const { return field_.stepCost(c, diagonal); }

  /// Cells expanded by the last field update (dijkstra), cell updates of the last
  /// propagation (navfn; a reused plan propagates nothing and leaves it), or global_planner's
  /// RosGlobalPlanner::lastExpanded (for reports).
  std::size_t lastExpanded() const;

 private:
  Plan planNavFn(const Costmap& costmap, const Eigen::Vector2d& start, const Eigen::Vector2d& goal, double goal_yaw);
  Plan computeNavFnPlan(const Costmap& costmap, CellIndex s, CellIndex g, const Eigen::Vector2d& goal, double goal_yaw);

  PlannerConfig config_;
  NavFn navfn_;
  std::vector<Eigen::Vector2f> navfn_points_;  // scratch: the descent's points
  // NavFn's plan depends on the costmap's costs, the robot's and the goal's cells and the goal
  // pose only. move_base replans at 20 Hz and the robot often stays in its cell between two
  // costmap updates; ROS then computes the same plan again, here the last one is returned.
  struct NavFnInputs {
    const Costmap* costmap = nullptr;
    std::uint64_t version = 0;
    CellIndex robot, goal_cell;
    Eigen::Vector2d goal = Eigen::Vector2d::Zero();
    double goal_yaw = 0.0;
    bool operator==(const NavFnInputs&) const = default;
  };
  NavFnInputs last_navfn_inputs_;
  Plan last_navfn_plan_;
  GoalField field_;
  RosGlobalPlanner ros_planner_;
  std::size_t last_expanded_ = 0;
};

}  // namespace barn::nav
