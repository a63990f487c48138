#include "barn/controllers/inventec.hpp"

#include <cmath>
#include <numbers>

#include <gtest/gtest.h>

namespace barn::controllers {
namespace {

constexpr double kDeg = std::numbers::pi / 180.0;

InventecState next(InventecState s, InventecInputs in) { return nextInventecState(s, in, InventecConfig{}); }

TEST(InventecFsm, InitialWaitsForAPath) {
  EXPECT_EQ(next(InventecState::Initial, {}), InventecState::Initial);
  InventecInputs in;
  in.has_path = true;
  EXPECT_EQ(next(InventecState::Initial, in), InventecState::Heading);
}

TEST(InventecFsm, HeadingHandsOverWithinThirtyDegrees) {
  InventecInputs in;
  in.has_path = true;
  in.heading_error = 31 * kDeg;
  EXPECT_EQ(next(InventecState::Heading, in), InventecState::Heading);
  in.heading_error = -29 * kDeg;
  EXPECT_EQ(next(InventecState::Heading, in), InventecState::Lflh);
  in.rotation_unsafe = true;  // an unsafe rotation wins over alignment
  EXPECT_EQ(next(InventecState::Heading, in), InventecState::Backtrack);
}

TEST(InventecFsm, LflhBacktracksOnDangerAndReturnsToHeadingWhenMisaligned) {
  InventecInputs in;
  in.has_path = true;
  in.heading_error = 45 * kDeg;  // between the 30 degree tolerance and the 60 degree limit: keep driving
  EXPECT_EQ(next(InventecState::Lflh, in), InventecState::Lflh);
  in.heading_error = 61 * kDeg;
  EXPECT_EQ(next(InventecState::Lflh, in), InventecState::Heading);
  in.command_unsafe = true;
  EXPECT_EQ(next(InventecState::Lflh, in), InventecState::Backtrack);
}

TEST(InventecFsm, BacktrackGoesForwardWhenBlockedBehindAndHeadingWhenDone) {
  InventecInputs in;
  EXPECT_EQ(next(InventecState::Backtrack, in), InventecState::Backtrack);
  in.backtrack_done = true;
  EXPECT_EQ(next(InventecState::Backtrack, in), InventecState::Heading);
  in.rear_blocked = true;
  EXPECT_EQ(next(InventecState::Backtrack, in), InventecState::Forward);
}

TEST(InventecFsm, ForwardBacktracksWhenStuckAndHeadsOnWhenDone) {
  InventecInputs in;
  EXPECT_EQ(next(InventecState::Forward, in), InventecState::Forward);
  in.forward_done = true;
  EXPECT_EQ(next(InventecState::Forward, in), InventecState::Heading);
  in.forward_unsafe = true;
  EXPECT_EQ(next(InventecState::Forward, in), InventecState::Backtrack);
}

TEST(SafetyChecks, FootprintInflationSeesPointsWithinTheOffset) {
  // 0.508 x 0.43 grown by 0.04: x in [-0.294, 0.294], y in [-0.255, 0.255].
  const Box box = footprintBox(0.508, 0.43, 0.04);
  EXPECT_TRUE(footprintInflationHit({{0.29, 0.0}}, box));
  EXPECT_FALSE(footprintInflationHit({{0.30, 0.0}}, box));
  EXPECT_TRUE(footprintInflationHit({{0.0, -0.25}}, box));
  EXPECT_FALSE(footprintInflationHit({{0.0, 0.26}, {-0.3, 0.0}}, box));
}

TEST(SafetyChecks, FiTripsAtFourCentimetresButNotTwoForAPointThreeCentimetresOut) {
  // The unpadded footprint's front edge is at x = 0.508 / 2 = 0.254; the point is 0.03 m out.
  const std::vector<Eigen::Vector2d> point = {{0.254 + 0.03, 0.0}};
  EXPECT_TRUE(footprintInflationHit(point, footprintBox(0.508, 0.43, 0.04)));   // edge at 0.294
  EXPECT_FALSE(footprintInflationHit(point, footprintBox(0.508, 0.43, 0.02)));  // edge at 0.274
}

TEST(SafetyChecks, RolloutTowardAWallTenCentimetresAheadIsDangerousAtOneMetrePerSecond) {
  // A wall 0.1 m ahead of the front edge (x = 0.354), sampled every centimetre across.
  std::vector<Eigen::Vector2d> wall;
  for (double y = -1.0; y <= 1.0; y += 0.01) wall.emplace_back(0.354, y);
  const Box body = footprintBox(0.508, 0.43, 0.0);
  // 20 steps of 0.01 s: 1 m/s covers 0.2 m > 0.1 m; 0.1 m/s covers 0.02 m < 0.1 m.
  EXPECT_TRUE(rolloutHit(wall, body, {1.0, 0.0}, 0.01, 20));
  EXPECT_FALSE(rolloutHit(wall, body, {0.1, 0.0}, 0.01, 20));
}

TEST(SafetyChecks, ScanPointsIncludeTheMountOffset) {
  sim::LidarConfig lidar;  // mounted 0.055 m ahead
  core::LaserScan scan;
  scan.angle_min = 0.0;
  scan.angle_increment = std::numbers::pi / 2;
  scan.ranges = {1.0, 2.0, std::numeric_limits<double>::infinity()};
  const auto points = scanPoints(scan, lidar);
  ASSERT_EQ(points.size(), 2u);  // the miss gives no point
  EXPECT_NEAR(points[0].x(), 1.055, 1e-12);
  EXPECT_NEAR(points[1].x(), 0.055, 1e-12);
  EXPECT_NEAR(points[1].y(), 2.0, 1e-12);
}

TEST(SafetyChecks, RolloutCatchesWhatTheCommandDrivesInto) {
  const Box body = footprintBox(0.508, 0.43, 0.0);  // front edge at x = 0.254
  const std::vector<Eigen::Vector2d> ahead = {{0.40, 0.0}};
  // 0.7 m/s for 20 x 0.01 s = 0.14 m: the front edge reaches 0.394 < 0.40 -> clear.
  EXPECT_FALSE(rolloutHit(ahead, body, {0.7, 0.0}, 0.01, 20));
  // 1.0 m/s: 0.2 m -> 0.454 > 0.40 -> hit.
  EXPECT_TRUE(rolloutHit(ahead, body, {1.0, 0.0}, 0.01, 20));
  // Turning in place never moves the front edge 0.40 m out... but swings the corner:
  // the corner (0.254, 0.215) is 0.333 m from the centre, below 0.40 -> clear.
  EXPECT_FALSE(rolloutHit(ahead, body, {0.0, 2.0}, 0.01, 20));
  // Backing away from it is always clear.
  EXPECT_FALSE(rolloutHit(ahead, body, {-0.5, 0.0}, 0.01, 20));
}

TEST(SafetyChecks, RearRegionSeesOnlyWhatIsDirectlyBehind) {
  nav::CostmapConfig c;
  c.rolling = true;
  nav::Costmap map(c);
  map.recentre({0.0, 0.0});
  const Box body = footprintBox(0.508, 0.43, 0.0);
  const core::Pose2 pose{0.0, 0.0, 0.0};
  EXPECT_FALSE(rearRegionBlocked(map, pose, body, 0.1));
  map.markObstacle({0.5, 0.0});  // ahead: not in the strip
  EXPECT_FALSE(rearRegionBlocked(map, pose, body, 0.1));
  map.markObstacle({-0.30, 0.1});  // 0.046 m behind the rear edge (-0.254): in the strip
  EXPECT_TRUE(rearRegionBlocked(map, pose, body, 0.1));
}

}  // namespace
}  // namespace barn::controllers
