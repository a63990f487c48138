#pragma once
/// ROS NavFn (navfn::NavFn with navfn::NavfnROS::makePlan), the global planner of BARN's
/// move_base runs, reimplemented from its documented behaviour.
///
/// 1. Cell costs (ROS mode): lethal and inscribed (253, 254) are impassable (254); unknown
///    (255) costs 253 if allow_unknown, else impassable; any other cost c costs
///    int(neutral + factor c) (50 + 0.8 c by default: 50 ... 251). The array border (first and
///    last row and column) is impassable. The robot's own cell is taken as free (NavfnROS
///    clears it in the costmap before planning).
/// 2. Potential propagation from the ROBOT cell (NavFn's "goal"; its "start" is the goal):
///    potential 0 there, 1e10 elsewhere, and a bucketed Dijkstra over three buffers (current,
///    next, overflow) with a threshold starting at 254 that rises by 2 neutral (100) whenever
///    the current buffer empties. A cell takes its potential from its 4 neighbours with
///    NavFn's quadratic interpolation of the planar wave (see updateCell). Propagation stops as
///    soon as the goal cell has a finite potential, when the buffers are empty, or after
///    max(nx ny / 20, nx + ny) cycles.
/// 3. Path extraction: gradient descent from the goal cell toward the robot in 0.5-cell steps
///    along the bilinearly blended, normalised per-cell gradient, falling back to the lowest
///    8-neighbour near unreached cells or on oscillation, until the potential drops below
///    neutral (only the robot cell). Reversed (robot -> goal), converted to world coordinates
///    as ROS does (origin + index res, without the half-cell offset), and the requested goal
///    appended.
///
/// Potentials are floats as in NavFn. The field is rooted at the robot, so unlike the
/// Dijkstra planner nothing is reused when the robot moves: every plan is a full
/// propagation. All arrays are allocated once per map size, not per plan.

#include <cstdint>
#include <vector>

#include <Eigen/Core>

#include "barn/nav/costmap.hpp"

namespace barn::nav {

class NavFn {
 public:
  static constexpr float kPotHigh = 1.0e10f;  // NavFn POT_HIGH: not reached
  static constexpr int kCostObs = 254;        // NavFn COST_OBS: impassable

  /// neutral_cost and cost_factor are NavFn's COST_NEUTRAL (50) and COST_FACTOR (0.8).
  NavFn(bool allow_unknown, double neutral_cost = 50.0, double cost_factor = 0.8);

  /// NavFn's cost of a cell of costmap cost `c` (254 = impassable), before the border rule.
  int cellCost(std::uint8_t c) const { return cost_lut_[c]; }

  /// Copies the costmap's costs (ROS mode mapping, impassable border). Skipped while the
  /// costmap's version is unchanged.
  void setCostmap(const Costmap& costmap);

  /// Propagates the potential from `robot` until `goal` is reached (calcNavFnDijkstra with
  /// atStart). Returns true if the goal's potential is finite.
  bool propagate(CellIndex robot, CellIndex goal);

  /// Gradient descent from `goal` to the robot cell of the last propagation (calcPath with
  /// `max_steps` steps). Points are fractional cell indices, goal ... robot (NavFn order).
  /// False (and `points` partial) if the descent fails.
  bool extractPath(CellIndex goal, int max_steps, std::vector<Eigen::Vector2f>& points);

  /// Whether the last propagate() propagated (false if it refused its robot or goal cell: the
  /// potentials are then those of an earlier one).
  bool propagated() const { return propagated_; }
  /// The potential of a cell after propagate() (kPotHigh if not reached).
  float potential(int x, int y) const { return cells_[index(x, y)].pot; }
  int width() const { return nx_; }
  int height() const { return ny_; }
  /// Cell updates (updateCell calls) and cycles of the last propagation.
  std::size_t lastUpdates() const { return updates_; }
  int lastCycles() const { return cycles_; }

 private:
  std::size_t index(int x, int y) const { return static_cast<std::size_t>(y) * static_cast<std::size_t>(nx_) + static_cast<std::size_t>(x); }
  void resize(int nx, int ny);
  void updateCell(int n);
  void gradCell(int n);

  bool allow_unknown_;
  bool propagated_ = false;
  float neutral_;
  std::vector<int> cost_lut_;    // NavFn cost by costmap cost (256 entries)
  std::vector<float> edge_lut_;  // INVSQRT2 * NavFn cost, by NavFn cost (256 entries)

  int nx_ = 0, ny_ = 0, ns_ = 0;
  // NavFn's potarr, costarr and pending flags side by side: an update reads all three of each
  // neighbour, so one cache line serves where three separate arrays needed three.
  struct Cell {
    float pot;
    std::uint8_t cost;
    std::uint8_t pending;
  };
  std::vector<Cell> cells_;
  std::vector<float> gradx_, grady_;  // normalised gradient cache (0, 0 = not computed)
  std::vector<int> grad_cells_;        // cells with a cached gradient, to reset
  // The current / next / overflow buffers. NavFn caps each at 10000 cells and drops pushes
  // beyond; here each is a preallocated array of ns cells (a cell is in at most one buffer at
  // a time, guarded by its pending flag), plus room for updateCell's unkept writes past the
  // end, so nothing is ever dropped. BARN's wavefronts are a
  // few hundred cells, far below NavFn's cap, so this changes nothing in practice.
  std::vector<int> buf_[3];
  int* cur_ = nullptr;
  int* next_ = nullptr;
  int* over_ = nullptr;
  int cur_size_ = 0, next_size_ = 0, over_size_ = 0;
  float threshold_ = 0.0f;
  int robot_ = -1;  // flat index of the propagation root
  // NavfnROS writes FREE into the robot's costmap cell before planning; here the robot cell
  // of the NavFn cost array is overridden and restored at the next propagation.
  int cleared_cell_ = -1;
  std::uint8_t cleared_cost_ = 0;

  const Costmap* map_ = nullptr;  // setCostmap cache key
  std::uint64_t map_version_ = 0;
  std::size_t updates_ = 0;
  int cycles_ = 0;
};

}  // namespace barn::nav
