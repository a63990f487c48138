#pragma once
/// The local planner of UT AMRL's 2023 BARN entry: graph_navigation's constant-curvature arcs,
/// its linear evaluator and its 1-D time-optimal control (ut-amrl/graph_navigation@6666062,
/// GPL-3, rebuilt from its description; no code copied).
///
/// Robot frame: x forward, y left; a curvature is positive to the left.
///  - Arcs: num_options curvatures evenly over [-max_curvature, max_curvature]. Each arc's length
///    starts at min(max_free_path_length, the arc length to the point of closest approach to
///    the target, a quarter circle), at least the stopping distance v^2 / (2 decel); obstacles
///    cut it where the robot's box (length x width, plus obstacle_margin on every side) would
///    first touch a point; an arc shorter than the stopping distance gets length 0. Clearance:
///    the least distance of a point from the arc's centreline over the first clearance_clip of
///    the arc, at most max_clearance.
///  - Evaluator: for each arc with length > 0, path_length = length + the distance from its end
///    to the target (when no point lies on the straight line between them). The shortest such
///    arc sets the baseline cost dw x subopt x path_length + fw x length + cw x clearance; an arc
///    whose cost dw x path_length + fw x length + cw x clearance is lower wins. With UT's
///    positive fw and cw, a longer free path and more clearance *raise* the cost.
///  - Speed: 1-D time-optimal control to stop at the arc's end; the yaw rate is speed x curvature.

#include <span>
#include <string>
#include <vector>

#include <Eigen/Core>

#include "barn/core/config.hpp"
#include "barn/core/errors.hpp"

namespace barn::controllers {

/// Speed, acceleration and deceleration limits along one axis (linear or angular).
struct MotionLimits {
  double max_speed = 0.0;  // [m/s] or [rad/s]
  double max_accel = 0.0;  // [m/s^2] or [rad/s^2]
  double max_decel = 0.0;  // [m/s^2] or [rad/s^2]
};

/// graph_navigation's 1-D time-optimal control: the speed to command now, moving at
/// |speed| with `distance` left to a stop, over one control period `dt`. It accelerates while
/// a stop after one more period of acceleration still fits, cruises while a stop after one
/// period at this speed fits, else brakes (and brakes when over the limit or past the end).
double timeOptimalSpeed(const MotionLimits& limits, double speed, double distance, double dt);

struct ArcPlannerConfig {
  double robot_length = 0.5;
  double robot_width = 0.44;
  double base_link_offset = 0.0;
  double obstacle_margin = 0.05;
  int num_options = 31;
  double max_curvature = 2.5;
  double max_free_path_length = 6.0;
  double max_clearance = 1.0;
  double clearance_clip = 0.8;
  double dw = 10.0;
  double cw = 0.2;
  double fw = 0.1;
  double subopt = 1.5;

  template <class V> void visit(V& v) {
    v("robot_length", robot_length,
      {.unit = "m", .range = core::kPositive, .doc = "team (graph_navigation navigation.lua)"});
    v("robot_width", robot_width, {.unit = "m", .range = core::kPositive, .doc = "team"});
    v("base_link_offset", base_link_offset, {.unit = "m", .doc = "team: the box's centre behind the base link"});
    v("obstacle_margin", obstacle_margin, {.unit = "m", .range = core::kNonNegative, .doc = "team"});
    v("num_options", num_options, {.range = core::atLeast(2), .doc = "team"});
    v("max_curvature", max_curvature,
      {.unit = "1/m", .range = core::kPositive, .doc = "team (AckermannSampler.max_curvature)"});
    v("max_free_path_length", max_free_path_length, {.unit = "m", .range = core::kPositive, .doc = "team"});
    v("max_clearance", max_clearance, {.unit = "m", .range = core::kNonNegative, .doc = "team"});
    v("clearance_clip", clearance_clip,
      {.range = core::openClosed(0.0, 1.0), .doc = "team (clearance_path_clip_fraction)"});
    v("dw", dw, {.doc = "team (run_graphnav.sh --dw)"});
    v("cw", cw, {.unit = "1", .doc = "team (--cw); graph_navigation's default is -0.5"});
    v("fw", fw, {.doc = "team (--fw); graph_navigation's default is -1"});
    v("subopt", subopt, {.range = core::atLeast(1.0), .doc = "graph_navigation's default (UT do not set it)"});
  }
};
void validate(const ArcPlannerConfig& config, core::Errors& errors, const std::string& prefix);

/// One constant-curvature option.
struct Arc {
  double curvature = 0.0;  // [1/m]
  double length = 0.0;     // [m] free path length along the arc (0: not drivable)
  double clearance = 0.0;  // [m]
  Eigen::Vector2d end = Eigen::Vector2d::Zero();  // [m] where the arc's length ends
};

/// The arc of `curvature` toward `target`, cut by `points` (robot frame) for a robot moving at
/// `speed` that brakes at `max_decel`.
Arc evaluateArc(double curvature, const Eigen::Vector2d& target, std::span<const Eigen::Vector2d> points, double speed,
                double max_decel, const ArcPlannerConfig& config);

/// The num_options arcs, from -max_curvature to +max_curvature.
std::vector<Arc> sampleArcs(const Eigen::Vector2d& target, std::span<const Eigen::Vector2d> points, double speed,
                            double max_decel, const ArcPlannerConfig& config);

/// The least distance from the segment a-b of a point whose projection falls on it; +inf if
/// none does.
double straightLineClearance(const Eigen::Vector2d& a, const Eigen::Vector2d& b, std::span<const Eigen::Vector2d> points);

/// The linear evaluator: the index of the chosen arc, -1 if none has length > 0 (or no arc's
/// end sees the target).
int chooseArc(std::span<const Arc> arcs, const Eigen::Vector2d& target, std::span<const Eigen::Vector2d> points,
              const ArcPlannerConfig& config);

/// A command as (forward speed, yaw rate).
struct ArcCommand {
  double linear = 0.0;   // [m/s]
  double angular = 0.0;  // [rad/s]
};

/// graph_navigation's Halt: the forward speed one deceleration step nearer 0 (0 once within
/// that step or below 0.01 m/s), no turning.
ArcCommand haltCommand(double speed, const MotionLimits& linear, double dt);

/// graph_navigation's TurnInPlace toward a heading error `angle` [rad], moving at (speed,
/// yaw_rate): brake first (Halt) while |speed| > max_turn_speed; if turning the wrong way, slow
/// the turn by one angular-acceleration step; else the 1-D time-optimal turn through |angle|.
ArcCommand turnInPlaceCommand(double angle, double speed, double yaw_rate, const MotionLimits& linear,
                              const MotionLimits& angular, double max_turn_speed, double dt);

}  // namespace barn::controllers
