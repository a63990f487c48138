// A researcher's controller built the way docs/controllers.md describes, against
// barn::controller_api alone: this target links no barn::sim (so no Box2D), and the
// controllers_controller_api_closure test checks that controller.hpp pulls in core headers only.
#include "barn/controllers/controller.hpp"

#include <algorithm>
#include <cmath>
#include <limits>
#include <numbers>

#include <gtest/gtest.h>

#include "scan_fixtures.hpp"

namespace {

using barn::controllers::Controller;
using barn::controllers::EpisodeInfo;
using barn::controllers::Observation;
using barn::controllers::uniformScan;

/// Turns toward the goal and drives at it, stopping short of anything the scan sees ahead
/// within `stop_distance` of the sensor. Uses the robot's limits and the LiDAR's geometry from
/// EpisodeInfo, as an out-of-tree controller would.
class CautiousStraight : public Controller {
 public:
  void reset(const EpisodeInfo& info) override { info_ = info; }

  barn::core::Twist act(const Observation& obs) override {
    const Eigen::Vector2d to_goal = obs.goal - obs.odom_pose.position();
    const double error = barn::core::wrapAngle(std::atan2(to_goal.y(), to_goal.x()) - obs.odom_pose.yaw);
    barn::core::Twist cmd;
    cmd.angular = std::clamp(2.0 * error, -info_.robot.max_angular_speed, info_.robot.max_angular_speed);
    cmd.linear = nearestAhead(*obs.scan) < kStopDistance ? 0.0 : info_.robot.max_linear_speed * std::max(0.0, std::cos(error));
    return cmd;
  }

  double period() const override { return 1.0 / 20.0; }

 private:
  static constexpr double kStopDistance = 0.5;  // [m] from the sensor

  // Closest return within +-0.3 rad of straight ahead. [m]
  static double nearestAhead(const barn::core::LaserScan& scan) {
    double nearest = std::numeric_limits<double>::infinity();
    for (std::size_t i = 0; i < scan.ranges.size(); ++i)
      if (std::abs(scan.angle(i)) < 0.3) nearest = std::min(nearest, scan.ranges[i]);
    return nearest;
  }

  EpisodeInfo info_;
};

TEST(ControllerApi, ControllerDrivesAtTheGoalWithinTheRobotsLimits) {
  EpisodeInfo info;
  info.goal = {5.0, 0.0};
  CautiousStraight controller;
  controller.reset(info);
  const barn::core::LaserScan scan = uniformScan(info.lidar, std::numeric_limits<double>::infinity());
  Observation obs;
  obs.scan = &scan;
  obs.goal = info.goal;
  // Facing the goal: full Jackal speed (2.0 m/s), no turn.
  const barn::core::Twist cmd = controller.act(obs);
  EXPECT_DOUBLE_EQ(cmd.linear, 2.0);
  EXPECT_DOUBLE_EQ(cmd.angular, 0.0);
}

TEST(ControllerApi, ControllerStopsForAnObstacleAheadAndTurnsWithinLimits) {
  EpisodeInfo info;
  info.goal = {0.0, 5.0};
  info.robot.max_angular_speed = 1.0;
  CautiousStraight controller;
  controller.reset(info);
  const barn::core::LaserScan scan = uniformScan(info.lidar, 0.3);
  Observation obs;
  obs.scan = &scan;
  obs.goal = info.goal;
  // Goal 90 degrees left: 2.0 * pi/2 = 3.14 rad/s, clamped to the 1.0 rad/s limit; 0.3 m < 0.5 m stops.
  const barn::core::Twist cmd = controller.act(obs);
  EXPECT_DOUBLE_EQ(cmd.linear, 0.0);
  EXPECT_DOUBLE_EQ(cmd.angular, 1.0);
}

// The descriptions' helpers are defined in barn::core's library, so this target links them
// without barn::sim.
TEST(ControllerApi, EpisodeInfoDescriptionsWorkWithoutTheSimulator) {
  const EpisodeInfo info;
  barn::core::Errors errors;
  validate(info.lidar, errors);
  validate(info.robot, errors);
  EXPECT_TRUE(errors.empty());
  // Mount 0.055 m ahead; robot at (1, 2) facing +y puts the sensor at (1, 2.055).
  const barn::core::Pose2 sensor = info.lidar.sensorPose({1.0, 2.0, std::numbers::pi / 2});
  EXPECT_NEAR(sensor.x, 1.0, 1e-12);
  EXPECT_NEAR(sensor.y, 2.055, 1e-12);
  // Farthest corner: wheel at (0.131 + 0.098, 0.187795 + 0.020) -> hypot(0.229, 0.207795).
  EXPECT_NEAR(info.robot.collisionRadius(), std::hypot(0.229, 0.207795), 1e-12);
}

}  // namespace
