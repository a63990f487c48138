#pragma once
/// move_base's reaction to its local planner, shared by the controllers that run on the
/// move_base-like stack (nav::NavStack): `dwa` and `eband`.
///
/// Each control cycle the local planner either finds a command or not. A cycle without one
/// publishes zero and enters PLANNING: the robot stands until the global planner delivers a
/// path again. If no command is found for controller_patience seconds, or no plan for
/// planner_patience seconds while waiting, move_base's recoveries run, in its default order:
/// clear the costmaps beyond 3 m, rotate, clear beyond 1.84 m, rotate. After the last the goal
/// is aborted and the robot stands until the episode ends (BARN never re-sends the goal).

#include <optional>
#include <string>
#include <vector>

#include <Eigen/Core>

#include "barn/controllers/controller.hpp"
#include "barn/core/errors.hpp"
#include "barn/nav/nav_stack.hpp"

namespace barn::controllers {

/// move_base's patience and recoveries as BARN runs them. A cycle without a valid command
/// makes move_base stop and run the local planner again only once the global planner has
/// found a path (its PLANNING state).
struct MoveBaseRecoveryConfig {
  bool enabled = true;
  double controller_patience = 15.0;       // [s] without a valid command before recovering
  double planner_patience = 5.0;           // [s] waiting for a plan before recovering
  // BARN's clearing recoveries clear nothing: ClearCostmapRecovery resets only layers named
  // "obstacles", and BARN's obstacle layer is called "obstacles_layer". true clears as intended.
  bool clear_costmaps = false;
  double conservative_reset_distance = 3.0;  // [m] first clearing keeps obstacles within this
  double aggressive_reset_distance = 1.84;   // [m] 4 x the default circumscribed radius (0.46)
  // rotate_recovery (it reads ~TrajectoryPlannerROS, BARN's base_local_planner_params.yaml,
  // which the E-Band launch loads too): always counter-clockwise, a full turn, at
  // clamp(sqrt(2 acc remaining), min, max); the footprint is checked over the whole remaining
  // sweep every tick and any hit ends the behaviour at once.
  double max_rotation_speed = 1.57;        // [rad/s] max_vel_theta
  double min_rotation_speed = 0.314;       // [rad/s] min_in_place_vel_theta
  double rotation_acceleration = 20.0;     // [rad/s^2] acc_lim_theta
  double rotation_tolerance = 0.157;       // [rad] yaw_goal_tolerance
  double sweep_step = 0.017;               // [rad] sim_granularity of the sweep check
  template <class V> void visit(V& v) {
    v("enabled", enabled); v("controller_patience", controller_patience);
    v("planner_patience", planner_patience); v("clear_costmaps", clear_costmaps);
    v("conservative_reset_distance", conservative_reset_distance);
    v("aggressive_reset_distance", aggressive_reset_distance); v("max_rotation_speed", max_rotation_speed);
    v("min_rotation_speed", min_rotation_speed); v("rotation_acceleration", rotation_acceleration);
    v("rotation_tolerance", rotation_tolerance); v("sweep_step", sweep_step);
  }
};
void validate(const MoveBaseRecoveryConfig& config, core::Errors& errors, const std::string& prefix);

/// True if the padded footprint (robot frame corners) at (x, y, yaw) touches a lethal or
/// unknown cell of `costmap` on its outline, or a corner is off the map: base_local_planner's
/// CostmapModel::footprintCost < 0, as rotate_recovery checks it.
bool footprintOutlineHits(const nav::Costmap& costmap, const std::vector<Eigen::Vector2d>& footprint, double x,
                          double y, double yaw);

/// move_base's state machine around a local planner. A controller calls, every cycle after
/// updating its NavStack:
///   if (auto cmd = move_base.beforeController(obs, nav)) return *cmd;   // not CONTROLLING
///   ... run the local planner: a command, or none ...
///   return move_base.afterController(obs, nav, command);
class MoveBase {
 public:
  /// CONTROLLING, PLANNING (waiting for a plan), a running rotate_recovery, the goal aborted.
  enum class Mode { Controlling, WaitingForPlan, RecoveryRotate, Aborted };
  explicit MoveBase(const MoveBaseRecoveryConfig& config) : config_(config) {}

  void reset();
  /// The part of the cycle before the local planner: a command to publish instead of running
  /// it (a recovery turning, waiting for a plan, aborted), or nothing when it is to run.
  std::optional<core::Twist> beforeController(const Observation& obs, nav::NavStack& nav);
  /// The local planner's result this cycle (none: it found no valid command) -> what move_base
  /// publishes.
  core::Twist afterController(const Observation& obs, nav::NavStack& nav, const std::optional<core::Twist>& command);
  /// move_base aborts the goal (e.g. the local planner refused the plan): zero from now on.
  void abort() { mode_ = Mode::Aborted; }
  Mode mode() const { return mode_; }

 private:
  /// What started the current recoveries: move_base forgets them when that recovers.
  enum class RecoveryTrigger { Controller, Planner };
  core::Twist recover(const Observation& obs, nav::NavStack& nav);
  bool sweepClear(const nav::NavStack& nav, const core::Pose2& pose, double sweep) const;
  /// move_base enters PLANNING: stop until the global planner finds a path.
  void waitForPlan(double time);

  MoveBaseRecoveryConfig config_;
  Mode mode_ = Mode::Controlling;
  double last_valid_time_ = 0.0;
  int recovery_index_ = 0;  // next of move_base's four recoveries
  RecoveryTrigger recovery_trigger_ = RecoveryTrigger::Controller;
  double waiting_since_ = 0.0;  // [s] when the controller started waiting for a plan
  double rotated_ = 0.0;        // [rad] turned in the current recovery rotation
  double last_yaw_ = 0.0;
};

}  // namespace barn::controllers
