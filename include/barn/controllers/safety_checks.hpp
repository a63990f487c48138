#pragma once
/// The Inventec controller's safety checks, as pure functions of the scan, the command and the
/// costmap (so they are tested without a simulator).
///
/// Robot frame throughout: x forward, y left, origin at the robot centre. LiDAR points include
/// the sensor's mounting offset.

#include <cstdint>
#include <numbers>
#include <string_view>
#include <vector>

#include <Eigen/Core>

#include "barn/core/beam_directions.hpp"
#include "barn/core/config.hpp"
#include "barn/core/lidar_config.hpp"
#include "barn/core/rect.hpp"
#include "barn/core/types.hpp"
#include "barn/nav/costmap.hpp"

namespace barn::controllers {

/// Every finite return of the scan as a point in the robot frame (`beams`: the caller's table
/// of beam directions, brought to the scan's layout).
std::vector<Eigen::Vector2d> scanPoints(const core::LaserScan& scan, const core::LidarConfig& lidar, core::BeamDirections& beams);

/// Footprint inflation (FI): true if any point lies inside the rectangle grown by the offset.
/// A direct rectangle test, the whole of what the original did with a polygon library.
bool footprintInflationHit(const std::vector<Eigen::Vector2d>& points, const core::Rect& inflated);

/// Rollout: rolls (v, w) forward with the unicycle model (x += v cos(psi) dt,
/// y += v sin(psi) dt, psi += w dt, one consistent model) for `steps` steps and returns true
/// if the footprint at any step contains a point: the team's real-world "MPC" check. (The
/// real-world code mirrored the lateral drift against the rotation; that is not copied here.)
bool rolloutHit(const std::vector<Eigen::Vector2d>& points, const core::Rect& footprint, const core::Twist& command,
                double dt, int steps);

/// The final-pose rollout check as the published simulation code computed it (the team's
/// `_bch_safety_check` with tolerance 0.02, LfLH's deployment script with 0.0): roll (v, w)
/// forward (`steps` Euler steps of `dt`, the unicycle model of rolloutHit) and put
/// `points_per_side` evenly spaced points, corners included, on each side of the rectangle at
/// the final pose. Each point inside the field of view reads the beam its bearing from the robot
/// centre falls in (index = floor((bearing - angle_min) / angle_increment); the LiDAR's mounting
/// offset is ignored, as the code ignored it); hit if that beam's range is below |x| + |y| of the
/// point plus the tolerance. |x| + |y| is an L1 length, up to 1.41 x the point's distance near the
/// diagonals, so returns up to that far beyond the rectangle's corners trip the check: the
/// code's test reaches well past the rectangle a point-in-rectangle test would check.
struct BeamRollout {
  core::Rect rectangle;      // [m] the costmap footprint (nav::NavStackConfig::footprint(); code: 0.42 x 0.33)
  int points_per_side = 10;  // code: 10 points per side (40 points)
  double tolerance = 0.0;    // [m] Inventec: 0.02 (safety.dist_tolerance); LfLH: 0.0
  double dt = 0.01;          // [s] code: safety.dt
  int steps = 20;            // code: safety.step (0.2 s)
};
bool beamRolloutHit(const core::LaserScan& scan, const core::Twist& command, const BeamRollout& check);

/// The configurable part of a BeamRollout, shared by LflhConfig (keys safety_*) and Inventec's
/// safety block (keys rollout_*). Each owner names the keys, and gives the doc lines of its
/// defaults' sources: visit(v, keys) with the owner's visitor puts them in the owner's block.
/// The defaults are LfLH's (tolerance 0.0, 20 steps of 0.01 s); Inventec sets its 0.02.
struct BeamRolloutConfig {
  double tolerance = 0.0;  // [m]
  int steps = 20;          // [-]
  double dt = 0.01;        // [s]

  /// The owner's key and doc line of one field (tolerance: a beam hits below the point's
  /// |x| + |y| plus it; steps: the rollout's length in Euler steps of dt).
  struct Key {
    const char* key;
    std::string_view doc;
  };
  struct Keys {
    Key tolerance, steps, dt;
  };
  template <class V> void visit(V& v, const Keys& keys) {
    v(keys.tolerance.key, tolerance, {.unit = "m", .range = core::kNonNegative, .doc = keys.tolerance.doc});
    v(keys.steps.key, steps, {.range = core::closed(1, 10000), .doc = keys.steps.doc});
    v(keys.dt.key, dt, {.unit = "s", .range = core::kPositive, .doc = keys.dt.doc});
  }
  /// The check on `rectangle` (the stack's footprint, nav::NavStackConfig::footprint()).
  BeamRollout check(const core::Rect& rectangle) const {
    BeamRollout c;
    c.rectangle = rectangle;
    c.tolerance = tolerance;
    c.dt = dt;
    c.steps = steps;
    return c;
  }
};

/// The front check of the team's simulation code: a rectangle |y| <= half_width + pad_x
/// (lateral), x from -half_length to half_length + max(pad_front, speed_gain * v) (forward),
/// rotated about the robot centre by rotate_gain * w toward the turn. True if a return whose beam
/// bearing is within +-front_angle of straight ahead lies inside. Returns at larger bearings are
/// ignored, however close.
struct FrontCheck {
  double front_angle = 47.0 * std::numbers::pi / 180.0;  // [rad] code: lidar.front_angle 47 deg
  double half_width = 0.0;     // [m] half core::RobotConfig::footprint_width (code: 0.43 / 2)
  double half_length = 0.0;    // [m] half core::RobotConfig::footprint_length (code: 0.508 / 2)
  double pad_x = 0.01;         // [m] code: front_pad_x_m (lateral, each side)
  double pad_front = 0.1;      // [m] code: front_pad_y_m (the minimum reach past the front edge)
  double speed_gain = 0.25;    // [s] code: linear_v_gain
  double rotate_gain = 0.2;    // [s] code: rotate_w_gain
};
bool frontCheckHit(const core::LaserScan& scan, const core::LidarConfig& lidar, core::BeamDirections& beams,
                   const core::Twist& command, const FrontCheck& check);

/// The LiDAR ring of the team's code (`is_collide`): true if any raw range (from the sensor, not
/// the robot centre) is at or below a threshold that grows linearly with |bearing| from `front`
/// straight ahead to `edge` at the scan's widest bearing (the code's linspace over beam indices).
bool ringHit(const core::LaserScan& scan, double front, double edge);

/// True if every return within +-angle of straight ahead is farther than `distance` from the
/// sensor (misses count as far): the team's condition for the speed boost.
bool frontClear(const core::LaserScan& scan, double angle, double distance);

/// The value (0-100) costmap_2d publishes for a cost, which the team's code read: 0 free,
/// 100 lethal, 99 inscribed, the rest scaled into 1-98 (unknown, -1, does not occur here).
int publishedCost(std::uint8_t cost);

/// The cells within `reach` of the robot centre that the costmap costs inscribed or lethal
/// (published 99 or 100: an obstacle cell, or one within the map's inscribed radius of one,
/// measured between cell centres as costmap_2d inflates), as robot-frame points at the cell
/// centres: what the team's real-world code rolled turns in place out against. Found from the
/// obstacle cells directly, so the map's own (lazy) inflation is never run.
std::vector<Eigen::Vector2d> inscribedCellPoints(const nav::Costmap& costmap, const core::Pose2& pose, double reach);

/// The team's costmap test of a robot-frame rectangle behind the robot (the LiDAR cannot see
/// there; the costmap remembers what it saw): true if a cell under it is lethal, or if the mean
/// published value of its cells with a nonzero cost exceeds `weight` x 100 (weight <= 0: the
/// lethal test only). Costs are the costmap's inflation of the distance to the nearest obstacle
/// cell, found directly, so the map's own (lazy) inflation is never run.
bool rearRegionBlocked(const nav::Costmap& costmap, const core::Pose2& pose, const core::Rect& region, double weight);

/// The strip `depth` deep directly behind `footprint`, as wide as it (the code's backtrack ROI).
core::Rect rearStrip(const core::Rect& footprint, double depth);

/// The rotate check of the team's simulation code (a 60 Hz thread whose flag aborts every turn
/// in place): true if a return lies in the footprint rectangle turned by rotate_gain * w toward
/// the turn, or if the costmap holds an obstacle in the half of a strip behind the robot that
/// the tail swings into (the LiDAR cannot see there; the costmap remembers what it saw).
struct RotateCheck {
  core::Rect body;                   // the footprint rectangle (code: 0.43 x 0.508)
  double rear_weight = 0.0;   // see rearRegionBlocked (the code: 0.85)
  double rotate_gain = 0.2;   // [s] code: rotate_w_gain
  double rear_centre = 0.28;  // [m] code: rear_rect_cy_m, the strip's centre behind the robot centre
  double rear_depth = 0.1;    // [m] code: rear_rect_h_m, along x
  double rear_width = 0.52;   // [m] code: rear_rect_w_m, across; half of it is tested
};
bool rotateCheckHit(const std::vector<Eigen::Vector2d>& points, const nav::Costmap& costmap, const core::Pose2& pose,
                    double turn_rate, const RotateCheck& check);

}  // namespace barn::controllers
