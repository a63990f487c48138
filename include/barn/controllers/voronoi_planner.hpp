#pragma once
/// The LiDAR-Voronoi global planner of UT AMRL's 2023 BARN entry (the team's `vor_node.py` /
/// `vor_utils.py`, luisa-mao/voronoi_global_planner@1b08652, rebuilt from its description; the
/// repository has no licence, so nothing of it is copied).
///
/// Each planning cycle, in decimetres in the odom frame:
///  1. The scan's returns become points, rounded to the even-decimetre grid (0.2 m).
///  2. A point memory keeps them for the whole episode; each scan first clears the remembered
///     points inside its own polygon (robot position + beam ends, inf beams at 5 m, every range
///     0.005 m longer).
///  3. Sites = goal (10 m along the heading of the first cycle), start (the robot), the memory
///     and a half ellipse of 20 points behind the start (relative to the first heading), a wall
///     that keeps paths going forward.
///  4. The Voronoi diagram of the sites (Boost.Polygon; the team used scipy/Qhull) gives a graph:
///     each finite edge joins its two vertices, with gap = the distance between the two sites it
///     separates; the start connects to its cell's vertices and its goal cell's vertices to the
///     goal, gap 10.
///  5. A* from start to goal: g Euclidean, h Manhattan, edges with gap < 5 skipped,
///     f = g + h + 800 / gap (the gap of the edge just taken), a closed set without reopening.
///  6. With a previous path, a second search (g Manhattan, f = g + h + 50 x the L1 distance to
///     the nearest old-path vertex) gives the re-planned old route; the fresh path replaces it only
///     if its average gap is > 1.05 x and the old path has > 8 points, or the old and re-planned
///     paths are > 5 dm apart (symmetric Hausdorff), or it is < 0.8 x as long as the old path
///     with >= 0.95 x the gap.
///  7. No path: the memory is cleared (and nothing new is published).
///
/// Tie orders: the team's A* pops (f, node) tuples from Python's heap, so equal f falls to the
/// node's coordinates (x, then y); ours does the same, then the node index. The graph itself
/// comes from another Voronoi code: where several sites are cocircular (common on an integer
/// grid) Qhull reports several vertices at one place joined by zero-length ridges, Boost one
/// vertex of higher degree, and the two enumerate edges in different orders, so equal-cost
/// alternatives may resolve differently.

#include <cstdint>
#include <optional>
#include <span>
#include <string>
#include <string_view>
#include <vector>

#include <Eigen/Core>

#include "barn/core/config.hpp"
#include "barn/core/errors.hpp"
#include "barn/core/types.hpp"

namespace barn::controllers {

/// Where the half ellipse behind the robot is centred.
enum class EllipseCentre { Start, Origin };
std::span<const std::string_view> enumNames(EllipseCentre);

struct VoronoiPlannerConfig {
  double scale = 10.0;
  int grid = 2;
  double clear_inf_range = 5.0;
  double clear_margin = 0.005;
  double goal_distance = 10.0;
  // The half ellipse: the team's (20 cos a, 15 sin a) dm in the odom frame's own axes, a from
  // the first heading + 90 to + 270 degrees. Their odom frame, like barnbench's, starts facing
  // +y, so it reaches 2 m to each side and 1.5 m back.
  double ellipse_x = 2.0;
  double ellipse_y = 1.5;
  int ellipse_points = 20;
  // Where it is centred: on the start (the robot, each cycle), as the description of the
  // `data`-tag planner says, or at the odom origin, as the node's later stored versions have it
  // (docs/systems/ut_amrl.md: at the origin the robot circles short of the goal).
  EllipseCentre ellipse_centre = EllipseCentre::Start;
  double end_gap = 10.0;
  double min_gap = 5.0;
  double gap_weight = 800.0;
  double average_gap_limit = 50.0;
  double old_path_weight = 50.0;
  double switch_gap_ratio = 1.05;
  int switch_min_old_points = 8;
  double switch_hausdorff = 5.0;
  double switch_length_ratio = 0.8;
  double switch_length_gap_ratio = 0.95;
  int hausdorff_samples = 10;

  template <class V> void visit(V& v) {
    v("scale", scale, {.unit = "1/m", .range = core::kPositive, .doc = "team: coordinates in decimetres (x 10)"});
    v("grid", grid, {.unit = "dm", .range = core::atLeast(1), .doc = "team: points rounded to even decimetres"});
    v("clear_inf_range", clear_inf_range,
      {.unit = "m", .range = core::kPositive, .doc = "team: an inf beam reaches 5 m in the clearing polygon"});
    v("clear_margin", clear_margin,
      {.unit = "m", .range = core::kNonNegative, .doc = "team: added to every range of the clearing polygon"});
    v("goal_distance", goal_distance,
      {.unit = "m", .range = core::kPositive, .doc = "team: the goal, 100 dm along the first heading"});
    v("ellipse_x", ellipse_x, {.unit = "m", .doc = "team: semi-axis along the odom x axis (20 dm)"});
    v("ellipse_y", ellipse_y, {.unit = "m", .doc = "team: semi-axis along the odom y axis (15 dm)"});
    v("ellipse_points", ellipse_points, {.doc = "team: points on the half ellipse, ends included"});
    v("ellipse_centre", ellipse_centre, {.doc = "team (description); see above"});
    v("end_gap", end_gap,
      {.unit = "dm", .range = core::kPositive, .doc = "team: gap of the start's and goal's connections"});
    v("min_gap", min_gap,
      {.unit = "dm", .range = core::kNonNegative, .doc = "team: edges with a smaller gap are skipped"});
    v("gap_weight", gap_weight, {.unit = "dm^2", .range = core::kNonNegative, .doc = "team: f += gap_weight / gap"});
    v("average_gap_limit", average_gap_limit, {.unit = "dm", .doc = "team: only gaps below this count in the average"});
    v("old_path_weight", old_path_weight,
      {.range = core::kNonNegative, .doc = "team: re-plan f += weight x L1 distance to the old path"});
    v("switch_gap_ratio", switch_gap_ratio,
      {.range = core::kPositive, .doc = "team: fresh average gap > 1.05 x the re-planned one ..."});
    v("switch_min_old_points", switch_min_old_points,
      {.range = core::kNonNegative, .doc = "team: ... and the old path has more than 8 points"});
    v("switch_hausdorff", switch_hausdorff,
      {.unit = "dm", .range = core::kNonNegative, .doc = "team: old vs re-planned path farther apart than this"});
    v("switch_length_ratio", switch_length_ratio,
      {.range = core::kPositive, .doc = "team: fresh path shorter than 0.8 x the old one ..."});
    v("switch_length_gap_ratio", switch_length_gap_ratio,
      {.range = core::kPositive, .doc = "team: ... with at least 0.95 x the re-planned gap"});
    v("hausdorff_samples", hausdorff_samples,
      {.range = core::atLeast(2), .doc = "team (the node's later version): points per path segment"});
  }
};
void validate(const VoronoiPlannerConfig& config, core::Errors& errors, const std::string& prefix);

/// A point of the memory: integer decimetres on the planner's grid.
struct GridPoint {
  int x = 0;  // [dm]
  int y = 0;  // [dm]
  auto operator<=>(const GridPoint&) const = default;
};

/// One directed graph edge.
struct GraphEdge {
  int to = 0;
  double gap = 0.0;  // [dm] distance between the two sites the Voronoi edge separates
};

/// The planning graph: the Voronoi vertices, then the start, then the goal.
struct VoronoiGraph {
  std::vector<Eigen::Vector2d> nodes;             // [dm]
  std::vector<std::vector<GraphEdge>> adjacency;  // out-edges of each node
  int start = -1;
  int goal = -1;
};

/// The graph of the sites' Voronoi diagram (sites [dm]; `start_site` and `goal_site` index
/// them). Sites are snapped to 1/1024 dm for Boost.Polygon's integer input; a site equal to an
/// earlier one after snapping is dropped (so list the start and goal first).
VoronoiGraph buildVoronoiGraph(std::span<const Eigen::Vector2d> sites, int start_site, int goal_site, double end_gap);

/// A path through the graph.
struct GraphPath {
  std::vector<Eigen::Vector2d> points;  // [dm] start first, goal last
  double average_gap = 0.0;             // [dm] mean gap of its edges below average_gap_limit
};

/// The team's A* (astar): g Euclidean, h Manhattan, f += gap_weight / gap, gaps < min_gap
/// skipped. Empty if the goal cannot be reached.
std::optional<GraphPath> searchWidest(const VoronoiGraph& graph, const VoronoiPlannerConfig& config);

/// The team's re-plan near the old path (astar2): g Manhattan, h Manhattan,
/// f += old_path_weight x (L1 distance to the nearest vertex of `old_path`), gaps < min_gap
/// skipped, no gap term.
std::optional<GraphPath> searchNearOldPath(const VoronoiGraph& graph, std::span<const Eigen::Vector2d> old_path,
                                           const VoronoiPlannerConfig& config);

/// Sum of the segment lengths.
double pathLength(std::span<const Eigen::Vector2d> path);

/// The symmetric Hausdorff distance between two polylines, each sampled at `samples` evenly
/// spaced points per segment (ends included).
double pathHausdorff(std::span<const Eigen::Vector2d> a, std::span<const Eigen::Vector2d> b, int samples);

/// Which path a cycle published, and why: the fresh one as the first path, the re-planned old
/// route (Kept), or the fresh one by one of the three switching rules.
enum class PathSwitch { First, Kept, WiderGap, Diverged, Shorter };
std::span<const std::string_view> enumNames(PathSwitch);

/// The hysteresis: the rule that makes the fresh path replace the re-planned old route (the
/// first that holds, in the order of PathSwitch), or Kept. Never First.
PathSwitch choosePath(const GraphPath& fresh, const GraphPath& replanned, std::span<const Eigen::Vector2d> old_path,
                      const VoronoiPlannerConfig& config);

/// The team's half ellipse: `count` points centre + (semi_x cos a, semi_y sin a), a evenly from
/// heading + 90 to heading + 270 degrees, ends included (axes are the frame's, not the heading's).
std::vector<Eigen::Vector2d> ellipseArc(const Eigen::Vector2d& centre, double heading, double semi_x, double semi_y,
                                        int count);

/// Whether `p` lies inside the polygon (even-odd rule). Built once per scan; edges are bucketed
/// by height so a query tests only the few edges at its y.
class ScanPolygon {
 public:
  explicit ScanPolygon(std::span<const Eigen::Vector2d> vertices);
  bool contains(const Eigen::Vector2d& p) const;

 private:
  std::vector<Eigen::Vector2d> vertices_;
  double x_min_ = 0.0, x_max_ = 0.0, y_min_ = 0.0, y_max_ = 0.0;
  double bin_height_ = 1.0;
  std::vector<int> bin_start_;  // bin b's edges: bin_edges_[bin_start_[b] .. bin_start_[b + 1])
  std::vector<int> bin_edges_;  // edge i runs from vertices_[i] to vertices_[(i + 1) % n]
};

/// The planner: point memory, graph, searches and hysteresis, one cycle per plan() call.
class VoronoiPlanner {
 public:
  explicit VoronoiPlanner(const VoronoiPlannerConfig& config) : config_(config) {}
  /// Forget the memory, the goal and the path (a new episode).
  void reset();
  /// One cycle with the scan taken at `robot` (odom frame) by a sensor at `sensor`. True if a
  /// path was found (path() is then the one to follow); false clears the memory and the path.
  bool plan(const core::LaserScan& scan, const core::Pose2& robot, const core::Pose2& sensor);

  /// The current path [m], odom frame, start first; empty before a path was found.
  std::vector<Eigen::Vector2d> pathMetres() const;
  const std::vector<Eigen::Vector2d>& path() const { return path_; }  // [dm]
  const std::vector<GridPoint>& memory() const { return memory_; }
  Eigen::Vector2d goal() const { return goal_; }                      // [dm]
  PathSwitch lastSwitch() const { return last_switch_; }
  std::size_t lastGraphNodes() const { return last_graph_nodes_; }

 private:
  /// Clears the remembered points inside the scan's polygon, then adds the scan's points.
  void updateMemory(const core::LaserScan& scan, const core::Pose2& robot, const core::Pose2& sensor);

  VoronoiPlannerConfig config_;
  bool started_ = false;
  Eigen::Vector2d goal_ = Eigen::Vector2d::Zero();    // [dm]
  Eigen::Vector2d origin_ = Eigen::Vector2d::Zero();  // [m] the first cycle's position
  double heading_ = 0.0;                              // [rad] the first cycle's heading
  std::vector<GridPoint> memory_;                   // sorted, unique
  std::vector<Eigen::Vector2d> path_;               // [dm]
  PathSwitch last_switch_ = PathSwitch::First;
  std::size_t last_graph_nodes_ = 0;
};

}  // namespace barn::controllers
