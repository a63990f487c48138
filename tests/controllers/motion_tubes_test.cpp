#include "barn/controllers/motion_tubes.hpp"

#include <cmath>
#include <limits>
#include <numbers>

#include <gtest/gtest.h>

#include "barn/core/errors.hpp"
#include "scan_fixtures.hpp"

namespace barn::controllers {
namespace {

constexpr double kInf = std::numeric_limits<double>::infinity();

// The default LiDAR: 720 beams over +-2.35619 rad (increment 4.71238 / 719 = 0.0065541 rad),
// 0.1 ... 30 m, mounted 0.055 m ahead of the robot centre.
const core::LidarConfig kLidar;

// ---- Sample -> beam mapping ----

TEST(MotionTubes, ASampleReadsTheBeamPointingAtItAndItsRangeFromTheSensor) {
  // (0.95, -0.25) in the robot frame is (0.895, -0.25) from the sensor:
  // bearing atan2(-0.25, 0.895) = -0.272387 rad, (-0.272387 + 2.35619) / 0.0065541 = 317.94 -> 318,
  // range hypot(0.895, 0.25) = 0.929260.
  SensorSample s;
  ASSERT_TRUE(toSensorSample({0.95, -0.25}, kLidar, s));
  EXPECT_EQ(s.beam, 318);
  EXPECT_NEAR(s.range, 0.929260, 1e-6);
  // (0.375, 0.25) -> (0.32, 0.25): bearing 0.663203, 460.69 -> 461, range 0.406079.
  ASSERT_TRUE(toSensorSample({0.375, 0.25}, kLidar, s));
  EXPECT_EQ(s.beam, 461);
  EXPECT_NEAR(s.range, 0.406079, 1e-6);
}

TEST(MotionTubes, PointsTheLidarCannotCheckAreLeftOut) {
  SensorSample s;
  // Behind: (-0.5, 0) is at bearing 180 deg from the sensor, outside +-135 deg.
  EXPECT_FALSE(toSensorSample({-0.5, 0.0}, kLidar, s));
  // (-0.2, -0.25) -> (-0.255, -0.25): bearing -135.56 deg, just outside.
  EXPECT_FALSE(toSensorSample({-0.2, -0.25}, kLidar, s));
  // Too near: (0.1, 0) is 0.045 m from the sensor, under range_min 0.1.
  EXPECT_FALSE(toSensorSample({0.1, 0.0}, kLidar, s));
}

// ---- Tube geometry ----

TEST(MotionTubes, AStraightTubeIsTheBoxSweptForwardSampledEveryTenthOfAMetreAtMost) {
  // Radius 1e9: straight to within 1e-6 m. The 0.75 m arcs take ceil(0.75 / 0.1) = 8 steps of
  // 0.09375 m (9 points each); the inner side at the end runs 0.75 -> 0.95 (2 steps, 3 points),
  // the front edge -0.25 -> 0.25 at x = 0.95 (5 steps, 6 points): 27 edge points.
  const TubeShape shape = tubeShape(0.75, 1e9, MotionTubeConfig{});
  ASSERT_EQ(shape.edge.size(), 27u);
  // Outer arc: the front-right corner (0.2, -0.25) -> (0.95, -0.25).
  EXPECT_NEAR(shape.edge[0].x(), 0.2, 1e-6);
  EXPECT_NEAR(shape.edge[0].y(), -0.25, 1e-6);
  EXPECT_NEAR(shape.edge[1].x(), 0.29375, 1e-6);
  EXPECT_NEAR(shape.edge[8].x(), 0.95, 1e-6);
  // Inner arc: the left side's centre (0, 0.25) -> (0.75, 0.25); point 4 is at x = 0.375.
  EXPECT_NEAR(shape.edge[9].x(), 0.0, 1e-6);
  EXPECT_NEAR(shape.edge[13].x(), 0.375, 1e-6);
  EXPECT_NEAR(shape.edge[13].y(), 0.25, 1e-6);
  // Front edge at the end, from the right corner to the left one.
  EXPECT_NEAR(shape.edge[21].x(), 0.95, 1e-6);
  EXPECT_NEAR(shape.edge[21].y(), -0.25, 1e-6);
  EXPECT_NEAR(shape.edge[26].y(), 0.25, 1e-6);
  // Whiskers: the outer arc 0.1 m farther from the centre of rotation (far to the left) than the
  // right corner (y = -0.35), the inner one 0.1 m nearer than the left side (y = 0.35), the front
  // line 0.05 m ahead of the front edge (x = 1.0). (Radius 1e9: the arithmetic near the centre
  // loses ~1e-7 m, hence 1e-6.)
  EXPECT_NEAR(shape.outer.front().y(), -0.35, 1e-6);
  EXPECT_NEAR(shape.inner.back().y(), 0.35, 1e-6);
  ASSERT_EQ(shape.front.size(), 6u);
  EXPECT_NEAR(shape.front[0].x(), 1.0, 1e-6);
}

TEST(MotionTubes, AStraightTubesSamplesMapToTheirBeams) {
  // The edge's samples in the order of the shape (none is hidden: all lie ahead of the sensor's
  // blind sector, the nearest (0, 0.25) is 0.256 m away); two checked by hand (see above).
  const TubeShape shape = tubeShape(0.75, 1e9, MotionTubeConfig{});
  const SampleSet edge = toSampleSet(shape.edge, kLidar);
  ASSERT_EQ(edge.size(), shape.edge.size());
  EXPECT_EQ(edge[8].beam, 318);   // (0.95, -0.25)
  EXPECT_NEAR(edge[8].range, 0.929260, 1e-6);
  EXPECT_EQ(edge[13].beam, 461);  // (0.375, 0.25)
  EXPECT_NEAR(edge[13].range, 0.406079, 1e-6);
  // (0, 0.25) -> (-0.055, 0.25): bearing 1.787347, 632.21 -> 632, range 0.255979.
  EXPECT_EQ(edge[9].beam, 632);
  EXPECT_NEAR(edge[9].range, 0.255979, 1e-6);
}

TEST(MotionTubes, ALeftTurnSweepsTheFrontRightCornerAndTheLeftSide) {
  // R = 1, L = pi / 2: a quarter turn about (0, 1). The left side's centre (0, 0.25) is 0.75 from
  // the centre and ends at (0.75, 1); the front-right corner (0.2, -0.25) ends at (1.25, 1.2).
  const TubeShape shape = tubeShape(std::numbers::pi / 2, 1.0, MotionTubeConfig{});
  const core::Pose2 end = arcEnd(std::numbers::pi / 2, 1.0);
  EXPECT_NEAR(end.x, 1.0, 1e-12);
  EXPECT_NEAR(end.y, 1.0, 1e-12);
  EXPECT_NEAR(end.yaw, std::numbers::pi / 2, 1e-12);
  // Outer arc: radius hypot(0.2, 1.25) = 1.26590, length 1.98848: ceil(19.88) = 20 steps.
  EXPECT_NEAR(shape.edge[20].x(), 1.25, 1e-9);
  EXPECT_NEAR(shape.edge[20].y(), 1.2, 1e-9);
  // Inner arc: radius 0.75, length 1.17810: 12 steps, points 21 ... 33.
  EXPECT_NEAR(shape.edge[33].x(), 0.75, 1e-9);
  EXPECT_NEAR(shape.edge[33].y(), 1.0, 1e-9);
}

TEST(MotionTubes, TheLibraryHas362TubesInTheTeamsOrder) {
  const std::vector<MotionTube> tubes = buildTubeLibrary(0.75, MotionTubeConfig{}, kLidar);
  ASSERT_EQ(tubes.size(), 362u);  // 2 (90 / 0.5 + 1)
  // alpha = 0: the curvature floor 0.001 gives radius 0.9 / 0.001 = 900, left then right.
  EXPECT_NEAR(tubes[0].radius, 900.0, 1e-9);
  EXPECT_NEAR(tubes[1].radius, -900.0, 1e-9);
  // alpha = 0.5 deg: curvature 0.0087266 / 0.75 = 0.0116355, radius 0.9 / that = 77.3493.
  EXPECT_NEAR(tubes[2].radius, 77.3493, 1e-4);
  // alpha = 90 deg, right: radius -0.9 * 0.75 / (pi / 2) = -0.429718; the heading changes by
  // 0.75 / -0.429718 = -1.745329 rad (-100 deg: alpha / 0.9).
  EXPECT_NEAR(tubes[361].radius, -0.429718, 1e-6);
  EXPECT_NEAR(tubes[361].heading_change, -100.0 * std::numbers::pi / 180.0, 1e-9);
}

TEST(MotionTubes, AReversingTubesRearIsOutOfTheLidarsSight) {
  // Straight back 0.75 m: the rear edge at x = -0.95 is behind the sensor's 270 deg; only the
  // samples ahead of the blind sector stay (the inner arc's start (0, 0.25) is one).
  MotionTubeConfig config;
  const TubeShape shape = tubeShape(-0.75, 1e9, config);
  const SampleSet edge = toSampleSet(shape.edge, kLidar);
  EXPECT_LT(edge.size(), shape.edge.size());
  for (const auto& p : shape.edge) {
    SensorSample s;
    if (p.x() < -0.3) {
      EXPECT_FALSE(toSensorSample(p, kLidar, s)) << p.transpose();
    }
  }
  EXPECT_NEAR(arcEnd(-0.75, 1e9).x, -0.75, 1e-9);
}

// ---- Availability ----

TEST(MotionTubes, ASetIsBlockedOnlyByAValidReturnNearerThanASample) {
  const SampleSet set{{318, 0.929260}, {461, 0.406079}};
  core::LaserScan scan = uniformScan(kLidar, kInf);
  EXPECT_TRUE(isFree(set, scan));
  scan.ranges[318] = 0.90;  // nearer than the sample 0.929 m along that beam
  EXPECT_FALSE(isFree(set, scan));
  scan.ranges[318] = 0.95;  // beyond the sample
  EXPECT_TRUE(isFree(set, scan));
  scan.ranges[318] = 0.05;  // under range_min 0.1: not a valid return
  EXPECT_TRUE(isFree(set, scan));
  scan.ranges[318] = 30.0;  // range_max: no return
  EXPECT_TRUE(isFree(set, scan));
  scan.ranges[461] = 0.4;   // the other sample: 0.4 < 0.406
  EXPECT_FALSE(isFree(set, scan));
  EXPECT_TRUE(isFree({}, scan));
}

TEST(MotionTubes, TheRotationRingIsWhereEachBeamLeavesACircleAboutTheRobotCentre) {
  // Three beams at -90, 0, 90 deg from a sensor 0.055 m ahead of the centre; circle 0.4:
  // straight ahead 0.4 - 0.055 = 0.345; sideways sqrt(0.4^2 - 0.055^2) = 0.396201.
  core::LidarConfig lidar;
  lidar.beams = 3;
  lidar.angle_min = -std::numbers::pi / 2;
  lidar.angle_max = std::numbers::pi / 2;
  const SampleSet ring = rotationRing(0.4, lidar);
  ASSERT_EQ(ring.size(), 3u);
  EXPECT_NEAR(ring[0].range, 0.396201, 1e-6);
  EXPECT_NEAR(ring[1].range, 0.345, 1e-12);
  EXPECT_NEAR(ring[2].range, 0.396201, 1e-6);
}

// ---- Config ----

TEST(MotionTubes, ValidationNamesTheField) {
  MotionTubeConfig config;
  config.edge_step = 0.0;
  config.max_angle_deg = 170.0;  // radius 0.9 * 0.75 / 2.967 = 0.2275 < 0.25 + 0.1: the inner whisker would cross the centre
  core::Errors errors;
  validate(config, errors, "kulfm.tubes");
  ASSERT_EQ(errors.messages().size(), 2u);
  EXPECT_NE(errors.messages()[0].find("kulfm.tubes.edge_step"), std::string::npos);
  EXPECT_NE(errors.messages()[1].find("kulfm.tubes.max_angle_deg"), std::string::npos);
}

}  // namespace
}  // namespace barn::controllers
