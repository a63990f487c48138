#pragma once
/// IN2BOT's mapping and global planning (BARN 2026), rebuilt for barnbench: a LiDAR count grid
/// in place of gmapping, the team's distance-field costs with the BARN containment-wall rule,
/// and the team's 8-connected A* with its footprint box and path check.
///
/// Sources (royalbegger/AAA, MIT): gmapping_pkg/configs/gmapping.yaml@2672db7 (grid),
/// esdf_mapping/src/esdf.cpp@5c27a07 (costs, wall rule), global_planner/src/astar_planner.cpp
/// @5c27a07 and global_planner/config/astar_planner_params.yaml@5f2bc36 (A*). No code copied.

#include <cstdint>
#include <optional>
#include <string>
#include <vector>

#include <Eigen/Core>

#include "barn/core/config.hpp"
#include "barn/core/errors.hpp"
#include "barn/core/types.hpp"

namespace barn::controllers {

/// The grid (gmapping's map in the team's stack), in the odom frame, which is the team's map
/// frame: both start at the robot's start pose.
struct In2botMapConfig {
  double origin_x = -4.0;
  double origin_y = -5.0;
  double size_x = 8.0;
  double size_y = 17.0;
  double resolution = 0.04;
  double max_range = 10.0;
  double usable_range = 8.0;
  double inf_range = 20.0;
  double occupied_ratio = 0.25;
  double linear_update = 0.2;
  double angular_update = 0.05;
  template <class V> void visit(V& v) {
    v("origin_x", origin_x, {.unit = "m", .doc = "team: gmapping xmin"});
    v("origin_y", origin_y, {.unit = "m", .doc = "team: ymin"});
    v("size_x", size_x, {.unit = "m", .doc = "team: xmax - xmin (xmax 4)"});
    v("size_y", size_y, {.unit = "m", .doc = "team: ymax - ymin (ymax 12)"});
    v("resolution", resolution, {.unit = "m", .range = core::kPositive, .doc = "team: delta"});
    v("max_range", max_range,
      {.unit = "m", .range = core::kPositive, .doc = "team: maxRange; longer readings are not used at all"});
    v("usable_range", usable_range,
      {.unit = "m", .doc = "team: maxUrange; longer readings clear this far, mark nothing"});
    v("inf_range", inf_range,
      {.unit = "m", .range = core::kPositive, .doc = "team: scan_preprocessor replace_inf_range (so, with max_range 10, a beam that saw nothing is not used)"});
    v("occupied_ratio", occupied_ratio,
      {.range = core::closedOpen(0.0, 1.0), .doc = "slam_gmapping's occ_thresh (default): occupied above"});
    v("linear_update", linear_update,
      {.unit = "m", .range = core::kNonNegative, .doc = "team: linearUpdate; a scan is added after this much travel"});
    v("angular_update", angular_update,
      {.unit = "rad", .range = core::kNonNegative, .doc = "team: angularUpdate; ... or this much turning"});
  }
};
void validate(const In2botMapConfig& config, core::Errors& errors, const std::string& prefix);

/// A grid cell: x along the odom x axis, y along odom y.
struct GridCell {
  int x = 0;
  int y = 0;
  friend bool operator==(const GridCell&, const GridCell&) = default;
};

/// Occupancy values as ROS publishes a map: unknown, free, occupied.
inline constexpr std::int8_t kUnknownCell = -1;
inline constexpr std::int8_t kFreeCell = 0;
inline constexpr std::int8_t kOccupiedCell = 100;

/// gmapping's map model without its particle filter: per cell, how often a beam passed
/// (visits) and ended there (hits); occupied when hits / visits > occupied_ratio, unknown if
/// never visited. Beams are traced from the sensor with Bresenham; a beam that was clipped at
/// usable_range marks no hit.
class ScanCountGrid {
 public:
  explicit ScanCountGrid(const In2botMapConfig& config);
  void clear();
  /// Adds one scan taken at `sensor_pose` (odom frame). Cells off the grid are skipped.
  void integrate(const core::LaserScan& scan, const core::Pose2& sensor_pose);
  int width() const { return width_; }
  int height() const { return height_; }
  double resolution() const { return config_.resolution; }
  Eigen::Vector2d origin() const { return {config_.origin_x, config_.origin_y}; }
  /// The cell holding `p` (odom frame); may be off the grid.
  GridCell cellOf(const Eigen::Vector2d& p) const;
  /// The map as published: kUnknownCell, kFreeCell or kOccupiedCell per cell, row-major (y).
  std::vector<std::int8_t> occupancy() const;

 private:
  In2botMapConfig config_;
  int width_ = 0;
  int height_ = 0;
  std::vector<std::uint32_t> visits_;
  std::vector<std::uint32_t> hits_;
};

/// The distance-field costs (the team's esdf node).
struct In2botEsdfConfig {
  double max_distance = 1.0;
  double unknown_decay = 0.8;
  bool wall_rule = true;
  int wall_row = 100;
  int wall_column = 96;
  template <class V> void visit(V& v) {
    v("max_distance", max_distance,
      {.unit = "m", .range = core::kPositive, .doc = "team: D_MAX; cost = (1 - min(d, D_MAX) / D_MAX) * 100"});
    v("unknown_decay", unknown_decay,
      {.range = core::kUnit, .doc = "team: unknown_decay_factor; unknown cells' cost x this"});
    v("wall_rule", wall_rule, {.doc = "team: cells outside BARN's containment walls are obstacles"});
    v("wall_row", wall_row,
      {.unit = "cell", .range = core::kNonNegative, .doc = "team: the rule scans rows from this one up (y = -1 m)"});
    v("wall_column", wall_column,
      {.unit = "cell", .range = core::kNonNegative, .doc = "team: ... until the walls found straddle this column"});
  }
};
void validate(const In2botEsdfConfig& config, core::Errors& errors, const std::string& prefix);

/// The team's wall rule on `occupancy` (width x height): scanning row wall_row, then the next
/// rows, left to right, x1 = the last occupied cell met while not inside a wall run and x2 =
/// the last unknown cell after one, until x1 < wall_column < x2. std::nullopt if no row up to
/// the top gives that (the team's loop has no bound; ours gives up and marks nothing).
std::optional<std::pair<int, int>> containmentWalls(const std::vector<std::int8_t>& occupancy, int width, int height,
                                                   const In2botEsdfConfig& config);
/// The costs the team's A* reads (0..100, as int8 of a ROS grid): 100 on occupied cells and,
/// with the wall rule, every column left of x1 or right of x2; (1 - d / D_MAX) * 100 truncated
/// elsewhere, d the Euclidean distance to the nearest such cell, computed in float as the team
/// did; unknown cells' costs then scaled by unknown_decay and truncated.
std::vector<std::int8_t> esdfCosts(const std::vector<std::int8_t>& occupancy, int width, int height,
                                   double resolution, const In2botEsdfConfig& config);

/// The team's A* and path check.
struct In2botPlannerConfig {
  double rate = 2.0;
  int cost_threshold = 85;
  double vehicle_width = 0.3;
  double vehicle_length = 0.35;
  int footprint_padding = 0;
  int goal_search_radius = 10;
  template <class V> void visit(V& v) {
    v("rate", rate,
      {.unit = "Hz", .range = core::kPositive, .doc = "team: planning_frequency; each tick replans if the path is gone or collides"});
    v("cost_threshold", cost_threshold,
      {.unit = "0-100", .range = core::openClosed(0, 101), .doc = "team: a cell is passable below this"});
    v("vehicle_width", vehicle_width,
      {.unit = "m", .doc = "team: along x of the grid for the box, across the path for the check"});
    v("vehicle_length", vehicle_length, {.unit = "m", .doc = "team"});
    v("footprint_padding", footprint_padding,
      {.unit = "cells", .range = core::kNonNegative, .doc = "team (added to the box; to the path check's metres as the code does)"});
    v("goal_search_radius", goal_search_radius,
      {.unit = "cells", .range = core::kNonNegative, .doc = "team: findNearestValidCell's default"});
  }
};
void validate(const In2botPlannerConfig& config, core::Errors& errors, const std::string& prefix);

/// A* on the cost grid (width x height, row-major in y), 8-connected. A neighbour is
/// expandable if every cell of the box of ceil(width / 2 res) + padding cells either side in x
/// and ceil(length / 2 res) + padding in y is on the grid and below the threshold; a step costs
/// 1 (1.414 diagonally) x (1 + cost / 100) of the cell entered; the heuristic is the Euclidean
/// cell distance. The start and goal cells themselves need only be below the threshold; a goal
/// whose box is not clear moves to the first clear cell on the square rings around it (up to
/// goal_search_radius). Ties on f go to the smaller heuristic, then to the earlier push.
/// Empty when no path is found.
std::vector<GridCell> planGridPath(const std::vector<std::int8_t>& costs, int width, int height, GridCell start,
                                   GridCell goal, double resolution, const In2botPlannerConfig& config);
/// The team's path check: at every path cell, the four corners of the length x width box
/// (plus padding, in metres as the code adds it) turned to the direction of the next cell (the
/// last cell: from the previous), rounded to cells, must be on the grid and below the threshold.
bool pathCollides(const std::vector<GridCell>& path, const std::vector<std::int8_t>& costs, int width, int height,
                  double resolution, const In2botPlannerConfig& config);

}  // namespace barn::controllers
