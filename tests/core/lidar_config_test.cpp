#include "barn/core/lidar_config.hpp"

#include <gmock/gmock.h>
#include <gtest/gtest.h>

#include <numbers>

namespace barn::core {
namespace {

using ::testing::Contains;
using ::testing::HasSubstr;
using ::testing::IsEmpty;

TEST(LidarConfig, DefaultsAreTheUst10Layout) {
  const LidarConfig lidar;
  Errors errors;
  validate(lidar, errors);
  EXPECT_THAT(errors.messages(), IsEmpty());
  // 270 degrees over 720 beams: 2 * 2.35619 / 719 rad between beams.
  EXPECT_DOUBLE_EQ(lidar.angleIncrement(), 2 * 2.35619 / 719);
}

TEST(LidarConfig, SensorPoseIsTheMountOffsetTurnedWithTheRobot) {
  LidarConfig lidar;
  lidar.mount_x = 0.1;
  lidar.mount_y = 0.2;
  // Robot at (1, 2) facing +y: forward 0.1 is +y, left 0.2 is -x -> (0.8, 2.1), same yaw.
  const Pose2 sensor = lidar.sensorPose({1.0, 2.0, std::numbers::pi / 2});
  EXPECT_NEAR(sensor.x, 0.8, 1e-12);
  EXPECT_NEAR(sensor.y, 2.1, 1e-12);
  EXPECT_DOUBLE_EQ(sensor.yaw, std::numbers::pi / 2);
}

TEST(LidarConfig, ValidateNamesEveryBadFieldUnderItsPrefix) {
  LidarConfig lidar;
  lidar.beams = 1;
  lidar.range_max = 0.05;  // below range_min 0.1
  Errors errors;
  validate(lidar, errors, "sim.lidar");
  EXPECT_THAT(errors.messages(), Contains(HasSubstr("sim.lidar.beams")));
  EXPECT_THAT(errors.messages(), Contains(HasSubstr("sim.lidar.range_max")));
  EXPECT_EQ(errors.messages().size(), 2u);
}

}  // namespace
}  // namespace barn::core
