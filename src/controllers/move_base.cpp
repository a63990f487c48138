#include "barn/controllers/move_base.hpp"

#include <algorithm>
#include <cmath>
#include <numbers>

#include "barn/nav/grid_line.hpp"

namespace barn::controllers {

void validate(const MoveBaseRecoveryConfig& r, core::Errors& errors, const std::string& prefix) {
  core::validateFields(r, errors, prefix);
  errors.check(r.min_rotation_speed > 0.0 && r.min_rotation_speed <= r.max_rotation_speed,
               prefix + ".min_rotation_speed", "must be in (0, max_rotation_speed]");
}

bool footprintOutlineHits(const nav::Costmap& map, const std::vector<Eigen::Vector2d>& footprint, double x, double y,
                          double yaw) {
  const double c = std::cos(yaw), s = std::sin(yaw);
  std::vector<nav::CellIndex> corners(footprint.size());
  for (std::size_t k = 0; k < footprint.size(); ++k) {
    const Eigen::Vector2d& p = footprint[k];
    if (!map.toCell(x + c * p.x() - s * p.y(), y + s * p.x() + c * p.y(), corners[k])) return true;
  }
  // Only the outline is walked; lethal and unknown are the two highest costs.
  for (std::size_t k = 0; k < corners.size(); ++k) {
    const nav::CellIndex a = corners[k], b = corners[(k + 1) % corners.size()];
    const bool clear = nav::walkLine(a.x, a.y, b.x, b.y, [&](int cx, int cy) { return map.cost(cx, cy) < nav::kLethalCost; });
    if (!clear) return true;
  }
  return false;
}

// ---------------------------------------------------------------------------------------------
// The transition function
// ---------------------------------------------------------------------------------------------

namespace {

using Mode = MoveBaseMode;

// move_base's four recoveries: clear (conservative), rotate, clear (aggressive), rotate.
constexpr int kRecoveryCount = 4;

MoveBaseStep doing(MoveBaseAction action, const MoveBaseState& state) { return {state, action, 0.0, std::nullopt}; }

// move_base enters PLANNING: stop until the global planner finds a path.
MoveBaseState waitingForPlan(MoveBaseState state, double time) {
  state.mode = Mode::WaitingForPlan;
  state.waiting_since = time;
  return state;
}

// One tick of rotate_recovery: it keeps turning while the rest of the full turn is more than
// the tolerance and sweeps free; then (done, or it would hit) move_base plans again.
MoveBaseStep rotationTick(MoveBaseState state, const MoveBaseInputs& in, const MoveBaseRecoveryConfig& r) {
  state.rotated += std::abs(core::wrapAngle(in.yaw - state.last_yaw));
  state.last_yaw = in.yaw;
  const double remaining = 2.0 * std::numbers::pi - state.rotated;
  if (remaining > r.rotation_tolerance && in.turn_clear(remaining)) {
    MoveBaseStep turn = doing(MoveBaseAction::Turn, state);
    turn.turn_speed =
        std::clamp(std::sqrt(2.0 * r.rotation_acceleration * remaining), r.min_rotation_speed, r.max_rotation_speed);
    return turn;
  }
  return doing(MoveBaseAction::Stop, waitingForPlan(state, in.time));
}

// move_base runs its recoveries in order, each after a failing cycle, until one lets the
// controller find a command again; after the last it aborts the goal.
MoveBaseStep startNextRecovery(MoveBaseState state, const MoveBaseInputs& in, const MoveBaseRecoveryConfig& r) {
  if (state.recovery_index >= kRecoveryCount) {
    state.mode = Mode::Aborted;
    return doing(MoveBaseAction::Stop, state);
  }
  const int recovery = state.recovery_index++;
  if (recovery % 2 == 0) {
    MoveBaseStep clearing = doing(MoveBaseAction::Stop, waitingForPlan(state, in.time));
    if (r.clear_costmaps) clearing.clear_beyond = recovery == 0 ? r.conservative_reset_distance : r.aggressive_reset_distance;
    return clearing;
  }
  state.mode = Mode::RecoveryRotate;
  state.rotated = 0.0;
  state.last_yaw = in.yaw;
  return rotationTick(state, in, r);  // the rotation turns from its first cycle
}

// The start of a cycle: a running rotation turns on; PLANNING waits for a plan (recovering
// after planner_patience); otherwise the local planner runs.
MoveBaseStep beforeLocalPlanner(MoveBaseState state, const MoveBaseInputs& in, const MoveBaseRecoveryConfig& r) {
  if (state.mode == Mode::Aborted) return doing(MoveBaseAction::Stop, state);
  if (state.mode == Mode::RecoveryRotate) {
    const MoveBaseStep rotation = rotationTick(state, in, r);
    if (rotation.state.mode == Mode::RecoveryRotate) return rotation;
    state = rotation.state;  // the turn is over: PLANNING, this same cycle
  }
  if (state.mode == Mode::WaitingForPlan) {
    // The plan of this cycle stands for the one move_base's planner thread makes between two
    // control cycles once woken.
    if (!in.plan_found) {
      if (r.enabled && in.time - state.waiting_since > r.planner_patience) {
        state.recovery_trigger = RecoveryTrigger::Planner;
        return startNextRecovery(state, in, r);
      }
      return doing(MoveBaseAction::Stop, state);
    }
    state.mode = Mode::Controlling;
  }
  // A new plan handed to the controller ends recoveries the planner started.
  if (state.recovery_trigger == RecoveryTrigger::Planner && in.plan_found) state.recovery_index = 0;
  return doing(MoveBaseAction::RunLocalPlanner, state);
}

// After the local planner: its command is published; a failed cycle publishes zero and waits
// for the planner, or after controller_patience starts the next recovery.
MoveBaseStep afterLocalPlanner(MoveBaseState state, const MoveBaseInputs& in, const MoveBaseRecoveryConfig& r) {
  if (*in.command_found) {
    state.last_valid_time = in.time;
    if (state.recovery_trigger == RecoveryTrigger::Controller) state.recovery_index = 0;
    return doing(MoveBaseAction::PublishCommand, state);
  }
  if (r.enabled && in.time - state.last_valid_time >= r.controller_patience) {
    state.recovery_trigger = RecoveryTrigger::Controller;
    return startNextRecovery(state, in, r);
  }
  return doing(MoveBaseAction::Stop, waitingForPlan(state, in.time));
}

}  // namespace

MoveBaseStep nextMoveBaseStep(const MoveBaseState& state, const MoveBaseInputs& inputs,
                              const MoveBaseRecoveryConfig& config) {
  return inputs.command_found ? afterLocalPlanner(state, inputs, config) : beforeLocalPlanner(state, inputs, config);
}

// ---------------------------------------------------------------------------------------------
// MoveBase: the transition applied to a NavStack
// ---------------------------------------------------------------------------------------------

bool MoveBase::sweepClear(const nav::NavStack& nav, const core::Pose2& pose, double sweep) const {
  const nav::Costmap& map = nav.localCostmap();
  const std::vector<Eigen::Vector2d> footprint = nav.paddedFootprint();
  for (double turned = 0.0; turned <= sweep; turned += config_.sweep_step)
    if (footprintOutlineHits(map, footprint, pose.x, pose.y, pose.yaw + turned)) return false;
  return true;
}

MoveBaseStep MoveBase::advance(const Observation& obs, nav::NavStack& nav, std::optional<bool> command_found) {
  MoveBaseInputs in;
  in.time = obs.time;
  in.yaw = obs.odom_pose.yaw;
  in.plan_found = nav.lastPlanFound();
  in.command_found = command_found;
  in.turn_clear = [this, &nav, &obs](double sweep) { return sweepClear(nav, obs.odom_pose, sweep); };
  const MoveBaseStep step = nextMoveBaseStep(state_, in, config_);
  state_ = step.state;
  if (step.clear_beyond) nav.clearCostmapsOutside(obs.odom_pose.position(), *step.clear_beyond);
  return step;
}

namespace {

// What move_base publishes for a step that is not the local planner's command.
core::Twist ownCommand(const MoveBaseStep& step) {
  return step.action == MoveBaseAction::Turn ? core::Twist{0.0, step.turn_speed} : core::Twist{};
}

}  // namespace

std::optional<core::Twist> MoveBase::beforeController(const Observation& obs, nav::NavStack& nav) {
  const MoveBaseStep step = advance(obs, nav, std::nullopt);
  if (step.action == MoveBaseAction::RunLocalPlanner) return std::nullopt;
  return ownCommand(step);
}

core::Twist MoveBase::afterController(const Observation& obs, nav::NavStack& nav,
                                      const std::optional<core::Twist>& command) {
  const MoveBaseStep step = advance(obs, nav, command.has_value());
  return step.action == MoveBaseAction::PublishCommand ? *command : ownCommand(step);
}

}  // namespace barn::controllers
