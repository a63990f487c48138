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

#include <functional>
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
  double controller_patience = 15.0;
  double planner_patience = 5.0;
  // BARN's clearing recoveries clear nothing: ClearCostmapRecovery resets only layers named
  // "obstacles", and BARN's obstacle layer is called "obstacles_layer". true clears as intended.
  bool clear_costmaps = false;
  double conservative_reset_distance = 3.0;
  double aggressive_reset_distance = 1.84;
  // rotate_recovery (it reads ~TrajectoryPlannerROS, BARN's base_local_planner_params.yaml,
  // which the E-Band launch loads too): always counter-clockwise, a full turn, at
  // clamp(sqrt(2 acc remaining), min, max); the footprint is checked over the whole remaining
  // sweep every tick and any hit ends the behaviour at once.
  double max_rotation_speed = 1.57;
  double min_rotation_speed = 0.314;
  double rotation_acceleration = 20.0;
  double rotation_tolerance = 0.157;
  double sweep_step = 0.017;
  template <class V> void visit(V& v) {
    v("enabled", enabled);
    v("controller_patience", controller_patience,
      {.unit = "s", .range = core::kPositive, .doc = "without a valid command before recovering"});
    v("planner_patience", planner_patience,
      {.unit = "s", .range = core::kPositive, .doc = "waiting for a plan before recovering"});
    v("clear_costmaps", clear_costmaps);
    v("conservative_reset_distance", conservative_reset_distance,
      {.unit = "m", .doc = "first clearing keeps obstacles within this"});
    v("aggressive_reset_distance", aggressive_reset_distance,
      {.unit = "m", .doc = "4 x the default circumscribed radius (0.46)"});
    v("max_rotation_speed", max_rotation_speed, {.unit = "rad/s", .range = core::kPositive, .doc = "max_vel_theta"});
    v("min_rotation_speed", min_rotation_speed, {.unit = "rad/s", .doc = "min_in_place_vel_theta"});
    v("rotation_acceleration", rotation_acceleration,
      {.unit = "rad/s^2", .range = core::kPositive, .doc = "acc_lim_theta"});
    v("rotation_tolerance", rotation_tolerance, {.unit = "rad", .range = core::kPositive, .doc = "yaw_goal_tolerance"});
    v("sweep_step", sweep_step, {.unit = "rad", .range = core::kPositive, .doc = "sim_granularity of the sweep check"});
  }
};
void validate(const MoveBaseRecoveryConfig& config, core::Errors& errors, const std::string& prefix);

/// True if the padded footprint (robot frame corners) at (x, y, yaw) touches a lethal or
/// unknown cell of `costmap` on its outline, or a corner is off the map: base_local_planner's
/// CostmapModel::footprintCost < 0, as rotate_recovery checks it.
bool footprintOutlineHits(const nav::Costmap& costmap, const std::vector<Eigen::Vector2d>& footprint, double x,
                          double y, double yaw);

/// What move_base is doing: CONTROLLING, PLANNING (waiting for a plan), a running
/// rotate_recovery, or the goal aborted.
enum class MoveBaseMode { Controlling, WaitingForPlan, RecoveryRotate, Aborted };

/// What started the current recoveries: move_base forgets them when that recovers (a valid
/// command for the controller, a plan for the planner).
enum class RecoveryTrigger { Controller, Planner };

/// Everything move_base remembers between control cycles.
struct MoveBaseState {
  MoveBaseMode mode = MoveBaseMode::Controlling;
  double last_valid_time = 0.0;  // [s] of the last cycle with a valid command
  int recovery_index = 0;        // next of move_base's four recoveries (4: none left)
  RecoveryTrigger recovery_trigger = RecoveryTrigger::Controller;
  double waiting_since = 0.0;    // [s] when PLANNING began
  double rotated = 0.0;          // [rad] turned so far in the current recovery rotation
  double last_yaw = 0.0;         // [rad] odom yaw at the previous rotation tick
};

/// What move_base knows at one point of a control cycle: at its start (command_found unset),
/// or after the local planner ran (command_found set).
struct MoveBaseInputs {
  double time = 0.0;        // [s]
  double yaw = 0.0;         // [rad] odom
  bool plan_found = false;  // the global planner's latest attempt found a path
  std::optional<bool> command_found;
  /// Whether the footprint can turn in place counter-clockwise by the given angle [rad] from
  /// `yaw` without touching an obstacle. Asked only when a recovery rotation ticks: the sweep
  /// check costs a few hundred footprint tests.
  std::function<bool(double)> turn_clear;
};

/// What the controller does this cycle.
enum class MoveBaseAction {
  RunLocalPlanner,  // (start of cycle) ask the local planner for a command
  PublishCommand,   // (after the local planner) publish the command it found
  Stop,             // publish zero
  Turn,             // publish a turn in place at turn_speed
};

/// The outcome of one transition: the next state and what to do.
struct MoveBaseStep {
  MoveBaseState state;
  MoveBaseAction action = MoveBaseAction::Stop;
  double turn_speed = 0.0;             // [rad/s] counter-clockwise, for Turn
  std::optional<double> clear_beyond;  // [m] clear the costmaps beyond this distance first
};

/// move_base's state machine as one function of its arguments (it asks inputs.turn_clear and
/// changes nothing): the state after one part of a control cycle and what to publish. Every
/// rule of this header's top comment lives here, so tests can drive each transition directly.
MoveBaseStep nextMoveBaseStep(const MoveBaseState& state, const MoveBaseInputs& inputs,
                              const MoveBaseRecoveryConfig& config);

/// move_base's state machine around a local planner (nextMoveBaseStep applied to a
/// NavStack). A controller calls, every cycle after updating its NavStack:
///   if (auto cmd = move_base.beforeController(obs, nav)) return *cmd;   // not CONTROLLING
///   ... run the local planner: a command, or none ...
///   return move_base.afterController(obs, nav, command);
class MoveBase {
 public:
  using Mode = MoveBaseMode;
  explicit MoveBase(const MoveBaseRecoveryConfig& config) : config_(config) {}

  void reset() { state_ = {}; }
  /// The part of the cycle before the local planner: a command to publish instead of running
  /// it (a recovery turning, waiting for a plan, aborted), or nothing when it is to run.
  std::optional<core::Twist> beforeController(const Observation& obs, nav::NavStack& nav);
  /// The local planner's result this cycle (none: it found no valid command) -> what move_base
  /// publishes.
  core::Twist afterController(const Observation& obs, nav::NavStack& nav, const std::optional<core::Twist>& command);
  /// move_base aborts the goal (e.g. the local planner refused the plan): zero from now on.
  void abort() { state_.mode = Mode::Aborted; }
  Mode mode() const { return state_.mode; }

 private:
  /// One transition with what `obs` and `nav` say (`command_found` unset before the local
  /// planner ran); carries out the step's costmap clearing and returns the step.
  MoveBaseStep advance(const Observation& obs, nav::NavStack& nav, std::optional<bool> command_found);
  bool sweepClear(const nav::NavStack& nav, const core::Pose2& pose, double sweep) const;

  MoveBaseRecoveryConfig config_;
  MoveBaseState state_;
};

}  // namespace barn::controllers
