#pragma once
/// The MECO motion planner (`meco`, their motion_planner.py): a manoeuvre is a list of
/// constant-command segments (v, w, duration) — turns on the spot, arcs and straight lines —
/// that takes the robot from its pose to a goal point through one corridor or from one
/// corridor into the next. Everything in the odom frame; headings from the x axis.
///
/// One corridor (planSingle), to the goal point (default: the corridor's front point, moved
/// `goal_offset` back):
///  - heading within atan((width / 2 - a / 2 - m) / distance) of the goal's bearing: straight on
///    along the heading, for distance / cos(error);
///  - else an arc toward the goal, radius R = the alignment radius (alignmentRadius) clamped to
///    [min_radius, v_max / w_max], then the straight tangent to the goal; a goal inside that
///    circle: turn on the spot to face it, then straight.
/// Two corridors (planTwo), from the first into the second, whose heading differs (left or
/// right): the corner where their edges meet on the inside of the turn (cornerPoint) sets a
/// circle of radius v_max / w_max whose arc passes a / 2 + m outside the corner (its centre on
/// the bisector, R - a / 2 - m beyond the corner). The manoeuvre: an alignment arc (radius as
/// above, turning toward the first corridor's heading), the straight tangent to the corner
/// circle, the arc round the corner, the straight tangent to the second corridor's goal point.
/// A goal point inside the corner circle: the circle's radius shrinks to reach it, and the
/// robot turns on the spot to face it where it meets the circle. Circles too close for a
/// tangent: turn on the spot toward the tangent from the robot to the corner circle.
/// plan() picks: one corridor when there is no second or the robot is already in it; two when
/// the corner is not behind the robot; else (planSemiBacktrack) it first reverses along the
/// first corridor to a point 0.8 of the way from its back edge toward the corner, then plans
/// the turn from there.
/// planSequence(): backtracking through a list of corridors (each turned round), the turn out
/// of each into the next, the whole last one.
///
/// Source: meco-group/Barn_challenge@66cef2c corridors/scripts/motion_planner.py,
/// alignment_radius.py, navigator.py (MIT; facts restated, no code copied). The team's case
/// analysis (left-left, right-left, left-right, right-right and their special cases) is
/// rebuilt here as one tangent construction; docs/systems/meco.md lists where it differs.

#include <optional>
#include <span>
#include <string>
#include <vector>

#include <Eigen/Core>

#include "barn/controllers/meco_corridor.hpp"
#include "barn/core/types.hpp"

namespace barn::controllers {

/// One constant command.
struct MecoSegment {
  double linear = 0.0;    // [m/s]
  double angular = 0.0;   // [rad/s]
  double duration = 0.0;  // [s]
};

/// A manoeuvre and the poses it passes: poses[0] the start, poses[i + 1] after segments[i].
struct MecoManoeuvre {
  std::vector<MecoSegment> segments;
  std::vector<core::Pose2> poses;
};

/// The robot and the bounds the planner works with.
struct MecoPlannerParams {
  double robot_length = 0.43;  // [m] a
  double margin = 0.10;        // [m] m
  double max_speed = 0.5;      // [m/s] v_max
  double max_turn_rate = 0.3;  // [rad/s] w_max
  double goal_offset = 0.3;    // [m] the goal point's distance back from a corridor's front edge
  double min_radius = 1e-3;    // [m] the alignment radius's floor
  double semi_backtrack_fraction = 0.8;  // [-] how far back toward the corner to reverse

  double radius() const { return max_speed / max_turn_rate; }
};

/// The pose after `segment` from `pose` (exact unicycle motion).
core::Pose2 integrate(const core::Pose2& pose, const MecoSegment& segment);

/// The largest radius of an arc that turns a robot at `pose` parallel to `corridor` without
/// coming nearer than `clearance` to the side it drifts toward: (width / 2 - clearance - the
/// robot's offset toward that side) / (1 - cos(heading error)); very large when aligned.
double alignmentRadius(const core::Pose2& pose, const MecoCorridor& corridor, double clearance);

/// The corner where the edges of `from` and `to` meet on the inside of the turn (to's front,
/// back and turn-side edges against from's front and turn-side edges, the meeting points in
/// both corridors, the one farthest to the turn side of `from`); nothing if there is none.
std::optional<Eigen::Vector2d> cornerPoint(const MecoCorridor& from, const MecoCorridor& to, bool turn_left);

/// One corridor, to `goal` (default: corridor.frontPoint(goal_offset)).
MecoManoeuvre planSingle(const MecoCorridor& corridor, const core::Pose2& pose, const MecoPlannerParams& params,
                         std::optional<Eigen::Vector2d> goal = std::nullopt);

/// From `from` into `to`, to `goal` (default: to.frontPoint(goal_offset)).
MecoManoeuvre planTwo(const MecoCorridor& from, const MecoCorridor& to, const core::Pose2& pose,
                      const MecoPlannerParams& params, std::optional<Eigen::Vector2d> goal = std::nullopt);

/// Back along `from` first (reversing), then into `to`.
MecoManoeuvre planSemiBacktrack(const MecoCorridor& from, const MecoCorridor& to, const core::Pose2& pose,
                                const MecoPlannerParams& params, std::optional<Eigen::Vector2d> goal = std::nullopt);

/// The navigator's planner: one corridor, two, or back first (see the header comment).
MecoManoeuvre plan(const MecoCorridor& first, const MecoCorridor* second, const core::Pose2& pose,
                   const MecoPlannerParams& params, std::optional<Eigen::Vector2d> goal = std::nullopt);

/// Through `corridors` in order from `pose`: for each pair but the last, the first two segments
/// of plan() (alignment and tangent), continuing from where they end; the last pair in full,
/// to `goal`. Fewer than two corridors: planSingle in the one.
MecoManoeuvre planSequence(std::span<const MecoCorridor> corridors, const core::Pose2& pose,
                           const MecoPlannerParams& params, std::optional<Eigen::Vector2d> goal = std::nullopt);

}  // namespace barn::controllers
