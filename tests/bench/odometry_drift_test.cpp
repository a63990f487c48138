#include "barn/bench/odometry_drift.hpp"

#include <cmath>

#include <gtest/gtest.h>

namespace barn::bench {
namespace {

TEST(OdometryDrift, WithoutErrorsTheEstimateIsTheTruthShiftedToTheStart) {
  const core::Pose2 start{-2.0, 3.0, 1.57};
  DriftingOdometry odometry(OdometryDriftConfig::groundTruth(), start, 7);
  // A 1 s quarter-circle arc at 200 Hz: the estimate follows the truth exactly.
  core::Pose2 pose = start;
  for (int i = 1; i <= 200; ++i) {
    pose.x += 0.005 * std::cos(pose.yaw);
    pose.y += 0.005 * std::sin(pose.yaw);
    pose.yaw += 0.5 * 0.005;
    odometry.update(pose, 0.005);
  }
  EXPECT_NEAR(odometry.pose().x, pose.x + 2.0, 1e-9);
  EXPECT_NEAR(odometry.pose().y, pose.y - 3.0, 1e-9);
  EXPECT_NEAR(odometry.pose().yaw, core::wrapAngle(pose.yaw), 1e-9);
}

TEST(OdometryDrift, AWheelScaleErrorStretchesEveryDistanceByTheSameFactor) {
  OdometryDriftConfig config = OdometryDriftConfig::groundTruth();
  config.speed_scale_stddev = 0.02;
  DriftingOdometry odometry(config, {0.0, 0.0, 0.0}, 11);
  core::Pose2 pose{0.0, 0.0, 0.0};
  double ratio_at_1m = 0.0;
  for (int i = 1; i <= 400; ++i) {  // 2 m straight ahead in 5 mm steps
    pose.x += 0.005;
    odometry.update(pose, 0.005);
    if (i == 200) ratio_at_1m = odometry.pose().x / pose.x;
  }
  const double ratio_at_2m = odometry.pose().x / pose.x;
  EXPECT_NE(ratio_at_1m, 1.0);                // the seed draws some scale error
  EXPECT_NEAR(ratio_at_2m, ratio_at_1m, 1e-12);  // and it is constant over the episode
  EXPECT_NEAR(odometry.pose().y, 0.0, 1e-12);
}

TEST(OdometryDrift, AGyroBiasTurnsTheEstimateOfAStandingRobotLinearlyInTime) {
  OdometryDriftConfig config = OdometryDriftConfig::groundTruth();
  config.gyro_bias_stddev = 0.01;
  DriftingOdometry odometry(config, {0.0, 0.0, 0.0}, 5);
  for (int i = 1; i <= 100; ++i) odometry.update({0.0, 0.0, 0.0}, 0.01);  // 1 s
  const double after_1s = odometry.pose().yaw;
  for (int i = 1; i <= 100; ++i) odometry.update({0.0, 0.0, 0.0}, 0.01);  // 2 s
  EXPECT_NE(after_1s, 0.0);
  EXPECT_NEAR(odometry.pose().yaw, 2.0 * after_1s, 1e-12);
  EXPECT_NEAR(odometry.pose().x, 0.0, 1e-12);  // turning in place does not move it
}

TEST(OdometryDrift, WheelsDoNotSeeSidewaysSlip) {
  OdometryDriftConfig config = OdometryDriftConfig::groundTruth();
  config.see_sideways_slip = false;
  DriftingOdometry odometry(config, {0.0, 0.0, 0.0}, 3);
  core::Pose2 pose{0.0, 0.0, 0.0};
  for (int i = 1; i <= 100; ++i) {  // slides 0.1 m to the left, facing +x
    pose.y += 0.001;
    odometry.update(pose, 0.005);
  }
  EXPECT_NEAR(odometry.pose().x, 0.0, 1e-12);
  EXPECT_NEAR(odometry.pose().y, 0.0, 1e-12);
}

TEST(OdometryDrift, ATurnRateErrorScalesEveryTurn) {
  OdometryDriftConfig config = OdometryDriftConfig::groundTruth();
  config.turn_scale_stddev = 0.05;
  DriftingOdometry odometry(config, {0.0, 0.0, 0.0}, 9);
  for (int i = 1; i <= 100; ++i) odometry.update({0.0, 0.0, 0.01 * i}, 0.01);  // 1 rad in place
  const double after_1rad = odometry.pose().yaw;
  for (int i = 101; i <= 200; ++i) odometry.update({0.0, 0.0, 0.01 * i}, 0.01);
  EXPECT_NE(after_1rad, 1.0);
  EXPECT_NEAR(odometry.pose().yaw, 2.0 * after_1rad, 1e-9);
}

TEST(OdometryDrift, TheDefaultsAreOnAndDrift) {
  // The shipped defaults drift: a 1 m straight drive is not estimated as exactly 1 m.
  DriftingOdometry odometry(OdometryDriftConfig{}, {0.0, 0.0, 0.0}, 1);
  ASSERT_TRUE(OdometryDriftConfig{}.enabled());
  for (int i = 1; i <= 200; ++i) odometry.update({0.005 * i, 0.0, 0.0}, 0.005);
  EXPECT_NE(odometry.pose().x, 1.0);
  EXPECT_NEAR(odometry.pose().x, 1.0, 0.1);
  EXPECT_FALSE(OdometryDriftConfig::groundTruth().enabled());
}

TEST(OdometryDrift, TheSameSeedGivesTheSameEstimate) {
  OdometryDriftConfig config = OdometryDriftConfig::groundTruth();
  config.speed_noise_density = 0.01;
  config.gyro_noise_density = 0.01;
  DriftingOdometry a(config, {0.0, 0.0, 0.0}, 42), b(config, {0.0, 0.0, 0.0}, 42);
  core::Pose2 pose{0.0, 0.0, 0.0};
  for (int i = 1; i <= 50; ++i) {
    pose.x += 0.01;
    a.update(pose, 0.01);
    b.update(pose, 0.01);
  }
  EXPECT_EQ(a.pose().x, b.pose().x);
  EXPECT_EQ(a.pose().yaw, b.pose().yaw);
  EXPECT_NE(a.pose().x, pose.x);
}

}  // namespace
}  // namespace barn::bench
