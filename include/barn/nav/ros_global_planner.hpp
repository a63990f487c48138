#pragma once
/// ROS global_planner/GlobalPlanner (ros-planning/navigation, noetic-devel, package
/// global_planner) as move_base runs it, reimplemented from its source: the same potential,
/// the same path and the same poses for the same costmap. docs/global_planners.md lists the
/// parameters, the sources and where this differs (out-of-array reads only).
///
/// makePlan, step by step:
/// 1. Start and goal to map coordinates. Both must be on the costmap. Unless
///    old_navfn_behavior, they are fractional: (w - origin) / resolution - 0.5, so a point at a
///    cell's centre has that cell's integer index; with it, the cell indices.
/// 2. The robot's cell is taken as free (clearRobotCell) and, with outline_map, the outer rows
///    and columns as lethal (254). ROS writes both into the costmap; here into a copy.
/// 3. The potential, grown from the ROBOT towards the goal for at most 2 nx ny cycles:
///    - use_dijkstra: DijkstraExpansion, NavFn's bucketed wavefront (three buffers of at most
///      10000 cells, threshold from lethal_cost up by 100 each time the current one empties)
///      until the goal cell has a potential. A cell of costmap cost c costs
///      neutral_cost + cost_factor c (at most lethal_cost - 1) if c < lethal_cost - 1 or it is
///      unknown (255) with allow_unknown; else it is impassable. Unless old_navfn_behavior the
///      start is "precise": the 2 x 2 cells at and beyond the start get
///      2 neutral_cost (dx dy, (1-dx) dy, dx (1-dy), (1-dx)(1-dy)) (dx, dy the start's
///      fractions, rounded to 0.01) and the 8 cells around that block are queued.
///    - else AStarExpansion: each cell gets a potential once, when first reached from the
///      cheapest queued cell (f = potential + neutral_cost times the Manhattan distance to
///      the goal cell); its step cost is (costmap cost + neutral_cost) as an unsigned char
///      (so it wraps past 255, and cost_factor is not used); cells of cost >= lethal_cost are
///      impassable unless unknown with allow_unknown.
///    A cell's potential is use_quadratic's QuadraticCalculator (NavFn's interpolated
///    planar-wave update from the 4 neighbours) or PotentialCalculator (lowest neighbour plus
///    the step cost; for A*, the cell it was reached from plus the step cost).
/// 4. Unless old_navfn_behavior, clearEndpoint: the 5 x 5 cells around the goal's cell that
///    have no potential get one from their neighbours (step cost costmap cost + neutral_cost).
/// 5. The path, traced from the goal to the start: use_grid_path's GridPath (to the lowest of
///    the 8 neighbours, cell by cell) or GradientPath (NavFn's 0.5-cell gradient descent with
///    its grid fallback near unreached cells and on oscillation; lethal_cost is the gradient
///    it gives an unreached cell towards a reached neighbour).
/// 6. Poses: the path reversed, at origin + (map coordinate + 0.5) resolution (+ 0 with
///    old_navfn_behavior), identity orientation; then the goal pose (twice with
///    old_navfn_behavior). Then the orientation filter (orientation_mode) over all of them.
///
/// Every plan is computed in full (the precise start depends on the robot's exact position).
/// All arrays are allocated once per map size.

#include <cstdint>
#include <span>
#include <string>
#include <string_view>
#include <utility>
#include <vector>

#include <Eigen/Core>

#include "barn/core/config.hpp"
#include "barn/core/errors.hpp"
#include "barn/core/types.hpp"
#include "barn/nav/costmap.hpp"
#include "barn/nav/plan.hpp"

namespace barn::nav {

/// GlobalPlanner's parameters under their ROS names, with ROS's defaults (the package's
/// planner_core.cpp for the node parameters, cfg/GlobalPlanner.cfg for the dynamically
/// reconfigurable ones, which move_base applies at start-up).
struct RosGlobalPlannerConfig {
  bool use_dijkstra = true;
  bool use_quadratic = true;
  bool use_grid_path = false;
  bool old_navfn_behavior = false;
  bool allow_unknown = true;
  bool outline_map = true;
  // ROS default. ROS reads it and passes it to makePlan, which does not use it (no goal
  // search): kept so a team's parameter file reads, with no effect here either.
  double default_tolerance = 0.0;
  double cost_factor = 3.0;
  int neutral_cost = 50;
  int lethal_cost = 253;
  // ROS default 1 (the cfg's; OrientationFilter's own NONE is overridden at start-up).
  // 0 none, 1 forward, 2 interpolate, 3 forward then interpolate, 4 backward, 5 leftward,
  // 6 rightward: an integer as in ROS parameter files (see OrientationMode).
  int orientation_mode = 1;
  int orientation_window_size = 1;

  template <class V> void visit(V& v) {
    v("use_dijkstra", use_dijkstra, {.doc = "ROS default. false: A*"});
    v("use_quadratic", use_quadratic, {.doc = "ROS default. false: lowest neighbour + cost"});
    v("use_grid_path", use_grid_path, {.doc = "ROS default. false: gradient descent"});
    v("old_navfn_behavior", old_navfn_behavior, {.doc = "ROS default. true: NavFn's conventions (see header)"});
    v("allow_unknown", allow_unknown, {.doc = "ROS default. unknown (255) cells are passable"});
    v("outline_map", outline_map, {.doc = "ROS default. the outer rows and columns are lethal"});
    v("default_tolerance", default_tolerance, {.unit = "m", .range = core::kNonNegative});
    v("cost_factor", cost_factor,
      {.range = core::closed(0.01, 5.0), .doc = "ROS default. weight of the costmap cost (cfg: 0.01 ... 5)"});
    v("neutral_cost", neutral_cost,
      {.range = core::closed(1, 255), .doc = "ROS default. cost of a step into a free cell (1 ... 255)"});
    v("lethal_cost", lethal_cost,
      {.range = core::closed(1, 255), .doc = "ROS default. impassable from this cost (1 ... 255)"});
    v("orientation_mode", orientation_mode, {.range = core::closed(0, 6)});
    v("orientation_window_size", orientation_window_size,
      {.unit = "poses", .range = core::closed(1, 255), .doc = "ROS default. half-width of the forward difference"});
  }
};

void validate(const RosGlobalPlannerConfig& config, core::Errors& errors, const std::string& prefix);

/// OrientationFilter's modes, numbered as ROS numbers them (orientation_mode).
enum class OrientationMode {
  None,                    // identity orientation (yaw 0), the goal keeps its own
  Forward,                 // yaw along the path (x axis forward), the goal keeps its own
  Interpolate,             // a linear blend from the start's yaw to the goal's
  ForwardThenInterpolate,  // forward up to the last straight stretch, then a blend to the goal's
  Backward,                // forward + pi
  Leftward,                // forward - pi/2 (the y axis points along the path)
  Rightward,               // forward + pi/2
};
std::span<const std::string_view> enumNames(OrientationMode);

/// OrientationFilter::processPath on poses `position` (with `yaw` as they are: 0 but the goal's
/// for makePlan's poses). `window` is orientation_window_size; `start_yaw` the robot's.
void applyOrientationFilter(OrientationMode mode, int window, double start_yaw, const std::vector<Eigen::Vector2d>& position,
                            std::vector<double>& yaw);

/// angles::normalize_angle: an angle in (-pi, pi].
double normalizeAngle(double angle);

/// The costs a plan reads: costmap_2d costs, row-major (x fastest), nx x ny cells.
struct CostGrid {
  const std::uint8_t* costs = nullptr;
  int nx = 0;
  int ny = 0;
  Eigen::Vector2d origin = Eigen::Vector2d::Zero();  // [m] lower-left corner
  double resolution = 1.0;                           // [m] cell size
};

class RosGlobalPlanner {
 public:
  static constexpr float kPotHigh = 1.0e10f;  // POT_HIGH: not reached

  explicit RosGlobalPlanner(const RosGlobalPlannerConfig& config);

  /// makePlan from the robot's pose to the goal pose (odom frame).
  Plan plan(const Costmap& costmap, const core::Pose2& start, const Eigen::Vector2d& goal, double goal_yaw);
  Plan plan(const CostGrid& grid, const core::Pose2& start, const Eigen::Vector2d& goal, double goal_yaw);

  /// The potential of a cell after plan() (kPotHigh if not reached).
  float potential(int x, int y) const { return pot_[x + nx_ * y]; }
  /// The expansion's cost of a cell of costmap cost c (DijkstraExpansion::getCost; lethal_cost
  /// = impassable).
  float dijkstraCost(std::uint8_t c) const { return cost_lut_[c]; }
  /// updateCell calls (Dijkstra) or cells taken from the queue (A*) in the last plan.
  std::size_t lastExpanded() const { return expanded_; }
  /// Whether the last plan's expansion reached the goal (before the path was traced).
  bool lastReached() const { return reached_; }

 private:
  void resize(int nx, int ny);
  bool expandDijkstra(double start_x, double start_y, double end_x, double end_y, int cycles);
  bool expandAStar(double start_x, double start_y, double end_x, double end_y, int cycles);
  void updateCell(int n);
  void addAStar(float prev_potential, int next, int end_x, int end_y);
  /// PotentialCalculator / QuadraticCalculator::calculatePotential (prev < 0: from neighbours).
  float calculatePotential(int n, std::uint8_t cost, float prev_potential) const;
  void clearEndpoint(int gx, int gy, int s);
  bool gridPath(double start_x, double start_y, double end_x, double end_y);
  bool gradientPath(double start_x, double start_y, double goal_x, double goal_y);
  void gradCell(int n);
  bool inMap(int n) const { return n >= 0 && n < ns_; }

  RosGlobalPlannerConfig config_;
  float lethal_ = 253.0f;
  float neutral_ = 50.0f;
  float cost_lut_[256];  // DijkstraExpansion::getCost by costmap cost
  float edge_lut_[256];  // float(INVSQRT2 * getCost) by costmap cost

  int nx_ = 0, ny_ = 0, ns_ = 0;
  // ROS reads a few cells past the map's edges (neighbours of edge cells, the 5 x 5 block
  // around the goal, the start's 2 x 2 block); here the arrays have a margin of 3 rows + 3
  // cells on each side: potentials unreached, costs lethal, gradients zero.
  int pad_ = 0;
  std::vector<std::uint8_t> cost_store_;
  std::vector<float> pot_store_;
  std::vector<float> gradx_store_, grady_store_;
  std::uint8_t* cost_ = nullptr;  // cell 0 of the padded arrays
  float* pot_ = nullptr;
  float* gradx_ = nullptr;
  float* grady_ = nullptr;
  std::vector<int> grad_cells_;         // cells with a gradient, zeroed before the next descent
  std::vector<std::uint8_t> pending_;   // Dijkstra: queued
  std::vector<int> buffers_[3];         // Dijkstra: current / next / overflow (10000 each)
  int* cur_ = nullptr;
  int* next_ = nullptr;
  int* over_ = nullptr;
  int cur_end_ = 0, next_end_ = 0, over_end_ = 0;
  float threshold_ = 0.0f;
  struct QueueEntry {
    int i;
    float cost;
  };
  std::vector<QueueEntry> queue_;  // A*: a binary heap (std::push_heap, lowest cost on top)
  std::vector<Eigen::Vector2f> points_;  // the traced path, goal -> start (map coordinates)
  std::size_t expanded_ = 0;
  bool reached_ = false;
};

}  // namespace barn::nav
