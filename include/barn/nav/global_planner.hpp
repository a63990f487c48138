#pragma once
/// The global planner, one of two algorithms (planner.algorithm):
///  - navfn: ROS NavFn as move_base runs it (navfn.hpp): a potential field grown from the
///    robot with NavFn's interpolated 4-neighbour update, and a path by gradient descent, so
///    paths are not quantised to 45 degrees. Recomputed in full at every plan.
///  - dijkstra (default): the 8-connected cell search below. Its paths follow cells
///    (45-degree steps) and, at a fork around an obstacle cluster, can flip between two
///    near-equal routes from one plan to the next.
/// neutral_cost and cost_factor are NavFn's COST_NEUTRAL and COST_FACTOR for both;
/// smoothing_window applies to dijkstra only.
///
/// dijkstra: the 8-connected cell search of nav::GoalField (goal_field.hpp): a cost-to-goal
/// field kept up to date incrementally and its steepest descent from the start.

#include <cstdint>
#include <string>
#include <vector>

#include <Eigen/Core>

#include "barn/core/errors.hpp"
#include "barn/nav/costmap.hpp"
#include "barn/nav/goal_field.hpp"
#include "barn/nav/navfn.hpp"

namespace barn::nav {

struct PlannerConfig {
  double rate = 20.0;          // [Hz] replanning rate (BARN's move_base configs: 20)
  bool allow_unknown = false;  // NavFn allow_unknown
  double neutral_cost = 50.0;  // cost of entering a free cell
  double cost_factor = 0.8;    // weight of the costmap cost
  int smoothing_window = 0;    // cells of moving-average smoothing (0 = raw cell path; dijkstra only)
  std::string algorithm = "dijkstra";  // navfn | dijkstra (see the header comment)

  template <class V> void visit(V& v) {
    v("algorithm", algorithm); v("rate", rate); v("allow_unknown", allow_unknown); v("neutral_cost", neutral_cost);
    v("cost_factor", cost_factor); v("smoothing_window", smoothing_window);
  }
};

void validate(const PlannerConfig& config, core::Errors& errors, const std::string& prefix);

struct Plan {
  bool found = false;
  // [m] odom frame. dijkstra: start cell centre ... goal cell centre. navfn: as NavfnROS, the
  // robot cell's corner (origin + index res, no half cell), the descent's points likewise,
  // then the requested goal itself.
  std::vector<Eigen::Vector2d> path;
  // dijkstra: total edge cost of the cell path (integer units). navfn: the goal's potential,
  // rounded.
  std::int64_t cost = 0;
};

class GlobalPlanner {
 public:
  explicit GlobalPlanner(const PlannerConfig& config);
  Plan plan(const Costmap& costmap, const Eigen::Vector2d& start, const Eigen::Vector2d& goal);

  /// Integer cost of stepping into a cell of costmap cost `c` (straight or diagonal step);
  /// negative if the cell cannot be entered (dijkstra).
  int stepCost(std::uint8_t c, bool diagonal) const { return field_.stepCost(c, diagonal); }

  /// Cells expanded by the last field update (dijkstra), or cell updates of the last
  /// propagation (navfn; a reused plan propagates nothing and leaves it) (for reports).
  std::size_t lastExpanded() const { return use_navfn_ ? last_expanded_ : field_.lastExpanded(); }

 private:
  Plan planNavFn(const Costmap& costmap, const Eigen::Vector2d& start, const Eigen::Vector2d& goal);
  Plan computeNavFnPlan(const Costmap& costmap, CellIndex s, CellIndex g, const Eigen::Vector2d& goal);

  PlannerConfig config_;
  bool use_navfn_ = false;
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
    bool operator==(const NavFnInputs&) const = default;
  };
  NavFnInputs last_navfn_inputs_;
  Plan last_navfn_plan_;
  GoalField field_;
  std::size_t last_expanded_ = 0;
};

}  // namespace barn::nav
