#include "barn/controllers/move_base.hpp"

#include <cmath>
#include <numbers>
#include <vector>

#include <gtest/gtest.h>

namespace barn::controllers {
namespace {

constexpr double kFullTurn = 2.0 * std::numbers::pi;

// Inputs at the start of a cycle (the local planner has not run), with a free sweep.
MoveBaseInputs startOfCycle(double time, bool plan_found, double yaw = 0.0) {
  MoveBaseInputs in;
  in.time = time;
  in.yaw = yaw;
  in.plan_found = plan_found;
  in.turn_clear = [](double) { return true; };
  return in;
}

// Inputs after the local planner ran and found a command or not.
MoveBaseInputs afterPlanner(double time, bool command_found) {
  MoveBaseInputs in = startOfCycle(time, true);
  in.command_found = command_found;
  return in;
}

MoveBaseState waitingSince(double time, int recovery_index = 0) {
  MoveBaseState s;
  s.mode = MoveBaseMode::WaitingForPlan;
  s.waiting_since = time;
  s.recovery_index = recovery_index;
  return s;
}

MoveBaseState rotating(double rotated, double last_yaw) {
  MoveBaseState s;
  s.mode = MoveBaseMode::RecoveryRotate;
  s.recovery_index = 2;
  s.rotated = rotated;
  s.last_yaw = last_yaw;
  return s;
}

TEST(MoveBaseTransition, RunsTheLocalPlannerWhileControlling) {
  const MoveBaseStep step = nextMoveBaseStep({}, startOfCycle(1.0, true), {});
  EXPECT_EQ(step.action, MoveBaseAction::RunLocalPlanner);
  EXPECT_EQ(step.state.mode, MoveBaseMode::Controlling);
}

TEST(MoveBaseTransition, PublishesAValidCommandAndForgetsTheControllersRecoveries) {
  MoveBaseState s;
  s.recovery_index = 3;
  s.recovery_trigger = RecoveryTrigger::Controller;
  const MoveBaseStep step = nextMoveBaseStep(s, afterPlanner(7.5, true), {});
  EXPECT_EQ(step.action, MoveBaseAction::PublishCommand);
  EXPECT_EQ(step.state.last_valid_time, 7.5);
  EXPECT_EQ(step.state.recovery_index, 0);
}

TEST(MoveBaseTransition, AValidCommandKeepsRecoveriesThePlannerStarted) {
  MoveBaseState s;
  s.recovery_index = 3;
  s.recovery_trigger = RecoveryTrigger::Planner;
  EXPECT_EQ(nextMoveBaseStep(s, afterPlanner(7.5, true), {}).state.recovery_index, 3);
}

TEST(MoveBaseTransition, AFailedCycleStopsAndWaitsForAPlanBeforeControllerPatience) {
  MoveBaseState s;
  s.last_valid_time = 10.0;
  // 24.9 s - 10 s = 14.9 s < controller_patience 15 s: no recovery yet.
  const MoveBaseStep step = nextMoveBaseStep(s, afterPlanner(24.9, false), {});
  EXPECT_EQ(step.action, MoveBaseAction::Stop);
  EXPECT_EQ(step.state.mode, MoveBaseMode::WaitingForPlan);
  EXPECT_EQ(step.state.waiting_since, 24.9);
  EXPECT_EQ(step.state.recovery_index, 0);
}

TEST(MoveBaseTransition, ControllerPatienceExpiryStartsTheFirstRecovery) {
  MoveBaseState s;
  s.last_valid_time = 10.0;
  // 25 s - 10 s = 15 s >= controller_patience: the first recovery (a conservative clearing).
  MoveBaseRecoveryConfig config;
  config.clear_costmaps = true;
  const MoveBaseStep step = nextMoveBaseStep(s, afterPlanner(25.0, false), config);
  EXPECT_EQ(step.action, MoveBaseAction::Stop);
  EXPECT_EQ(step.state.recovery_trigger, RecoveryTrigger::Controller);
  EXPECT_EQ(step.state.recovery_index, 1);
  EXPECT_EQ(step.state.mode, MoveBaseMode::WaitingForPlan);
  EXPECT_EQ(step.state.waiting_since, 25.0);
  ASSERT_TRUE(step.clear_beyond.has_value());
  EXPECT_EQ(*step.clear_beyond, config.conservative_reset_distance);
}

TEST(MoveBaseTransition, ClearingRecoveriesClearNothingAsBarnConfiguresThem) {
  MoveBaseState s;
  const MoveBaseStep step = nextMoveBaseStep(s, afterPlanner(15.0, false), {});  // clear_costmaps off
  EXPECT_EQ(step.state.recovery_index, 1);
  EXPECT_FALSE(step.clear_beyond.has_value());
}

TEST(MoveBaseTransition, WaitsForAPlanUntilPlannerPatienceExpires) {
  // 6 s - 1 s = 5 s, not more than planner_patience 5 s: keep waiting, no recovery.
  const MoveBaseStep step = nextMoveBaseStep(waitingSince(1.0), startOfCycle(6.0, false), {});
  EXPECT_EQ(step.action, MoveBaseAction::Stop);
  EXPECT_EQ(step.state.mode, MoveBaseMode::WaitingForPlan);
  EXPECT_EQ(step.state.waiting_since, 1.0);
  EXPECT_EQ(step.state.recovery_index, 0);
}

TEST(MoveBaseTransition, PlannerPatienceExpiryStartsARecovery) {
  const MoveBaseStep step = nextMoveBaseStep(waitingSince(1.0), startOfCycle(6.05, false), {});
  EXPECT_EQ(step.state.recovery_trigger, RecoveryTrigger::Planner);
  EXPECT_EQ(step.state.recovery_index, 1);
  EXPECT_EQ(step.state.waiting_since, 6.05);  // the clearing restarts the wait
}

TEST(MoveBaseTransition, APlanEndsTheWaitAndTheRecoveriesThePlannerStarted) {
  MoveBaseState s = waitingSince(1.0, 2);
  s.recovery_trigger = RecoveryTrigger::Planner;
  const MoveBaseStep step = nextMoveBaseStep(s, startOfCycle(2.0, true), {});
  EXPECT_EQ(step.action, MoveBaseAction::RunLocalPlanner);
  EXPECT_EQ(step.state.mode, MoveBaseMode::Controlling);
  EXPECT_EQ(step.state.recovery_index, 0);
}

TEST(MoveBaseTransition, DisabledRecoveriesOnlyWait) {
  MoveBaseRecoveryConfig config;
  config.enabled = false;
  EXPECT_EQ(nextMoveBaseStep(waitingSince(0.0), startOfCycle(100.0, false), config).state.recovery_index, 0);
  EXPECT_EQ(nextMoveBaseStep({}, afterPlanner(100.0, false), config).state.mode, MoveBaseMode::WaitingForPlan);
}

TEST(MoveBaseTransition, SecondRecoveryTurnsAtOnceAtTheCappedSpeed) {
  std::vector<double> asked;
  MoveBaseInputs in = startOfCycle(10.0, false, 0.4);
  in.turn_clear = [&](double sweep) {
    asked.push_back(sweep);
    return true;
  };
  const MoveBaseStep step = nextMoveBaseStep(waitingSince(0.0, 1), in, {});
  EXPECT_EQ(step.action, MoveBaseAction::Turn);
  EXPECT_EQ(step.state.mode, MoveBaseMode::RecoveryRotate);
  EXPECT_EQ(step.state.recovery_index, 2);
  EXPECT_EQ(step.state.last_yaw, 0.4);
  ASSERT_EQ(asked.size(), 1u);
  EXPECT_DOUBLE_EQ(asked.front(), kFullTurn);  // the whole turn is checked first
  // sqrt(2 * 20 rad/s^2 * 2 pi) = 15.9 rad/s, capped at max_rotation_speed 1.57.
  EXPECT_DOUBLE_EQ(step.turn_speed, 1.57);
}

TEST(MoveBaseTransition, RotationSlowsDownAsTheTurnEnds) {
  MoveBaseRecoveryConfig config;
  config.rotation_acceleration = 1.0;
  // Turned 6.0 rad, then 0.03 rad more: remaining 2 pi - 6.03 = 0.253 rad > tolerance 0.157.
  const MoveBaseStep step = nextMoveBaseStep(rotating(6.0, 0.1), startOfCycle(3.0, false, 0.13), config);
  EXPECT_EQ(step.action, MoveBaseAction::Turn);
  EXPECT_NEAR(step.state.rotated, 6.03, 1e-12);
  // sqrt(2 * 1 rad/s^2 * 0.253 rad) = 0.711 rad/s, within [0.314, 1.57].
  EXPECT_NEAR(step.turn_speed, std::sqrt(2.0 * (kFullTurn - 6.03)), 1e-12);
}

TEST(MoveBaseTransition, RotationCountsTurnsAcrossTheAngleWrap) {
  // From 3.1 rad to -3.1 rad is 2 pi - 6.2 = 0.083 rad turned, not 6.2.
  const MoveBaseStep step = nextMoveBaseStep(rotating(1.0, 3.1), startOfCycle(3.0, false, -3.1), {});
  EXPECT_NEAR(step.state.rotated, 1.0 + kFullTurn - 6.2, 1e-9);
}

TEST(MoveBaseTransition, RotationWithinToleranceEndsInPlanning) {
  // remaining 2 pi - 6.2 = 0.083 rad <= rotation_tolerance 0.157: the turn is done.
  const MoveBaseStep step = nextMoveBaseStep(rotating(6.2, 0.0), startOfCycle(4.0, false), {});
  EXPECT_EQ(step.action, MoveBaseAction::Stop);
  EXPECT_EQ(step.state.mode, MoveBaseMode::WaitingForPlan);
  EXPECT_EQ(step.state.waiting_since, 4.0);
}

TEST(MoveBaseTransition, BlockedRotationEndsAtOnceAndAPlanResumesControlling) {
  MoveBaseInputs in = startOfCycle(4.0, true);
  in.turn_clear = [](double) { return false; };
  const MoveBaseStep step = nextMoveBaseStep(rotating(1.0, 0.0), in, {});
  // The rotation ends, PLANNING finds this cycle's plan, and the local planner runs.
  EXPECT_EQ(step.action, MoveBaseAction::RunLocalPlanner);
  EXPECT_EQ(step.state.mode, MoveBaseMode::Controlling);
}

TEST(MoveBaseTransition, ThirdRecoveryClearsAggressively) {
  MoveBaseRecoveryConfig config;
  config.clear_costmaps = true;
  const MoveBaseStep step = nextMoveBaseStep(waitingSince(0.0, 2), startOfCycle(10.0, false), config);
  EXPECT_EQ(step.state.recovery_index, 3);
  ASSERT_TRUE(step.clear_beyond.has_value());
  EXPECT_EQ(*step.clear_beyond, config.aggressive_reset_distance);
}

TEST(MoveBaseTransition, AbortsAfterTheFourthRecoveryAndStaysAborted) {
  MoveBaseState s;
  s.recovery_index = 4;
  const MoveBaseStep aborted = nextMoveBaseStep(s, afterPlanner(20.0, false), {});
  EXPECT_EQ(aborted.action, MoveBaseAction::Stop);
  EXPECT_EQ(aborted.state.mode, MoveBaseMode::Aborted);
  // A plan afterwards changes nothing: BARN never re-sends the goal.
  const MoveBaseStep later = nextMoveBaseStep(aborted.state, startOfCycle(21.0, true), {});
  EXPECT_EQ(later.action, MoveBaseAction::Stop);
  EXPECT_EQ(later.state.mode, MoveBaseMode::Aborted);
}

}  // namespace
}  // namespace barn::controllers
