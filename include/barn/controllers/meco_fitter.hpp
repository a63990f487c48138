#pragma once
/// The MECO corridor sweeper/fitter (`meco`, their corridor_sweeper_fitter.py, 2 Hz): from one
/// scan, the directions with room for the robot, a corridor grown along each, and the two that
/// reach farthest along +y.
///
/// 1. The central `beams` (480, about 180 deg) of the scan, +inf as `inf_range` (10 m), are cut
///    into `sectors` (8) sectors and again into `sectors` + 1 sectors shifted by half a sector
///    (the first and the last half as wide).
/// 2. In each sector (openingInSector), the candidate ranges are tried from the smallest up
///    (skipping those below `min_range`): walking the sector's beams in order, a beam at least as
///    far as the candidate adds one arc (candidate range x beam increment) to the opening, the
///    first half an arc more; the opening is found when it exceeds 2 (robot_radius +
///    safety_radius) = 0.7 m. A nearer beam adds half an arc, finds the opening if the width
///    then exceeds 2 robot_radius + safety_radius = 0.6 m, and otherwise starts it again from 0.
///    The direction is halfway between the candidate's beam and the beam where it was found.
///    One direction at most per sector, up to 17.
/// 3. Every direction seeds a child corridor, `child_width` (0.6 m) wide and `child_length`
///    (1.0 m) long, centred on the robot and tilted along it (one direction: a straight-ahead
///    child is added; none: straight ahead and 60 deg left). Each grows (growCorridor): its
///    front edge, then its sides by the heading's world sector: heading within 45 deg of +y
///    both sides, toward -x its right side, toward +x its left side (the side toward +y), toward
///    -y none. A corridor wider than long is turned a quarter, away from its tilt.
/// 4. A final corridor, `final_width` (1.5 m) wide, aimed at the goal, grows its front edge only,
///    at `final_step_multiplier` (3) times the step, when the goal lies within
///    `final_max_bearing_deg` (45 deg) of the heading.
/// 5. All of them, in the odom frame (placed with the robot's pose when the scan was taken),
///    ordered by their largest corner y (stable), and the first `published` (2) go to the manager.
///
/// Growing an edge (growCorridorEdge): a corridor with a scan point inside does not grow. Else
/// the edge moves out by `growth_step` (0.5 m) up to `growth_steps` (5) times, while no point
/// is inside and no corner has reached odom y >= `forward_limit_y` (11 m); at the first step
/// that takes in a point it moves back by growth_step / `backoff_divisions` (0.1 m) until no
/// point is inside. The points are every `point_stride`-th (4th) return of the whole scan.
///
/// Source: meco-group/Barn_challenge@66cef2c corridors/scripts/corridor_sweeper_fitter.py,
/// corridor.py (MIT; facts restated, no code copied). docs/systems/meco.md says which stored
/// version each detail was read in.

#include <optional>
#include <span>
#include <string>
#include <vector>

#include <Eigen/Core>

#include "barn/controllers/meco_corridor.hpp"
#include "barn/core/config.hpp"
#include "barn/core/errors.hpp"
#include "barn/core/lidar_config.hpp"
#include "barn/core/types.hpp"

namespace barn::controllers {

struct MecoFitterConfig {
  double rate = 2.0;
  int beams = 480;
  int sectors = 8;
  double inf_range = 10.0;
  double min_range = 0.1;
  double robot_radius = 0.25;
  double safety_radius = 0.1;
  // team: the directions as the team's code computes them: a plain sector's half a sector to
  // the right of the beams it was found at, a shifted sector's half a sector to the left
  // (their start angles are swapped between the two loops). false: the beams' own angles.
  bool team_sector_angles = true;
  int point_stride = 4;
  double child_width = 0.6;
  double child_length = 1.0;
  double growth_step = 0.5;
  int growth_steps = 5;
  int backoff_divisions = 5;
  // Team: GOAL_2 = (-2, 11); the team compares it with map-frame corners, whose origin is
  // the start: 1 m beyond the goal line (docs/systems/meco.md)
  double forward_limit_y = 11.0;
  double fallback_tilt_deg = 60.0;
  double final_width = 1.5;
  double final_length = 1.0;
  double final_step_multiplier = 3.0;
  double final_max_bearing_deg = 45.0;
  int published = 2;

  template <class V> void visit(V& v) {
    v("rate", rate, {.unit = "Hz", .range = core::kPositive, .doc = "team: sweeper_fitter_rate"});
    v("beams", beams, {.range = core::kPositive, .doc = "team (submission): the central 480 of 720 beams"});
    v("sectors", sectors, {.range = core::kPositive, .doc = "team (submission): 8 sectors, and 9 shifted ones"});
    v("inf_range", inf_range, {.unit = "m", .range = core::kPositive, .doc = "team: +inf read as 10 m"});
    v("min_range", min_range,
      {.unit = "m", .range = core::kNonNegative, .doc = "team: nearer candidate ranges are skipped"});
    v("robot_radius", robot_radius, {.unit = "m", .range = core::kPositive, .doc = "team"});
    v("safety_radius", safety_radius, {.unit = "m", .range = core::kNonNegative, .doc = "team"});
    v("team_sector_angles", team_sector_angles);
    v("point_stride", point_stride, {.range = core::atLeast(1), .doc = "team: every 4th return is a point"});
    v("child_width", child_width, {.unit = "m", .range = core::kPositive, .doc = "team"});
    v("child_length", child_length, {.unit = "m", .range = core::kPositive, .doc = "team"});
    v("growth_step", growth_step, {.unit = "m", .range = core::kPositive, .doc = "team: Corridor.DELTA"});
    v("growth_steps", growth_steps, {.range = core::kNonNegative, .doc = "team"});
    v("backoff_divisions", backoff_divisions, {.range = core::atLeast(1), .doc = "team: back off by growth_step / 5"});
    v("forward_limit_y", forward_limit_y, {.unit = "m"});
    v("fallback_tilt_deg", fallback_tilt_deg, {.unit = "deg", .doc = "team: no opening: children at 0 and pi / 3"});
    v("final_width", final_width, {.unit = "m", .range = core::kPositive, .doc = "team"});
    v("final_length", final_length, {.unit = "m", .range = core::kPositive, .doc = "team"});
    v("final_step_multiplier", final_step_multiplier,
      {.range = core::kPositive, .doc = "team: grow_edge(step_multiplier=3)"});
    v("final_max_bearing_deg", final_max_bearing_deg,
      {.unit = "deg", .range = core::closed(0.0, 180.0), .doc = "team (submission): the goal within +-45 deg"});
    v("published", published, {.range = core::atLeast(1), .doc = "team: the two best children"});
  }
};
void validate(const MecoFitterConfig& config, core::Errors& errors, const std::string& prefix);

/// Step 2 for one sector (`ranges` its beams in order, +inf already read as inf_range):
/// the direction as a fractional beam index into the sector, (found beam + candidate beam) / 2,
/// or nothing. Ties between equal candidate ranges go to the lower beam index.
std::optional<double> openingInSector(std::span<const double> ranges, double increment, const MecoFitterConfig& config);

/// Steps 1-2: the opening directions [rad] in the sensor frame (robot heading 0, left +), plain
/// sectors first, then the shifted ones, each in order from the right.
std::vector<double> openingDirections(const core::LaserScan& scan, const MecoFitterConfig& config);

/// Every `point_stride`-th finite return (the 4th, 8th, ...) in the robot frame.
std::vector<Eigen::Vector2d> scanPoints(const core::LaserScan& scan, const core::LidarConfig& lidar, int stride);

/// Whether any of `points` lies in `corridor` (boundary included).
bool anyInside(const MecoCorridor& corridor, std::span<const Eigen::Vector2d> points);

/// Grows `edge` of `corridor` (robot frame; `pose` places it in the odom frame for the forward
/// limit) as the header comment says, with steps `step_multiplier` x growth_step.
void growCorridorEdge(MecoCorridor& corridor, MecoEdge edge, std::span<const Eigen::Vector2d> points,
                      const core::Pose2& pose, double step_multiplier, const MecoFitterConfig& config);

/// Step 3's growth of one child (robot frame): front, then the sides by the heading's world
/// sector, then the quarter turn if it came out wider than long.
void growChild(MecoCorridor& corridor, std::span<const Eigen::Vector2d> points, const core::Pose2& pose,
               const MecoFitterConfig& config);

/// Steps 1-5: the published corridors in the odom frame, best first. `pose` is the odometry when
/// the scan was taken, `goal` the goal in the odom frame.
std::vector<MecoCorridor> fitCorridors(const core::LaserScan& scan, const core::LidarConfig& lidar,
                                       const core::Pose2& pose, const Eigen::Vector2d& goal,
                                       const MecoFitterConfig& config);

}  // namespace barn::controllers
