#pragma once
/// The global planner, one of two algorithms (planner.algorithm):
///  - navfn: ROS NavFn as move_base runs it (navfn.hpp): a potential field grown from the
///    robot with NavFn's interpolated 4-neighbour update, and a path by gradient descent, so
///    paths are not quantised to 45 degrees. Recomputed in full at every plan.
///  - dijkstra (default): the 8-connected cell Dijkstra below. Its paths follow parent cells
///    (45-degree steps) and, at a fork around an obstacle cluster, can flip between two
///    near-equal routes from one plan to the next.
/// neutral_cost and cost_factor are NavFn's COST_NEUTRAL and COST_FACTOR for both;
/// smoothing_window applies to dijkstra only.
///
/// dijkstra:
/// Each cell costs neutral_cost + cost_factor * (its costmap cost) to enter (NavFn's
/// COST_NEUTRAL 50 and COST_FACTOR 0.8), times the step length (1 or sqrt 2 cells), so paths
/// keep away from obstacles as much as the inflation says. Inscribed and lethal cells are
/// impassable; unknown cells too unless allow_unknown. Moves are 8-connected without cutting
/// the corner of an impassable cell. The start cell may be impassable (a robot brushing an
/// obstacle must still be able to leave); the goal may not.
///
/// Unlike NavFn (whose field is rooted at the robot), the search runs from the goal and yields
/// a cost-to-goal field; the path from the start follows it downhill (steepest descent with a
/// fixed tie-break, so the path does not depend on the order cells were settled in). The
/// search is A* toward the start with the octile distance at the cheapest step costs (so it
/// covers the band between goal and start, not the disc around the goal) and stops once the
/// start's cost is final. The field is reused while the costmap and the goal are unchanged and
/// the new start is settled, so replanning at 20 Hz between 10 Hz map updates mostly costs only
/// the path extraction. Edge costs are rounded to integers (tenths of the NavFn unit) so the
/// open list is a bucket queue (Dial's algorithm): exact on those integer costs.

#include <cstdint>
#include <string>
#include <vector>

#include <Eigen/Core>

#include "barn/core/errors.hpp"
#include "barn/nav/costmap.hpp"
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
  /// negative if the cell cannot be entered. round(10 (neutral + factor c) length).
  int stepCost(std::uint8_t c, bool diagonal) const;

  /// Cells settled by the last field computation (dijkstra), or cell updates of the last
  /// propagation (navfn) (for reports).
  std::size_t lastExpanded() const { return last_expanded_; }

 private:
  void computeField(const Costmap& costmap, CellIndex goal, CellIndex start);
  /// Steepest descent on the field from the start to the goal into descent_ (padded flat
  /// indices): each step to the neighbour with the least step cost + cost-to-goal; among
  /// equals, the one nearest the goal (the dearer step: a diagonal before a straight one, so a
  /// sideways shift comes early, as Dijkstra's first-settled parent has it), then the one
  /// pointing most nearly at the goal, then the first in kSteps order. The path is a function
  /// of the costs, start and goal alone, not of the search order.
  bool descend(int start_index, int goal_index, int w);
  /// A cell's flat index on the padded grid `padded_width` wide.
  static int paddedIndex(CellIndex cell, int padded_width) { return (cell.y + 1) * padded_width + cell.x + 1; }
  Plan planNavFn(const Costmap& costmap, const Eigen::Vector2d& start, const Eigen::Vector2d& goal);

  PlannerConfig config_;
  bool use_navfn_ = false;
  NavFn navfn_;
  std::vector<Eigen::Vector2f> navfn_points_;  // scratch: the descent's points
  std::vector<int> straight_cost_;  // by costmap cost (256 entries), -1 impassable
  std::vector<int> diagonal_cost_;
  // The cost-to-goal field and where it was computed.
  std::vector<std::int64_t> field_;
  std::vector<char> settled_;       // cells whose field value is final
  std::vector<int> descent_;        // scratch: the last descent's cells
  std::vector<int> heuristic_;      // scratch: A*'s h of every cell for the current start
  std::vector<std::uint8_t> padded_cost_;  // scratch: the costs, padded by a lethal border
  std::vector<std::vector<int>> buckets_;  // scratch: Dial's bucket ring
  std::vector<std::uint64_t> occupied_buckets_;  // scratch: a bit per non-empty bucket
  std::uint64_t field_version_ = 0;
  const Costmap* field_map_ = nullptr;
  CellIndex field_goal_{-1, -1};
  std::size_t last_expanded_ = 0;
};

}  // namespace barn::nav
