#pragma once
/// The global planner: Dijkstra on the costmap, as move_base's NavFn.
///
/// Each cell costs neutral_cost + cost_factor * (its costmap cost) to enter (NavFn's
/// COST_NEUTRAL 50 and COST_FACTOR 0.8), times the step length (1 or sqrt 2 cells), so paths
/// prefer the middle of gaps as much as the inflation says. Inscribed and lethal cells are
/// impassable; unknown cells too unless allow_unknown. Moves are 8-connected without cutting
/// the corner of an impassable cell. The start cell may be impassable (a robot brushing an
/// obstacle must still be able to leave); the goal may not.

#include <vector>

#include <Eigen/Core>

#include "barn/core/errors.hpp"
#include "barn/nav/costmap.hpp"

namespace barn::nav {

struct PlannerConfig {
  double rate = 20.0;        // [Hz] replanning rate (BARN's move_base configs: 20)
  bool allow_unknown = false;  // NavFn allow_unknown
  double neutral_cost = 50.0;  // cost of entering a free cell
  double cost_factor = 0.8;    // weight of the costmap cost
  int smoothing_window = 0;    // cells of moving-average smoothing (0 = raw cell path)

  template <class V> void visit(V& v) {
    v("rate", rate); v("allow_unknown", allow_unknown); v("neutral_cost", neutral_cost);
    v("cost_factor", cost_factor); v("smoothing_window", smoothing_window);
  }
};

void validate(const PlannerConfig& config, core::Errors& errors, const std::string& prefix);

struct Plan {
  bool found = false;
  std::vector<Eigen::Vector2d> path;  // [m] odom frame, start cell centre ... goal
  double cost = 0.0;                  // Dijkstra cost of the cell path
};

/// Dijkstra from the start to the goal cell (stops when the goal is settled).
class GlobalPlanner {
 public:
  explicit GlobalPlanner(const PlannerConfig& config) : config_(config) {}
  Plan plan(const Costmap& costmap, const Eigen::Vector2d& start, const Eigen::Vector2d& goal);

  /// The cost of entering a cell of costmap cost `c` (negative: impassable).
  double cellCost(std::uint8_t c) const;

 private:
  PlannerConfig config_;
  // Scratch kept between plans.
  std::vector<double> distance_;
  std::vector<int> parent_;
};

}  // namespace barn::nav
