#include "barn/bench/protocol_monitor.hpp"

#include <optional>

#include <gtest/gtest.h>

#include "barn/core/errors.hpp"

namespace barn::bench {
namespace {

// barn2023: start (-2, 3), goal (-2, 13), success radius 1 m, timer after 0.1 m, checks every
// 0.1 s. The tests step at dt = 0.05 s, so a check falls on every second step after the timer
// starts, and time after step k (1-based) is k x 0.05.
constexpr double kDt = 0.05;
const Eigen::Vector2d kStart(-2.0, 3.0);
const Eigen::Vector2d kInGoal(-2.0, 12.5);  // 0.5 m from the goal

// Steps the monitor once as physics step `k` (1-based) with the robot at `p`.
std::optional<Outcome> stepAt(ProtocolMonitor& monitor, int k, const Eigen::Vector2d& p, bool collided = false) {
  return monitor.afterPhysicsStep(k * kDt, p, collided);
}

TEST(ProtocolMonitor, TheTimerStartsAtTheStepThatFirstLeavesATenthOfAMetreAndSuccessWaitsForACheck) {
  ProtocolMonitor monitor(core::protocolPreset(core::ProtocolName::Barn2023), kDt);
  // Step 1: 0.06 m from the start, the timer waits; step 2: 0.12 m, it starts (after 2 steps).
  EXPECT_EQ(stepAt(monitor, 1, kStart + Eigen::Vector2d(0.0, 0.06)), std::nullopt);
  EXPECT_FALSE(monitor.timerStarted());
  EXPECT_EQ(stepAt(monitor, 2, kStart + Eigen::Vector2d(0.0, 0.12)), std::nullopt);
  EXPECT_TRUE(monitor.timerStarted());
  // Step 3 is 1 step (0.05 s) after the start: no check, so even inside the goal radius the
  // episode goes on. Step 4 is 2 steps = one check (0.1 s): success, AT = 0.1 s.
  EXPECT_EQ(stepAt(monitor, 3, kInGoal), std::nullopt);
  EXPECT_EQ(stepAt(monitor, 4, kInGoal), Outcome::Success);
  EXPECT_EQ(monitor.actualTime(), 0.1);
}

TEST(ProtocolMonitor, TheSuccessRadiusIsInclusiveAndMeasuredFromTheGoal) {
  ProtocolMonitor monitor(core::protocolPreset(core::ProtocolName::Barn2023), kDt);
  EXPECT_EQ(stepAt(monitor, 1, kStart + Eigen::Vector2d(0.0, 0.5)), std::nullopt);  // timer starts
  // 2 checks (steps 3 and 5) at 1.25 m and 1.01 m from the goal (-2, 13): not yet; the 3rd
  // (step 7) at exactly 1 m (-1, 13): success at 3 x 0.1 = 0.3 s.
  EXPECT_EQ(stepAt(monitor, 2, {-2.0, 11.75}), std::nullopt);
  EXPECT_EQ(stepAt(monitor, 3, {-2.0, 11.75}), std::nullopt);
  EXPECT_EQ(stepAt(monitor, 4, {-2.0, 11.99}), std::nullopt);
  EXPECT_EQ(stepAt(monitor, 5, {-2.0, 11.99}), std::nullopt);
  EXPECT_EQ(stepAt(monitor, 6, {-1.0, 13.0}), std::nullopt);
  EXPECT_EQ(stepAt(monitor, 7, {-1.0, 13.0}), Outcome::Success);
  EXPECT_EQ(monitor.actualTime(), 0.3);
}

TEST(ProtocolMonitor, ACollisionEndsTheEpisodeAtOnceTimedFromTheTimersStart) {
  // Timer started after step 2 (0.1 s); contact at step 5 (0.25 s), between checks:
  // AT = 0.25 - 2 x 0.05 = 0.15 s.
  ProtocolMonitor moving(core::protocolPreset(core::ProtocolName::Barn2023), kDt);
  EXPECT_EQ(stepAt(moving, 1, kStart), std::nullopt);
  EXPECT_EQ(stepAt(moving, 2, kStart + Eigen::Vector2d(0.2, 0.0)), std::nullopt);
  EXPECT_EQ(stepAt(moving, 3, kStart + Eigen::Vector2d(0.3, 0.0)), std::nullopt);
  EXPECT_EQ(stepAt(moving, 4, kStart + Eigen::Vector2d(0.4, 0.0)), std::nullopt);
  EXPECT_EQ(stepAt(moving, 5, kStart + Eigen::Vector2d(0.5, 0.0), true), Outcome::Collision);
  EXPECT_NEAR(moving.actualTime(), 0.15, 1e-12);
  // Contact before the robot left the start: AT 0, even inside the goal radius.
  ProtocolMonitor still(core::protocolPreset(core::ProtocolName::Barn2023), kDt);
  EXPECT_EQ(stepAt(still, 1, kStart, true), Outcome::Collision);
  EXPECT_EQ(still.actualTime(), 0.0);
}

TEST(ProtocolMonitor, ARobotThatNeverLeavesTheStartTimesOutAtTheTimeoutWithThatAsItsTime) {
  core::Protocol protocol = core::protocolPreset(core::ProtocolName::Barn2023);
  protocol.timeout = 1.0;
  ProtocolMonitor monitor(protocol, kDt);
  // 0.09 m from the start forever: steps 1-19 (to 0.95 s) go on, step 20 (1.0 s) times out.
  for (int k = 1; k < 20; ++k) ASSERT_EQ(stepAt(monitor, k, kStart + Eigen::Vector2d(0.09, 0.0)), std::nullopt) << k;
  EXPECT_EQ(stepAt(monitor, 20, kStart + Eigen::Vector2d(0.09, 0.0)), Outcome::Timeout);
  EXPECT_EQ(monitor.actualTime(), 1.0);
}

TEST(ProtocolMonitor, TheTimeoutCountsFromTheTimersStartAndBeatsASuccessAtTheSameCheck) {
  core::Protocol protocol = core::protocolPreset(core::ProtocolName::Barn2023);
  protocol.timeout = 1.0;
  ProtocolMonitor monitor(protocol, kDt);
  // The timer starts after step 2; the 10th check is 20 steps later, step 22: elapsed
  // 10 / 10 = 1.0 s >= the timeout, a timeout although the robot is in the goal radius. The
  // 9th (step 20, 0.9 s) still finds it outside.
  EXPECT_EQ(stepAt(monitor, 1, kStart), std::nullopt);
  for (int k = 2; k <= 21; ++k) ASSERT_EQ(stepAt(monitor, k, kStart + Eigen::Vector2d(0.0, 1.0)), std::nullopt) << k;
  EXPECT_EQ(stepAt(monitor, 22, kInGoal), Outcome::Timeout);
  EXPECT_EQ(monitor.actualTime(), 1.0);
}

TEST(ProtocolMonitor, ActualTimeIsWholeChecksDividedByTenNotMultipliedByATenth) {
  // 200 Hz physics: 20 steps a check. Timer after step 1; the 189th check is 189 x 20 = 3780
  // steps later: AT = 189 / 10 = 18.9 exactly (189 x 0.1 would be 18.900000000000002).
  constexpr double dt = 0.005;
  ProtocolMonitor monitor(core::protocolPreset(core::ProtocolName::Barn2023), dt);
  const Eigen::Vector2d away = kStart + Eigen::Vector2d(0.0, 1.0);
  ASSERT_EQ(monitor.afterPhysicsStep(dt, away, false), std::nullopt);
  for (int k = 2; k < 3781; ++k) ASSERT_EQ(monitor.afterPhysicsStep(k * dt, away, false), std::nullopt) << k;
  EXPECT_EQ(monitor.afterPhysicsStep(3781 * dt, kInGoal, false), Outcome::Success);
  EXPECT_EQ(monitor.actualTime(), 18.9);
  EXPECT_NE(189 * 0.1, 18.9);  // what the division avoids
}

TEST(ProtocolMonitor, RefusesAPhysicsStepThatDoesNotDivideTheCheckPeriod) {
  // 0.1 / 0.03 = 3.33 steps.
  EXPECT_THROW(ProtocolMonitor(core::protocolPreset(core::ProtocolName::Barn2023), 0.03), core::InputError);
  EXPECT_EQ(wholeStepsIn(0.1, 0.005), 20);
  EXPECT_EQ(wholeStepsIn(0.1, 0.03), std::nullopt);
}

}  // namespace
}  // namespace barn::bench
