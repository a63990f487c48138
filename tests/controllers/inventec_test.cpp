#include "barn/controllers/inventec.hpp"

#include <cmath>
#include <limits>
#include <numbers>

#include <gtest/gtest.h>

#include "barn/core/config.hpp"
#include "policy_fixtures.hpp"
#include "scan_fixtures.hpp"

namespace barn::controllers {
namespace {

constexpr double kDeg = std::numbers::pi / 180.0;
constexpr double kInf = std::numeric_limits<double>::infinity();
// BARN's costmaps' inscribed radius: the 0.42 x 0.33 footprint padded by 0.1, 0.33 / 2 + 0.1.
const double kBarnInscribed = nav::NavStackConfig{}.inscribedRadius({});

// The team's front check on the Jackal's planning footprint (0.508 x 0.43), as the controller
// sets it from core::RobotConfig.
FrontCheck jackalFrontCheck() {
  const core::RobotConfig jackal;
  FrontCheck check;
  check.half_width = jackal.footprint_width / 2;    // 0.215
  check.half_length = jackal.footprint_length / 2;  // 0.254
  return check;
}

// The final-pose rollout on BARN's costmap footprint (0.42 x 0.33), as the controllers set it.
BeamRollout barnBeamRollout() {
  BeamRollout check;
  check.rectangle = nav::NavStackConfig{}.footprint();
  return check;
}

InventecConfig codeConfig() { return InventecConfig{}; }
InventecConfig paperConfig() {
  InventecConfig c;
  c.variant = InventecVariant::Paper;
  c.heading_tolerance_deg = 30.0;
  return c;
}
InventecState next(InventecState s, InventecInputs in, const InventecConfig& c = codeConfig()) {
  return nextInventecState(s, in, InventecRules::of(c));
}

// ---- The code's state machine: every edge ----

TEST(InventecFsm, InitialWaitsForAPathThenStartsInLflh) {
  EXPECT_EQ(next(InventecState::Initial, {}), InventecState::Initial);
  InventecInputs in;
  in.has_path = true;
  in.heading_error = 90 * kDeg;  // the code starts in LfLH, which then hands over to HardTurn
  EXPECT_EQ(next(InventecState::Initial, in), InventecState::Lflh);
}

TEST(InventecFsm, LflhKeepsDrivingUpToSixtyDegreesThenHardTurns) {
  InventecInputs in;
  in.has_path = true;
  in.heading_error = 59 * kDeg;
  EXPECT_EQ(next(InventecState::Lflh, in), InventecState::Lflh);
  in.heading_error = -61 * kDeg;
  EXPECT_EQ(next(InventecState::Lflh, in), InventecState::HardTurn);
}

TEST(InventecFsm, LflhBacktracksOnAnUnsafeCommandFirst) {
  InventecInputs in;
  in.has_path = true;
  in.heading_error = 90 * kDeg;
  in.command_unsafe = true;  // wins over the hard turn
  EXPECT_EQ(next(InventecState::Lflh, in), InventecState::BackTrack);
}

TEST(InventecFsm, HardTurnRecoversBelowTenDegrees) {
  InventecInputs in;
  in.has_path = true;
  in.heading_error = 11 * kDeg;
  EXPECT_EQ(next(InventecState::HardTurn, in), InventecState::HardTurn);
  in.heading_error = -9 * kDeg;
  EXPECT_EQ(next(InventecState::HardTurn, in), InventecState::Lflh);
}

TEST(InventecFsm, HardTurnBacktracksWhenTheRotationIsUnsafe) {
  InventecInputs in;
  in.has_path = true;
  in.heading_error = 0.0;  // aligned, but the rotation check (or the ring) fired: unsafe wins
  in.rotation_unsafe = true;
  EXPECT_EQ(next(InventecState::HardTurn, in), InventecState::BackTrack);
}

TEST(InventecFsm, BackTrackHardTurnsWhenDoneAndWigglesWhenTheRearIsBlocked) {
  InventecInputs in;
  EXPECT_EQ(next(InventecState::BackTrack, in), InventecState::BackTrack);
  in.backtrack_done = true;
  EXPECT_EQ(next(InventecState::BackTrack, in), InventecState::HardTurn);
  in.rear_blocked = true;
  EXPECT_EQ(next(InventecState::BackTrack, in), InventecState::Wiggle);
}

TEST(InventecFsm, WiggleGoesForwardWhenTurned) {
  InventecInputs in;
  EXPECT_EQ(next(InventecState::Wiggle, in), InventecState::Wiggle);
  in.wiggle_done = true;
  EXPECT_EQ(next(InventecState::Wiggle, in), InventecState::Forward);
}

TEST(InventecFsm, ForwardHardTurnsAfterItsTime) {
  InventecInputs in;
  EXPECT_EQ(next(InventecState::Forward, in), InventecState::Forward);
  in.forward_done = true;
  EXPECT_EQ(next(InventecState::Forward, in), InventecState::HardTurn);
}

// ---- The paper's variant: the edges that differ ----

TEST(InventecFsmPaper, InitialTurnsTowardThePathFirst) {
  InventecInputs in;
  in.has_path = true;
  EXPECT_EQ(next(InventecState::Initial, in, paperConfig()), InventecState::HardTurn);
}

TEST(InventecFsmPaper, HeadingHandsOverWithinThirtyDegrees) {
  InventecInputs in;
  in.has_path = true;
  in.heading_error = 31 * kDeg;
  EXPECT_EQ(next(InventecState::HardTurn, in, paperConfig()), InventecState::HardTurn);
  in.heading_error = -29 * kDeg;
  EXPECT_EQ(next(InventecState::HardTurn, in, paperConfig()), InventecState::Lflh);
}

TEST(InventecFsmPaper, BlockedRearGoesStraightToForwardAndAnUnsafeForwardBacktracks) {
  InventecInputs in;
  in.rear_blocked = true;
  EXPECT_EQ(next(InventecState::BackTrack, in, paperConfig()), InventecState::Forward);
  InventecInputs f;
  f.forward_unsafe = true;
  EXPECT_EQ(next(InventecState::Forward, f, paperConfig()), InventecState::BackTrack);
}

// ---- The code's front check ----

/// A scan with one return at `bearing` [rad] and `range` [m] (sensor frame), every other beam a miss.
core::LaserScan oneReturn(double bearing, double range) {
  const core::LidarConfig lidar;
  core::LaserScan scan;
  scan.angle_min = lidar.angle_min;
  scan.angle_increment = lidar.angleIncrement();
  scan.ranges.assign(static_cast<std::size_t>(lidar.beams), std::numeric_limits<double>::infinity());
  const auto i = static_cast<std::size_t>(std::lround((bearing - scan.angle_min) / scan.angle_increment));
  scan.ranges.at(i) = range;
  return scan;
}

/// The robot-frame point of that return (the sensor is 0.055 m ahead of the centre).
Eigen::Vector2d pointOf(const core::LaserScan& scan) {
  const core::LidarConfig lidar;
  core::BeamDirections beams;
  const auto points = scanPoints(scan, lidar, beams);
  return points.at(0);
}

TEST(InventecConfig, SharedGroupsKeepTheirKeysAndInventecsDefaults) {
  // The drive's keys at the top of the block, the rollout's under safety as rollout_*; the
  // defaults Inventec sets (0.7 m/s, 2 rad/s, tolerance 0.02) where the file says nothing.
  const InventecConfig c = core::readConfig<InventecConfig>(
      core::ConfigNode::parseString("rate: 20\nsafety: {rollout_steps: 10}\n", "inventec.yaml"));
  EXPECT_EQ(c.drive.rate, 20.0);
  EXPECT_EQ(c.drive.max_speed, 0.7);
  EXPECT_EQ(c.drive.max_turn_rate, 2.0);
  EXPECT_EQ(c.drive.local_goal_distance, 1.5);
  EXPECT_EQ(c.safety.rollout.steps, 10);
  EXPECT_EQ(c.safety.rollout.tolerance, 0.02);
  const std::string text = core::writeConfig(c);
  EXPECT_NE(text.find("\nrate: 20\nlocal_goal_distance: 1.5\nmax_speed: 0.7\nmax_turn_rate: 2\n"), std::string::npos)
      << text;
  EXPECT_NE(text.find("\n  rollout_tolerance: 0.02\n  rollout_steps: 10\n  rollout_dt: 0.01\n"), std::string::npos)
      << text;
}

TEST(InventecConfig, TheTeamsCostmapsDeriveTheirInscribedRadiiFromTheFootprint) {
  // The 0.42 x 0.33 footprint, padded by the team's 0.075 (global: 0.165 + 0.075 = 0.24) and,
  // on the local costmap, by its own -0.08 (0.165 - 0.08 = 0.085): the values the team's
  // costmap_2d derived, to the last bit (the runs' records depend on them).
  const nav::NavStack nav(InventecConfig{}.nav);
  EXPECT_EQ(nav.globalCostmap().inscribedRadius(), 0.24);
  EXPECT_EQ(nav.localCostmap().inscribedRadius(), 0.085);
}

TEST(FrontCheck, IgnoresReturnsBeyondFortySevenDegreesEvenInsideTheBox) {
  const core::LidarConfig lidar;
  const FrontCheck check = jackalFrontCheck();
  core::BeamDirections beams;
  // 0.25 m from the sensor at 50 deg: robot frame (0.216, 0.192), inside |y| <= 0.225, x <= 0.354.
  const core::LaserScan at50 = oneReturn(50 * kDeg, 0.25);
  const Eigen::Vector2d p = pointOf(at50);
  ASSERT_LT(std::abs(p.y()), 0.225);
  ASSERT_LT(p.x(), 0.354);
  EXPECT_FALSE(frontCheckHit(at50, lidar, beams, {0.5, 0.0}, check));
  // The same distance at 40 deg is seen.
  EXPECT_TRUE(frontCheckHit(oneReturn(40 * kDeg, 0.25), lidar, beams, {0.5, 0.0}, check));
}

TEST(FrontCheck, ReachGrowsWithSpeed) {
  const core::LidarConfig lidar;
  const FrontCheck check = jackalFrontCheck();
  core::BeamDirections beams;
  // Straight ahead, 0.40 m from the sensor: x = 0.455 from the centre.
  const core::LaserScan ahead = oneReturn(0.0, 0.40);
  // The reach is 0.254 + max(0.1, 0.25 v): 0.354 at v <= 0.4, 0.429 at 0.7, 0.504 at 1.0.
  EXPECT_FALSE(frontCheckHit(ahead, lidar, beams, {0.1, 0.0}, check));
  EXPECT_FALSE(frontCheckHit(ahead, lidar, beams, {0.7, 0.0}, check));
  EXPECT_TRUE(frontCheckHit(ahead, lidar, beams, {1.0, 0.0}, check));
  // Lateral limit: 0.215 + 0.01 (points 0.25 m ahead of the sensor, bearing about 42 deg).
  const core::LaserScan side = oneReturn(std::atan2(0.23, 0.25), std::hypot(0.25, 0.23));  // y = 0.23
  EXPECT_FALSE(frontCheckHit(side, lidar, beams, {0.3, 0.0}, check));
  const core::LaserScan inner = oneReturn(std::atan2(0.22, 0.25), std::hypot(0.25, 0.22));  // y = 0.22
  EXPECT_TRUE(frontCheckHit(inner, lidar, beams, {0.3, 0.0}, check));
}

TEST(FrontCheck, TurningRotatesTheRegionTowardTheTurn) {
  const core::LidarConfig lidar;
  const FrontCheck check = jackalFrontCheck();
  core::BeamDirections beams;
  // A point ahead-left, just outside the straight region (|y| > 0.225): robot frame (0.30, 0.25).
  const double bx = 0.30 - lidar.mount_x, by = 0.25;
  const core::LaserScan left = oneReturn(std::atan2(by, bx), std::hypot(bx, by));
  EXPECT_FALSE(frontCheckHit(left, lidar, beams, {0.7, 0.0}, check));
  // Turning left at 2 rad/s turns the region 0.4 rad to the left: in the region's frame the
  // point is at (0.374, 0.114), inside the 0.429 m reach of 0.7 m/s.
  EXPECT_TRUE(frontCheckHit(left, lidar, beams, {0.7, 2.0}, check));
  // Turning right swings the region away from it: (0.179, 0.347), outside.
  EXPECT_FALSE(frontCheckHit(left, lidar, beams, {0.7, -2.0}, check));
  // A point ahead-left inside the straight region, (0.34, 0.20), drops out when turning right.
  const core::LaserScan inside = oneReturn(std::atan2(0.20, 0.34 - lidar.mount_x), std::hypot(0.34 - lidar.mount_x, 0.20));
  EXPECT_TRUE(frontCheckHit(inside, lidar, beams, {0.3, 0.0}, check));
  EXPECT_FALSE(frontCheckHit(inside, lidar, beams, {0.3, -2.0}, check));
}

// ---- The final-pose rollout ----

TEST(BeamRollout, ReachesPastTheCornersByTheirLOneLength) {
  // Standing still, the 0.42 x 0.33 rectangle's corner (0.21, 0.165) is 0.267 from the centre
  // at 38.2 deg, but its beam is compared with |x| + |y| = 0.375. A post whose near side is 0.30
  // out at that bearing is outside the rectangle, yet trips the check; at 0.40 it does not.
  const core::LidarConfig lidar = centredLidar();
  const double bearing = std::atan2(0.165, 0.21);
  const Eigen::Vector2d direction(std::cos(bearing), std::sin(bearing));
  const BeamRollout check = barnBeamRollout();
  const core::LaserScan near = withPost(uniformScan(lidar, kInf), lidar, 0.32 * direction, 0.02);
  EXPECT_TRUE(beamRolloutHit(near, {0.0, 0.0}, check));
  core::BeamDirections beams;
  EXPECT_FALSE(footprintInflationHit(scanPoints(near, lidar, beams), check.rectangle));  // nothing inside the rectangle
  EXPECT_FALSE(beamRolloutHit(withPost(uniformScan(lidar, kInf), lidar, 0.42 * direction, 0.02), {0.0, 0.0}, check));
}

TEST(BeamRollout, WallAheadAndTheTolerance) {
  const core::LidarConfig lidar = centredLidar();
  BeamRollout check = barnBeamRollout();
  // 1 m/s for 0.2 s puts the front edge at 0.41, past a wall at 0.33; 0.1 m/s at 0.23, where the
  // corner (0.23, 0.165) reads the wall 0.406 away against |x| + |y| = 0.395: clear, but not
  // with Inventec's 0.02 tolerance.
  const core::LaserScan wall = wallScan(lidar, 0.33);
  EXPECT_TRUE(beamRolloutHit(wall, {1.0, 0.0}, check));
  EXPECT_FALSE(beamRolloutHit(wall, {0.1, 0.0}, check));
  check.tolerance = 0.02;
  EXPECT_TRUE(beamRolloutHit(wall, {0.1, 0.0}, check));
}

TEST(BeamRollout, PointsOutsideTheFieldOfViewAreNotChecked) {
  // Backing 0.2 m toward a wall 0.3 m behind: the rear edge (x = -0.41) lies beyond +-135 deg,
  // where no beam looks, and the beams that do look back see the wall farther than their
  // points' |x| + |y|. The code's check is blind behind the robot.
  const core::LidarConfig lidar = centredLidar();
  core::LaserScan behind = uniformScan(lidar, kInf);
  for (std::size_t i = 0; i < behind.ranges.size(); ++i) {
    const double c = std::cos(behind.angle(i));
    if (c < -1e-9) behind.ranges[i] = -0.3 / c;
  }
  EXPECT_FALSE(beamRolloutHit(behind, {-1.0, 0.0}, barnBeamRollout()));
}

TEST(MpcRollout, RolloutCatchesWhatTheCommandDrivesInto) {
  const core::Rect body = core::Rect::centred(0.508, 0.43);  // front edge at x = 0.254
  const std::vector<Eigen::Vector2d> ahead = {{0.40, 0.0}};
  // 0.7 m/s for 20 x 0.01 s = 0.14 m: the front edge reaches 0.394 < 0.40 -> clear.
  EXPECT_FALSE(rolloutHit(ahead, body, {0.7, 0.0}, 0.01, 20));
  // 1.0 m/s: 0.2 m -> 0.454 > 0.40 -> hit. 20 x 0.02 s at 0.7 m/s: 0.28 m -> hit.
  EXPECT_TRUE(rolloutHit(ahead, body, {1.0, 0.0}, 0.01, 20));
  EXPECT_TRUE(rolloutHit(ahead, body, {0.7, 0.0}, 0.02, 20));
  // Turning in place: the corner (0.254, 0.215) is 0.333 m from the centre, below 0.40.
  EXPECT_FALSE(rolloutHit(ahead, body, {0.0, 2.0}, 0.01, 20));
  // Backing away from it is always clear.
  EXPECT_FALSE(rolloutHit(ahead, body, {-0.5, 0.0}, 0.01, 20));
}

// ---- The LiDAR ring and the boost's clear front ----

TEST(RingCheck, ThresholdGrowsFromThirtyCentimetresAheadToThirtyNineAtTheEdge) {
  EXPECT_TRUE(ringHit(oneReturn(0.0, 0.29), 0.30, 0.39));
  EXPECT_FALSE(ringHit(oneReturn(0.0, 0.32), 0.30, 0.39));
  // At -135 deg the threshold is 0.39.
  EXPECT_TRUE(ringHit(oneReturn(-135 * kDeg, 0.38), 0.30, 0.39));
  EXPECT_FALSE(ringHit(oneReturn(-135 * kDeg, 0.40), 0.30, 0.39));
  // At 90 deg: 0.30 + 0.09 * 90 / 135 = 0.36.
  EXPECT_TRUE(ringHit(oneReturn(90 * kDeg, 0.355), 0.30, 0.39));
  EXPECT_FALSE(ringHit(oneReturn(90 * kDeg, 0.365), 0.30, 0.39));
}

TEST(FrontClear, LooksOnlyWithinTheAngle) {
  EXPECT_TRUE(frontClear(oneReturn(60 * kDeg, 0.5), 47 * kDeg, 1.5));
  EXPECT_FALSE(frontClear(oneReturn(30 * kDeg, 1.4), 47 * kDeg, 1.5));
  EXPECT_TRUE(frontClear(oneReturn(30 * kDeg, 1.6), 47 * kDeg, 1.5));
}

// ---- Path cues and the Wiggle ----

TEST(CodePathCues, GoalIsOneAndAHalfMetresOutAndDirectionSumsHalfAMetre) {
  // Straight 1 m ahead, then 2 m to the left.
  nav::Path path;
  for (double x = 0.0; x <= 1.0 + 1e-9; x += 0.05) path.emplace_back(x, 0.0);
  for (double y = 0.05; y <= 2.0 + 1e-9; y += 0.05) path.emplace_back(1.0, y);
  const PathCues cues = codePathCues(path, 1.5, 0.5);
  EXPECT_NEAR(cues.path_direction, 0.0, 1e-9);  // the first 0.5 m is straight ahead
  // The first point more than 1.5 m (Euclidean) from the start: (1.0, 1.15).
  EXPECT_NEAR(cues.goal_direction.x(), 1.0 / std::hypot(1.0, 1.15), 1e-9);
  EXPECT_NEAR(cues.goal_direction.y(), 1.15 / std::hypot(1.0, 1.15), 1e-9);
  // A path that starts 0.2 m to the left: the start is that point, not the robot.
  nav::Path shifted;
  for (double x = 0.0; x <= 1.0 + 1e-9; x += 0.05) shifted.emplace_back(x, 0.2);
  EXPECT_NEAR(codePathCues(shifted, 1.5, 0.5).path_direction, 0.0, 1e-9);
  // A path turning back: direction behind the robot.
  const nav::Path back = {{0.0, 0.0}, {-0.2, 0.01}, {-0.4, 0.02}, {-0.6, 0.03}};
  EXPECT_GT(std::abs(codePathCues(back, 1.5, 0.5).path_direction), 170 * kDeg);
}

TEST(Wiggle, TargetIsThreeDegreesToThreePlusPointTwoRadiansOnThePathSide) {
  core::Rng rng(7);
  const double yaw = 1.0;
  for (int k = 0; k < 200; ++k) {
    const double left = wiggleTarget(yaw, 0.5, 3 * kDeg, 0.2, 20, rng) - yaw;
    EXPECT_GE(left, 3 * kDeg - 1e-12);
    EXPECT_LE(left, 3 * kDeg + 0.2 + 1e-12);
    const double right = wiggleTarget(yaw, -0.5, 3 * kDeg, 0.2, 20, rng) - yaw;
    EXPECT_LE(right, -3 * kDeg + 1e-12);
    EXPECT_GE(right, -3 * kDeg - 0.2 - 1e-12);
  }
}

TEST(Wiggle, SameSeedSameTargets) {
  core::Rng a(42), b(42), c(43);
  bool differs = false;
  for (int k = 0; k < 20; ++k) {
    const double ta = wiggleTarget(0.0, 1.0, 3 * kDeg, 0.2, 20, a);
    EXPECT_EQ(ta, wiggleTarget(0.0, 1.0, 3 * kDeg, 0.2, 20, b));
    differs = differs || ta != wiggleTarget(0.0, 1.0, 3 * kDeg, 0.2, 20, c);
  }
  EXPECT_TRUE(differs);
}

// ---- The paper's static check and the shared helpers ----

TEST(SafetyChecks, FootprintInflationSeesPointsWithinTheOffset) {
  // 0.508 x 0.43 grown by 0.04: x in [-0.294, 0.294], y in [-0.255, 0.255].
  const core::Rect box = core::Rect::centred(0.508, 0.43).grownBy(0.04);
  EXPECT_TRUE(footprintInflationHit({{0.29, 0.0}}, box));
  EXPECT_FALSE(footprintInflationHit({{0.30, 0.0}}, box));
  EXPECT_TRUE(footprintInflationHit({{0.0, -0.25}}, box));
  EXPECT_FALSE(footprintInflationHit({{0.0, 0.26}, {-0.3, 0.0}}, box));
}

TEST(SafetyChecks, ScanPointsIncludeTheMountOffset) {
  core::LidarConfig lidar;  // mounted 0.055 m ahead
  core::LaserScan scan;
  scan.angle_min = 0.0;
  scan.angle_increment = std::numbers::pi / 2;
  scan.ranges = {1.0, 2.0, std::numeric_limits<double>::infinity()};
  core::BeamDirections beams;
  const auto points = scanPoints(scan, lidar, beams);
  ASSERT_EQ(points.size(), 2u);  // the miss gives no point
  EXPECT_NEAR(points[0].x(), 1.055, 1e-12);
  EXPECT_NEAR(points[1].x(), 0.055, 1e-12);
  EXPECT_NEAR(points[1].y(), 2.0, 1e-12);
}

TEST(SafetyChecks, RearRegionSeesOnlyWhatIsDirectlyBehind) {
  nav::CostmapConfig c;
  c.rolling = true;
  nav::Costmap map(c, kBarnInscribed);
  map.recentre({0.0, 0.0});
  map.update();
  const core::Rect body = core::Rect::centred(0.508, 0.43);
  const core::Pose2 pose{0.0, 0.0, 0.0};
  const core::Rect strip = rearStrip(body, 0.1);
  EXPECT_FALSE(rearRegionBlocked(map, pose, strip, 0.0));
  map.markObstacle({0.5, 0.0});  // ahead: not in the strip
  map.update();
  EXPECT_FALSE(rearRegionBlocked(map, pose, strip, 0.0));
  map.markObstacle({-0.30, 0.1});  // 0.046 m behind the rear edge (-0.254): in the strip
  map.update();
  EXPECT_TRUE(rearRegionBlocked(map, pose, strip, 0.0));
}

TEST(SafetyChecks, BackTrackStripIsTheCodesTenByTenCellBoxExtended) {
  // The code drew the box on the 5 cm local costmap as (int(0.43 / 0.05) + 2) x int(0.508 / 0.05)
  // = 10 x 10 cells: its strip reaches 0.25 m to each side, past the 0.43 m robot's 0.215.
  nav::CostmapConfig c;
  c.rolling = true;
  nav::Costmap map(c, kBarnInscribed);
  map.recentre({0.0, 0.0});
  map.update();
  // The robot 2 cm off the cell grid: its 0.43 m strip reaches y = 0.235, the code's 0.27, and
  // the cell [-0.30, -0.25] x [0.25, 0.30] lies between.
  map.markObstacle({-0.28, 0.27});
  map.update();
  const InventecConfig config;
  const core::Pose2 pose{0.0, 0.02, 0.0};
  EXPECT_TRUE(rearRegionBlocked(map, pose, rearStrip(core::Rect::centred(config.roi_length, config.roi_width), config.roi_depth), 0.0));
  // A strip only as wide as the robot misses it.
  EXPECT_FALSE(rearRegionBlocked(map, pose, rearStrip(core::Rect::centred(0.508, 0.43), config.roi_depth), 0.0));
}

TEST(SafetyChecks, PublishedCostIsCostmap2dsZeroToHundredScale) {
  EXPECT_EQ(publishedCost(nav::kFreeCost), 0);
  EXPECT_EQ(publishedCost(1), 1);
  EXPECT_EQ(publishedCost(252), 98);
  EXPECT_EQ(publishedCost(nav::kInscribedCost), 99);
  EXPECT_EQ(publishedCost(nav::kLethalCost), 100);
}

// An empty rolling costmap around the origin with the team's local inflation (inscribed radius
// 0.085 m = 0.165 - 0.08 padding, scaling 1), reaching `inflation_radius` (theirs: 5 m).
nav::Costmap teamLocalCostmap(double inflation_radius) {
  nav::CostmapConfig c;
  c.rolling = true;
  c.inflation_radius = inflation_radius;
  c.cost_scaling_factor = 1.0;
  nav::Costmap map(c, 0.085);
  map.recentre({0.0, 0.0});
  map.update();
  return map;
}

TEST(SafetyChecks, RearWeightSeesObstaclesCloseBehindTheStripWithNoneInIt) {
  const core::Pose2 pose{0.0, 0.0, 0.0};
  const core::Rect strip = rearStrip(core::Rect::centred(0.508, 0.43), 0.1);  // x in [-0.354, -0.254]

  // A wall 0.07-0.17 m behind every strip cell: each costs more than 85 of 100.
  nav::Costmap near = teamLocalCostmap(5.0);
  for (double y = -0.4; y <= 0.4; y += 0.05) near.markObstacle({-0.42, y});
  near.update();
  EXPECT_FALSE(rearRegionBlocked(near, pose, strip, 0.0));  // nothing lethal in the strip
  EXPECT_TRUE(rearRegionBlocked(near, pose, strip, 0.85));

  // The same wall 0.65-0.75 m behind: the strip's mean cost is about 54 of 100.
  nav::Costmap far = teamLocalCostmap(5.0);
  for (double y = -0.4; y <= 0.4; y += 0.05) far.markObstacle({-1.0, y});
  far.update();
  EXPECT_FALSE(rearRegionBlocked(far, pose, strip, 0.85));
  EXPECT_TRUE(rearRegionBlocked(far, pose, strip, 0.5));
}

TEST(SafetyChecks, RearWeightLeavesCellsBeyondTheInflationOutOfTheMean) {
  // Inflation reaching only 0.3 m: of a 1 m wide region, the cells near an obstacle off its left
  // end cost 79-96 of 100, the rest 0 (not counted), so the mean is over the near ones.
  nav::Costmap map = teamLocalCostmap(0.3);
  map.markObstacle({-0.30, 0.58});
  map.update();
  const core::Rect wide{-0.354, -0.254, -0.5, 0.5};
  const core::Pose2 pose{0.0, 0.0, 0.0};
  EXPECT_TRUE(rearRegionBlocked(map, pose, wide, 0.8));
  EXPECT_FALSE(rearRegionBlocked(map, pose, wide, 0.0));  // nothing lethal in it
}

TEST(RotateCheck, SeesTheTurnedFootprintAndOnlyTheRearHalfTheTailSwingsInto) {
  nav::CostmapConfig c;
  c.rolling = true;
  c.width = 4.0;
  c.height = 4.0;
  nav::Costmap map(c, kBarnInscribed);
  map.recentre({0.0, 0.0});
  map.update();
  RotateCheck check;
  check.body = core::Rect::centred(0.508, 0.43);
  check.rear_weight = 0.0;  // lethal cells only (the weight has its own test)
  const core::Pose2 pose{0.0, 0.0, 0.0};
  EXPECT_FALSE(rotateCheckHit({}, map, pose, 1.0, check));

  // A return just past the front-left corner (0.254, 0.215) is outside the footprint; turned
  // 0.2 rad to the left the footprint's front edge reaches it, turned right it does not.
  const std::vector<Eigen::Vector2d> beside_corner{{0.20, 0.25}};
  EXPECT_FALSE(rotateCheckHit(beside_corner, map, pose, 0.0, check));
  EXPECT_TRUE(rotateCheckHit(beside_corner, map, pose, 1.0, check));
  EXPECT_FALSE(rotateCheckHit(beside_corner, map, pose, -1.0, check));

  // An obstacle in the strip 0.23-0.33 m behind, on the right: turning left swings the tail
  // into it, turning right swings it away.
  map.markObstacle({-0.30, -0.15});
  map.update();
  EXPECT_TRUE(rotateCheckHit({}, map, pose, 1.0, check));
  EXPECT_FALSE(rotateCheckHit({}, map, pose, -1.0, check));
  // The strip follows the robot's pose: turned half round, the obstacle is ahead.
  EXPECT_FALSE(rotateCheckHit({}, map, core::Pose2{0.0, 0.0, std::numbers::pi}, 1.0, check));
}

TEST(SafetyChecks, InscribedCellPointsAreObstacleCellsAndTheirInscribedRingInTheRobotFrame) {
  // The team's local costmap: 5 cm cells, inscribed radius 0.085 m (1.7 cells), so an obstacle
  // cell and its 8 neighbours (1 and 1.41 cells away) cost inscribed or more, the ring 2 cells
  // away does not.
  nav::Costmap map = teamLocalCostmap(5.0);
  map.markObstacle({-0.325, -0.125});  // the cell [-0.35, -0.30] x [-0.15, -0.10], behind on the right
  map.update();
  const core::Pose2 pose{0.0, 0.0, 0.0};
  std::vector<Eigen::Vector2d> points = inscribedCellPoints(map, pose, 1.0);
  ASSERT_EQ(points.size(), 9u);
  for (const Eigen::Vector2d& p : points) {
    EXPECT_LE(std::abs(p.x() + 0.325), 0.05 + 1e-9);
    EXPECT_LE(std::abs(p.y() + 0.125), 0.05 + 1e-9);
  }
  // Only the cells whose centres lie within the reach: the obstacle cell is 0.348 m away.
  EXPECT_TRUE(inscribedCellPoints(map, pose, 0.2).empty());
  // In the robot frame: turned half round, the same cells lie ahead on the left.
  points = inscribedCellPoints(map, core::Pose2{0.0, 0.0, std::numbers::pi}, 1.0);
  ASSERT_EQ(points.size(), 9u);
  for (const Eigen::Vector2d& p : points) {
    EXPECT_GT(p.x(), 0.27);
    EXPECT_GT(p.y(), 0.07);
  }
}

TEST(SafetyChecks, ATurnInPlaceRolledOutAgainstTheCostmapSeesWhatTheTailSwingsInto) {
  // An obstacle cell behind on the right, centred at (-0.225, -0.275): from the LiDAR (0.055 m
  // ahead of the centre) at -135.5 deg, just outside its 270 deg, so the scan has no point
  // there; the costmap remembers it. Its inscribed ring reaches to (-0.175, -0.225), outside the
  // footprint (|y| > 0.215).
  nav::Costmap map = teamLocalCostmap(5.0);
  map.markObstacle({-0.21, -0.26});
  map.update();
  const core::Pose2 pose{0.0, 0.0, 0.0};
  const core::Rect body = core::Rect::centred(0.508, 0.43);
  const std::vector<Eigen::Vector2d> remembered = inscribedCellPoints(map, pose, 0.5);
  // Turning left for 0.4 s swings the rear right corner (-0.254, -0.215) into the cells.
  EXPECT_TRUE(rolloutHit(remembered, body, {0.0, 1.0}, 0.02, 20));
  // The obstacle cells alone (without the inscribed ring) stay outside the whole turn.
  EXPECT_FALSE(rolloutHit({{-0.225, -0.275}}, body, {0.0, 1.0}, 0.02, 20));
  // Turning right swings it away.
  EXPECT_FALSE(rolloutHit(remembered, body, {0.0, -1.0}, 0.02, 20));
}

// ---- The controller: what act() sends in each state ----

struct Tick {
  InventecState state;
  core::Twist command;
};

// Ticks at the start of a BARN episode (the odom origin, heading +y, inside the default global
// costmap: x in [-3, 3], y in [-3, 12]) toward `goal`, every beam of every scan at `range`:
// the controller's state after each tick and what it sent.
std::vector<Tick> runTicks(InventecConfig config, double v, double w, Eigen::Vector2d goal, double range, int ticks) {
  InventecController controller(config, constantPolicy(v, w));
  EpisodeInfo info;
  info.start = {0.0, 0.0, std::numbers::pi / 2};
  info.goal = goal;
  controller.reset(info);
  core::LaserScan scan = uniformScan(info.lidar, range);
  std::vector<Tick> out;
  for (int k = 0; k < ticks; ++k) {
    Observation obs;
    obs.odom_pose = obs.scan_odom_pose = info.start;
    obs.time = k * controller.period();
    scan.stamp = obs.time;
    obs.scan = &scan;
    obs.goal = goal;
    const core::Twist command = controller.act(obs);
    out.push_back({controller.state(), command});
  }
  return out;
}

const double kNothing = std::numeric_limits<double>::infinity();
const Eigen::Vector2d kAhead(0.0, 10.0);
const Eigen::Vector2d kBehind(0.0, -2.5);

// A tick that changed the state sent (0, 0), as the code publishes on every transition.
void expectTransitionInto(const Tick& tick, InventecState state) {
  EXPECT_EQ(tick.state, state);
  EXPECT_EQ(tick.command.linear, 0.0);
  EXPECT_EQ(tick.command.angular, 0.0);
}

TEST(InventecController, StartsInLflhOnceItHasAPathAndSendsThePolicysCommand) {
  const std::vector<Tick> ticks = runTicks(codeConfig(), 0.5, 0.1, kAhead, kNothing, 3);
  expectTransitionInto(ticks[0], InventecState::Lflh);  // the first tick plans and starts
  EXPECT_EQ(ticks[2].state, InventecState::Lflh);
  EXPECT_FLOAT_EQ(static_cast<float>(ticks[2].command.linear), 0.5f);
  EXPECT_FLOAT_EQ(static_cast<float>(ticks[2].command.angular), 0.1f);
}

TEST(InventecController, ClipsTheSpeedToPointSevenAndBoostsToTwoOnlyAboveTheThresholdWithAClearFront) {
  // The default threshold (0.8, barnbench's policy) and the code's 1.0 (the published network).
  EXPECT_FLOAT_EQ(static_cast<float>(runTicks(codeConfig(), 0.75, 0.0, kAhead, kNothing, 3)[2].command.linear),
                  0.7f);
  EXPECT_EQ(runTicks(codeConfig(), 0.85, 0.0, kAhead, kNothing, 3)[2].command.linear, 2.0);
  InventecConfig published_scale = codeConfig();
  published_scale.boost_threshold = 1.0;
  EXPECT_FLOAT_EQ(static_cast<float>(runTicks(published_scale, 0.9, 0.0, kAhead, kNothing, 3)[2].command.linear),
                  0.7f);
  EXPECT_EQ(runTicks(published_scale, 1.5, 0.0, kAhead, kNothing, 3)[2].command.linear, 2.0);
  // Everything 1.4 m away: nothing in reach of the checks, but not clear for a boost (1.5 m).
  InventecConfig no_hard_turn = codeConfig();
  no_hard_turn.heading_limit_deg = 180.0;
  no_hard_turn.heading_tolerance_deg = 180.0;
  const std::vector<Tick> near = runTicks(no_hard_turn, 1.5, 0.0, kAhead, 1.4, 3);
  EXPECT_EQ(near[2].state, InventecState::Lflh);
  EXPECT_FLOAT_EQ(static_cast<float>(near[2].command.linear), 0.7f);
}

TEST(InventecController, HardTurnsTowardAGoalBehindAtItsTurnRateLimit) {
  const std::vector<Tick> ticks = runTicks(codeConfig(), 0.5, 0.0, kBehind, kNothing, 4);
  // Planned, then (LfLH) the path points 180 degrees away.
  expectTransitionInto(ticks[1], InventecState::HardTurn);
  // Then it turns in place at 1.5 x 180 degrees, clipped to max_turn_rate 2.
  EXPECT_EQ(ticks[2].state, InventecState::HardTurn);
  EXPECT_EQ(ticks[2].command.linear, 0.0);
  EXPECT_EQ(std::abs(ticks[2].command.angular), 2.0);
}

TEST(InventecController, BacktracksInsteadOfSendingACommandThatWouldHit) {
  // A ring of returns 0.3 m from the sensor: 0.5 m/s for 0.2 s puts the 0.42 x 0.33 rectangle
  // (+ 0.02 m) 0.1 m further, into the ring ahead.
  InventecConfig no_hard_turn = codeConfig();
  no_hard_turn.heading_limit_deg = 180.0;
  no_hard_turn.heading_tolerance_deg = 180.0;
  const std::vector<Tick> ticks = runTicks(no_hard_turn, 0.5, 0.0, kAhead, 0.3, 3);
  expectTransitionInto(ticks[1], InventecState::BackTrack);
  // In the open the same config drives on.
  EXPECT_EQ(runTicks(no_hard_turn, 0.5, 0.0, kAhead, kNothing, 3)[2].state, InventecState::Lflh);
}

}  // namespace
}  // namespace barn::controllers
