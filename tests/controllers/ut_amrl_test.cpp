// UT AMRL's 2023 entry as one controller: the local goal, graph_navigation's carrot, and the
// controller's ticks in the open.
#include "barn/controllers/ut_amrl.hpp"

#include <cmath>
#include <limits>
#include <numbers>
#include <vector>

#include <gtest/gtest.h>

#include "scan_fixtures.hpp"

namespace barn::controllers {
namespace {

constexpr double kInf = std::numeric_limits<double>::infinity();
using V = Eigen::Vector2d;

TEST(UtAmrlLocalGoal, ShiftsThePathToTheRobotThenTakesTheFirstPoseBeyondThirtyCentimetres) {
  // The path starts at (0, 0); the robot is at (0.1, 0.1) now, so the path moves by (0.1, 0.1):
  // its poses are 0, 0.2 and 0.5 m from the robot. The first beyond 0.3: (0.6, 0.1).
  const std::vector<V> path = {{0, 0}, {0.2, 0}, {0.5, 0}, {1.0, 0}};
  const auto goal = shiftedLocalGoal(path, {0.1, 0.1}, 0.3);
  ASSERT_TRUE(goal.has_value());
  EXPECT_NEAR((*goal - V(0.6, 0.1)).norm(), 0.0, 1e-12);
  // All within 0.3: none.
  EXPECT_FALSE(shiftedLocalGoal(std::vector<V>{{0, 0}, {0.2, 0}}, {5, 5}, 0.3).has_value());
}

TEST(UtAmrlCarrot, IsTheGoalWithinCarrotDistElseWhereTheCircleCrossesThePlan) {
  // Goal 2 m away: the goal itself.
  EXPECT_EQ(*carrotOnPlan({0, 0}, {2, 0}, {0, 0}, 3.0), V(2, 0));
  // Goal 5 m away along +x, robot at the plan's start: 3 m along.
  EXPECT_NEAR((*carrotOnPlan({0, 0}, {5, 0}, {0, 0}, 3.0) - V(3, 0)).norm(), 0.0, 1e-12);
  // Robot 0.4 off the plan at x = 1: the crossing nearer the goal, 1 + sqrt(9 - 0.16) = 3.973.
  EXPECT_NEAR((*carrotOnPlan({0, 0}, {5, 0}, {1, 0.4}, 3.0) - V(1.0 + std::sqrt(8.84), 0)).norm(), 0.0, 1e-12);
  // The circle misses the plan altogether: no carrot.
  EXPECT_FALSE(carrotOnPlan({0, 0}, {5, 0}, {1, 4}, 3.0).has_value());
}

/// An episode in the open: the robot at the origin facing +y, the goal 10 m ahead.
EpisodeInfo openEpisode() {
  EpisodeInfo info;
  info.start = {0.0, 0.0, std::numbers::pi / 2.0};
  info.goal = {0.0, 10.0};
  return info;
}

Observation observe(const core::LaserScan& scan, const core::Pose2& pose, double time) {
  Observation obs;
  obs.time = time;
  obs.scan = &scan;
  obs.odom_pose = pose;
  obs.scan_odom_pose = pose;
  obs.goal = {0.0, 10.0};
  return obs;
}

TEST(UtAmrlController, InTheOpenItSetsOffOnAnArcAtTheTeamsAcceleration) {
  // Nothing seen: the path runs through (-1, 5) (voronoi_planner_test), the local goal. It is
  // 11 degrees off the heading, inside local_fov: an arc, from rest one acceleration step,
  // 0.5 m/s^2 x 0.025 s = 0.0125 m/s.
  UtAmrlController controller{UtAmrlConfig{}};
  controller.reset(openEpisode());
  const core::LaserScan scan = uniformScan(core::LidarConfig{}, kInf);
  const core::Twist first = controller.act(observe(scan, {0.0, 0.0, std::numbers::pi / 2.0}, 0.0));
  ASSERT_TRUE(controller.localGoal().has_value());
  EXPECT_NEAR((*controller.localGoal() - V(-1, 5)).norm(), 0.0, 1e-6);
  EXPECT_EQ(controller.stateLabel(), "Arcs");
  EXPECT_DOUBLE_EQ(first.linear, 0.0125);
  EXPECT_GT(first.angular, 0.0);  // toward the local goal, on the left
  // The next tick accelerates one more step.
  const core::Twist second = controller.act(observe(scan, {0.0, 0.0, std::numbers::pi / 2.0}, 0.025));
  EXPECT_DOUBLE_EQ(second.linear, 0.025);
}

TEST(UtAmrlController, ACarrotBeyondThirtyDegreesTurnsItInPlace) {
  // After the first tick the robot is found facing +x: the local goal (-1, 5) is 101 degrees
  // to its left (the carrot 3 m toward it, (-0.59, 2.94)). Its last command (0.0125 m/s) is
  // below 0.1, so it turns at once, standing, one angular step (5 rad/s^2 x 0.025 s = 0.125
  // rad/s) above the yaw rate it last commanded.
  UtAmrlController controller{UtAmrlConfig{}};
  controller.reset(openEpisode());
  const core::LaserScan scan = uniformScan(core::LidarConfig{}, kInf);
  const core::Twist first = controller.act(observe(scan, {0.0, 0.0, std::numbers::pi / 2.0}, 0.0));
  const core::Twist turn = controller.act(observe(scan, {0.0, 0.0, 0.0}, 0.025));
  EXPECT_EQ(controller.stateLabel(), "TurnInPlace");
  EXPECT_EQ(turn.linear, 0.0);
  EXPECT_DOUBLE_EQ(turn.angular, first.angular + 0.125);  // the last yaw rate, one step up
}

TEST(UtAmrlController, ResetForgetsTheEpisode) {
  UtAmrlController controller{UtAmrlConfig{}};
  controller.reset(openEpisode());
  const core::LaserScan wall = wallScan(core::LidarConfig{}, 2.0);
  controller.act(observe(wall, {0.0, 0.0, 0.0}, 0.0));
  EXPECT_FALSE(controller.globalPlanner().memory().empty());
  controller.reset(openEpisode());
  EXPECT_TRUE(controller.globalPlanner().memory().empty());
  EXPECT_FALSE(controller.localGoal().has_value());
  EXPECT_EQ(controller.stateLabel(), "Idle");
}

TEST(UtAmrlConfig, RejectsAPlanPeriodThatIsNoWholeNumberOfTicks) {
  UtAmrlConfig c;
  c.plan_period = 0.11;  // 4.4 ticks of 0.025 s
  core::Errors errors;
  validate(c, errors, "ut_amrl");
  ASSERT_EQ(errors.messages().size(), 1u);
  EXPECT_NE(errors.messages()[0].find("ut_amrl.plan_period"), std::string::npos);
  core::Errors fine;
  validate(UtAmrlConfig{}, fine, "ut_amrl");
  EXPECT_TRUE(fine.empty());
}

}  // namespace
}  // namespace barn::controllers
