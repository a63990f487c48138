#include "barn/core/robot_config.hpp"

#include <gmock/gmock.h>
#include <gtest/gtest.h>

#include <cmath>

namespace barn::core {
namespace {

using ::testing::Contains;
using ::testing::HasSubstr;
using ::testing::IsEmpty;

TEST(RobotConfig, CollisionShapeIsTheChassisAndFourWheels) {
  const RobotConfig robot;
  const std::vector<Rect> rects = robot.collisionRects();
  ASSERT_EQ(rects.size(), 5u);
  // Chassis 0.420 x 0.310 at the centre.
  EXPECT_DOUBLE_EQ(rects[0].min_x, -0.21);
  EXPECT_DOUBLE_EQ(rects[0].max_x, 0.21);
  EXPECT_DOUBLE_EQ(rects[0].min_y, -0.155);
  EXPECT_DOUBLE_EQ(rects[0].max_y, 0.155);
  // Front-left wheel at (0.131, 0.187795), 0.196 x 0.040.
  EXPECT_DOUBLE_EQ(rects[1].centreX(), 0.131);
  EXPECT_DOUBLE_EQ(rects[1].centreY(), 0.187795);
  EXPECT_DOUBLE_EQ(rects[1].halfLength(), 0.098);
  EXPECT_DOUBLE_EQ(rects[1].halfWidth(), 0.02);
  // The wheels' outer corners are farthest: hypot(0.131 + 0.098, 0.187795 + 0.02).
  EXPECT_DOUBLE_EQ(robot.collisionRadius(), std::hypot(0.131 + 0.098, 0.187795 + 0.02));
}

TEST(RobotConfig, ValidateNamesEveryBadFieldUnderItsPrefix) {
  RobotConfig robot;
  Errors errors;
  validate(robot, errors);
  EXPECT_THAT(errors.messages(), IsEmpty());
  robot.max_linear_speed = 0.0;
  robot.turn_slip_speed = 2.0;
  validate(robot, errors, "sim.robot");
  EXPECT_THAT(errors.messages(), Contains(HasSubstr("sim.robot.max_linear_speed: must be in (0, 20] m/s, got 0 m/s")));
  EXPECT_THAT(errors.messages(), Contains(HasSubstr("sim.robot.turn_slip_speed: must be in [0, 1]")));
  EXPECT_EQ(errors.messages().size(), 2u);
}

TEST(Rect, FarthestCornerDistanceIsFromTheOriginWhereverTheRectangleLies) {
  EXPECT_NEAR(Rect::centred(0.6, 0.8).farthestCornerDistance(), 0.5, 1e-15);
  // Entirely behind and to the right of the origin: the corner (-0.4, -0.3).
  EXPECT_NEAR((Rect{-0.4, -0.1, -0.3, -0.2}).farthestCornerDistance(), 0.5, 1e-15);
}

}  // namespace
}  // namespace barn::core
