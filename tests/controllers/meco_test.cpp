// The MECO Barners' corridor stack: the fitter's openings and growth, the manager's tree, the
// motion planner's manoeuvres and the controller's filter, against worked examples.
#include "barn/controllers/meco.hpp"

#include <cmath>
#include <limits>
#include <numbers>
#include <vector>

#include <gtest/gtest.h>

#include "scan_fixtures.hpp"

namespace barn::controllers {
namespace {

constexpr double kInf = std::numeric_limits<double>::infinity();
constexpr double kPi = std::numbers::pi;
using V = Eigen::Vector2d;

MecoCorridor corridor(V center, double heading, double length, double width, V growth) {
  return {center, heading, length, width, growth};
}

// ---------------------------------------------------------------------------------------------
// Corridor geometry

TEST(MecoCorridor, CornersComeInTheTeamsOrderAndEdgesMoveOutward) {
  // Facing +y, 2 long, 1 wide, centred on (0, 1): front right (0.5, 2), back right (0.5, 0),
  // back left (-0.5, 0), front left (-0.5, 2).
  MecoCorridor c = corridor({0, 1}, kPi / 2, 2.0, 1.0, {0, 0});
  const auto k = c.corners();
  EXPECT_NEAR((k[0] - V(0.5, 2)).norm(), 0.0, 1e-12);
  EXPECT_NEAR((k[1] - V(0.5, 0)).norm(), 0.0, 1e-12);
  EXPECT_NEAR((k[2] - V(-0.5, 0)).norm(), 0.0, 1e-12);
  EXPECT_NEAR((k[3] - V(-0.5, 2)).norm(), 0.0, 1e-12);
  EXPECT_NEAR(c.maxCornerY(), 2.0, 1e-12);
  EXPECT_NEAR((c.frontPoint(0.3) - V(0, 1.7)).norm(), 0.0, 1e-12);
  EXPECT_NEAR((c.backPoint(0.3) - V(0, 0.3)).norm(), 0.0, 1e-12);
  // The left edge (-x) out by 0.4: width 1.4, centre 0.2 to the left.
  c.moveEdge(MecoEdge::Left, 0.4);
  EXPECT_NEAR(c.width, 1.4, 1e-12);
  EXPECT_NEAR((c.center - V(-0.2, 1)).norm(), 0.0, 1e-12);
  EXPECT_TRUE(c.contains({-0.9, 1.0}));
  EXPECT_FALSE(c.contains({-0.91, 1.0}));
  EXPECT_TRUE(c.contains({-0.9005, 1.0}, 1e-3));
}

// ---------------------------------------------------------------------------------------------
// Fitter: openings

TEST(MecoFitter, FindsAnOpeningWhereTheArcsAtTheCandidateRangeExceedSeventyCentimetres) {
  // Increment 0.012 rad, every beam at 10 m: arcs of 0.12 m. From 0.06 the opening grows by
  // 0.12 per beam: 0.18, 0.30, 0.42, 0.54, 0.66, 0.78 > 0.7 at beam 5; candidate beam 0 (the
  // first of the equal ranges): direction (5 + 0) / 2.
  const MecoFitterConfig config;
  const std::vector<double> open(12, 10.0);
  ASSERT_TRUE(openingInSector(open, 0.012, config).has_value());
  EXPECT_DOUBLE_EQ(*openingInSector(open, 0.012, config), 2.5);

  // A post at beam 3 (1 m): its own arcs (0.012 m) never reach 0.7. At 10 m: 0.18, 0.30, 0.42,
  // then the post adds 0.06 (0.48 <= 0.6) and the opening starts again: 0.12, 0.24, ... 0.72 at
  // beam 9: direction (9 + 0) / 2.
  std::vector<double> post = open;
  post[3] = 1.0;
  EXPECT_DOUBLE_EQ(*openingInSector(post, 0.012, config), 4.5);

  // A post at beam 5: 0.66 after beam 4, the post's half arc gives 0.72 > 0.6 = 2 x 0.25 + 0.1:
  // found at beam 5 under the narrower rule.
  std::vector<double> late = open;
  late[5] = 1.0;
  EXPECT_DOUBLE_EQ(*openingInSector(late, 0.012, config), 2.5);

  // Too few beams for 0.7 m at any range, or every range below 0.1 m: none.
  EXPECT_FALSE(openingInSector(std::vector<double>(5, 10.0), 0.012, config).has_value());
  EXPECT_FALSE(openingInSector(std::vector<double>(12, 0.05), 0.012, config).has_value());
}

TEST(MecoFitter, OpenScanGivesSeventeenDirectionsWithTheTeamsHalfSectorOffsets) {
  // 720 beams, inf everywhere (read as 10 m): arcs of 10 x 0.0065541 = 0.0655 m; the opening
  // passes 0.7 m after 11 beams (0.0328 + 11 x 0.0655 = 0.754), so each sector's direction is
  // at (10 + 0) / 2 = 5 beams from its first beam. The central 480 beams start at beam 120.
  const core::LidarConfig lidar;
  const core::LaserScan scan = uniformScan(lidar, kInf);
  const auto at = [&](double beam) { return scan.angle_min + beam * scan.angle_increment; };
  MecoFitterConfig config;
  const std::vector<double> team = openingDirections(scan, config);
  ASSERT_EQ(team.size(), 17u);  // 8 plain + 9 shifted
  // Plain sector 1 (beams 180-239): the team's code starts it half a sector (30 beams) early.
  EXPECT_NEAR(team[1], at(120 + 60 - 30 + 5), 1e-12);
  // Shifted sector 8 (the last half sector, beams 570-599): started half a sector late, at 600.
  EXPECT_NEAR(team[16], at(120 + 480 + 5), 1e-12);
  config.team_sector_angles = false;
  const std::vector<double> exact = openingDirections(scan, config);
  EXPECT_NEAR(exact[1], at(120 + 60 + 5), 1e-12);
  EXPECT_NEAR(exact[16], at(120 + 450 + 5), 1e-12);
  EXPECT_NEAR(exact[0], team[0], 1e-12);  // the first sectors carry no offset
}

TEST(MecoFitter, TakesEveryFourthReturnPlacedAtTheSensor) {
  // Returns at beams 0, 2, 4, ..., 718 (360 of them): the 4th, 8th, ... are beams 6, 14, ...:
  // 90 points. Beam 6 at 2 m, seen from the sensor 0.055 m ahead of the centre.
  const core::LidarConfig lidar;
  core::LaserScan scan = uniformScan(lidar, kInf);
  for (std::size_t i = 0; i < scan.ranges.size(); i += 2) scan.ranges[i] = 2.0;
  const std::vector<V> points = scanPoints(scan, lidar, 4);
  ASSERT_EQ(points.size(), 90u);
  const double a = scan.angle(6);
  EXPECT_NEAR((points[0] - V(0.055 + 2 * std::cos(a), 2 * std::sin(a))).norm(), 0.0, 1e-12);
}

// ---------------------------------------------------------------------------------------------
// Fitter: growth

TEST(MecoFitter, GrowsAChildAgainstHandPlacedPoints) {
  // A child along the robot's heading (robot frame), the robot facing +y in the odom frame, so
  // both sides may grow. Points: (2.25, 0) ahead, (0.3, -0.65) right, (0.3, 0.95) left.
  // Front from 0.5: 1.0, 1.5, 2.0, 2.5 takes in (2.25, 0); back 0.1 at a time: 2.4, 2.3, 2.2.
  // Right from -0.3: -0.8 takes in (0.3, -0.65); back: -0.7, -0.6. Left from 0.3: 0.8, 1.3
  // takes in (0.3, 0.95); back: 1.2, 1.1, 1.0, 0.9. So x in [-0.5, 2.2], y in [-0.6, 0.9]:
  // length 2.7, width 1.5, centre (0.85, 0.15); not wider than long, so not turned.
  const MecoFitterConfig config;
  const std::vector<V> points = {{2.25, 0.0}, {0.3, -0.65}, {0.3, 0.95}};
  MecoCorridor child = corridor({0, 0}, 0.0, 1.0, 0.6, {0, 0});
  growChild(child, points, {0.0, 0.0, kPi / 2}, config);
  EXPECT_NEAR(child.length, 2.7, 1e-9);
  EXPECT_NEAR(child.width, 1.5, 1e-9);
  EXPECT_NEAR((child.center - V(0.85, 0.15)).norm(), 0.0, 1e-9);
  EXPECT_NEAR(child.heading, 0.0, 1e-12);
}

TEST(MecoFitter, StopsGrowingForwardOnceACornerReachesElevenMetresInY) {
  // Robot at odom (0, 9.2) facing +y, no points. The front edge (robot x 0.5, odom y 9.7) steps
  // to 10.2, 10.7, then 11.2 >= 11: it stops there (no point to back off from), at robot x 2.0:
  // length 2.5 instead of the 3.5 five steps would give.
  const MecoFitterConfig config;
  MecoCorridor c = corridor({0, 0}, 0.0, 1.0, 0.6, {0, 0});
  growCorridorEdge(c, MecoEdge::Front, {}, {0.0, 9.2, kPi / 2}, 1.0, config);
  EXPECT_NEAR(c.length, 2.5, 1e-9);
  // A corridor with a point inside does not grow at all.
  MecoCorridor blocked = corridor({0, 0}, 0.0, 1.0, 0.6, {0, 0});
  const std::vector<V> inside = {{0.2, 0.1}};
  growCorridorEdge(blocked, MecoEdge::Front, inside, {0.0, 0.0, kPi / 2}, 1.0, config);
  EXPECT_DOUBLE_EQ(blocked.length, 1.0);
}

TEST(MecoFitter, TurnsACorridorWiderThanLongAQuarterAwayFromItsTilt) {
  // Robot facing +x (odom), child straight ahead: heading east, only the left side (toward +y)
  // grows. A wall point at (0.65, 0): front 1.0 takes it in, back to 0.9, 0.8, 0.7, 0.6: length
  // 1.1. Left: five free steps, 0.3 + 2.5 = 2.8: width 3.1 > 1.1. Tilt 0 (not > 0): turned
  // counter-clockwise, to face +y: length 3.1, width 1.1.
  const MecoFitterConfig config;
  const std::vector<V> points = {{0.65, 0.0}};
  MecoCorridor child = corridor({0, 0}, 0.0, 1.0, 0.6, {0, 0});
  growChild(child, points, {0.0, 0.0, 0.0}, config);
  EXPECT_NEAR(child.length, 3.1, 1e-9);
  EXPECT_NEAR(child.width, 1.1, 1e-9);
  EXPECT_NEAR(child.heading, kPi / 2, 1e-12);
}

TEST(MecoFitter, InTheOpenPublishesTheFinalCorridorFirst) {
  // Nothing seen: the final corridor (aimed at the goal straight ahead) grows its front in 1.5 m
  // steps, five of them: front at 0.5 + 7.5 = 8 m (odom y 8 < 11). The children reach 3 m.
  // Best by largest corner y: the final corridor, 1.5 wide, 8.5 long, centred 3.75 m ahead.
  const core::LidarConfig lidar;
  const core::LaserScan scan = uniformScan(lidar, kInf);
  const std::vector<MecoCorridor> best = fitCorridors(scan, lidar, {0.0, 0.0, kPi / 2}, {0.0, 10.0}, MecoFitterConfig{});
  ASSERT_EQ(best.size(), 2u);
  EXPECT_NEAR(best[0].maxCornerY(), 8.0, 1e-9);
  EXPECT_NEAR(best[0].width, 1.5, 1e-12);
  EXPECT_NEAR(best[0].length, 8.5, 1e-9);
  EXPECT_NEAR((best[0].center - V(0, 3.75)).norm(), 0.0, 1e-9);
  EXPECT_NEAR(best[0].heading, kPi / 2, 1e-12);
  EXPECT_NEAR((best[0].growth_center - V(0, 0)).norm(), 0.0, 1e-12);
  EXPECT_LT(best[1].maxCornerY(), best[0].maxCornerY());
}

// ---------------------------------------------------------------------------------------------
// Manager

TEST(MecoManager, ImprovementIsHowFarTheChildReachesBeyondItsParent) {
  // Parent: facing +y, 2 x 1, centred on (0, 1) (front at y = 2, left side at x = -0.5).
  const MecoCorridor parent = corridor({0, 1}, kPi / 2, 2.0, 1.0, {0, 0});
  // Straight on from the parent's centre to y = 4: 4 - 2 = 2.
  EXPECT_NEAR(corridorImprovement(parent, corridor({0, 2.5}, kPi / 2, 3.0, 0.6, {0, 1})), 2.0, 1e-12);
  // Due west from the parent's centre to x = -3: out through the left side (the heading passes
  // the front-left corner, atan2(0.5, 1) = 27 deg < 90 deg): 3 - 0.5 = 2.5.
  EXPECT_NEAR(corridorImprovement(parent, corridor({-1.5, 1}, kPi, 3.0, 0.6, {0, 1})), 2.5, 1e-12);
  // To y = 2.2 only: 0.2 < 0.4, stuck.
  EXPECT_NEAR(corridorImprovement(parent, corridor({0, 1.6}, kPi / 2, 1.2, 0.6, {0, 1})), 0.2, 1e-12);
}

TEST(MecoManager, SignificantlyDifferentNeedsBothFarCornersAndAnotherHeading) {
  const MecoCorridor a = corridor({0, 1}, kPi / 2, 2.0, 1.0, {0, 0});
  // Shifted 1 m in x: the front corners are 1 + 1 = 2 m apart, but the headings are equal.
  const MecoCorridor b = corridor({1, 1}, kPi / 2, 2.0, 1.0, {0, 0});
  EXPECT_FALSE(significantlyDifferent(a, b, 1.0, kPi / 8));
  EXPECT_TRUE(significantlyDifferent(a, b, 1.0, -1.0));  // any heading differs
  EXPECT_FALSE(significantlyDifferent(a, b, 2.0, -1.0)); // 2 is not > 2
}

TEST(MecoManager, TakesTheRootThenAChildReachingHigherAtOnce) {
  // A spans y 0..3, B (same heading) y 0..5, both fitted at the origin. A is the root; B reaches
  // 2 m beyond it (not stuck), 5 > 3 + 0.2 gives it quality 1, so the manager moves on to it in
  // the same cycle, long before A's end.
  MecoManager manager{MecoManagerConfig{}};
  const MecoCorridor a = corridor({0, 1.5}, kPi / 2, 3.0, 1.0, {0, 0});
  const MecoCorridor b = corridor({0, 2.5}, kPi / 2, 5.0, 1.0, {0, 0});
  const std::vector<MecoCorridor> fitted = {a, b};
  manager.receive(fitted);
  const std::vector<MecoMessage> out = manager.tick(0.0, {0, 0}, {0, 10});
  ASSERT_EQ(out.size(), 2u);
  EXPECT_EQ(out[0].kind, MecoMessageKind::Next);
  EXPECT_NEAR(out[0].corridors[0].maxCornerY(), 3.0, 1e-12);
  EXPECT_EQ(out[1].kind, MecoMessageKind::Next);
  EXPECT_NEAR(out[1].corridors[0].maxCornerY(), 5.0, 1e-12);
  EXPECT_EQ(manager.current(), 1);
  EXPECT_DOUBLE_EQ(manager.nodes()[1].quality, 1.0);
  EXPECT_EQ(manager.phase(), MecoPhase::Exploring);
}

TEST(MecoManager, ACorridorHoldingTheGoalIsPublishedAsFinal) {
  MecoManager manager{MecoManagerConfig{}};
  const std::vector<MecoCorridor> root = {corridor({0, 1.5}, kPi / 2, 3.0, 1.0, {0, 0})};
  manager.receive(root);
  manager.tick(0.0, {0, 0}, {0, 10});
  // Reaching y = 10.5 from the origin: holds (0, 10).
  const std::vector<MecoCorridor> reach = {corridor({0, 5.25}, kPi / 2, 10.5, 1.5, {0, 0})};
  manager.receive(reach);
  const std::vector<MecoMessage> out = manager.tick(0.5, {0, 0}, {0, 10});
  ASSERT_EQ(out.size(), 1u);
  EXPECT_EQ(out[0].kind, MecoMessageKind::Final);
  EXPECT_EQ(manager.phase(), MecoPhase::GoalInSight);
  EXPECT_TRUE(manager.tick(0.6, {0, 0}, {0, 10}).empty());
}

TEST(MecoManager, BacksOutOfADeadEndAfterWaiting) {
  // Root A (y 0..3) and child B (y 0..5, taken at once). The robot stands at B's end, (0, 4.8),
  // and nothing new arrives. From t = 10: the end wait (0.5 s) runs, no child to take, so the
  // backtracking clock started at t = 10 fires on the first tick past 1.5 s: t = 11.6 (tick 16).
  MecoManager manager{MecoManagerConfig{}};
  const MecoCorridor a = corridor({0, 1.5}, kPi / 2, 3.0, 1.0, {0, 0});
  const MecoCorridor b = corridor({0, 2.5}, kPi / 2, 5.0, 1.0, {0, 0});
  const std::vector<MecoCorridor> fitted = {a, b};
  manager.receive(fitted);
  manager.tick(0.0, {0, 0}, {0, 10});
  int fired = -1;
  MecoMessage backtrack;
  for (int k = 0; k < 30 && fired < 0; ++k) {
    for (const MecoMessage& m : manager.tick(10.0 + 0.1 * k, {0, 4.8}, {0, 10}))
      if (m.kind == MecoMessageKind::Backtrack) {
        fired = k;
        backtrack = m;
      }
    if (fired < 0) {
      EXPECT_EQ(manager.phase(), MecoPhase::WaitingToBacktrack) << k;
    }
  }
  EXPECT_EQ(fired, 16);
  // The route: the dead end, then the corridor returned to. B is an orphan now.
  ASSERT_EQ(backtrack.corridors.size(), 2u);
  EXPECT_NEAR(backtrack.corridors[0].maxCornerY(), 5.0, 1e-12);
  EXPECT_NEAR(backtrack.corridors[1].maxCornerY(), 3.0, 1e-12);
  EXPECT_EQ(manager.current(), manager.root());
  EXPECT_EQ(manager.orphanage().size(), 1u);
  EXPECT_TRUE(manager.nodes()[0].children.empty());
  EXPECT_EQ(manager.phase(), MecoPhase::Backtracking);
  // Still outside A (y > 3): backtracking; inside: done.
  manager.tick(11.7, {0, 4.0}, {0, 10});
  EXPECT_EQ(manager.phase(), MecoPhase::Backtracking);
  manager.tick(11.8, {0, 2.0}, {0, 10});
  EXPECT_NE(manager.phase(), MecoPhase::Backtracking);
}

// ---------------------------------------------------------------------------------------------
// Motion planner

MecoPlannerParams teamParams() { return plannerParams(MecoNavigatorConfig{}); }

TEST(MecoMotion, FacingTheGoalPointItDrivesStraightThere) {
  // Corridor facing +y, 4 x 1, from y 0 to 4: goal point 0.3 short of the front, (0, 3.7). The
  // robot at the origin faces it exactly: one straight segment, 3.7 / 0.5 = 7.4 s.
  const MecoCorridor c = corridor({0, 2}, kPi / 2, 4.0, 1.0, {0, 0});
  const MecoManoeuvre m = planSingle(c, {0.0, 0.0, kPi / 2}, teamParams());
  ASSERT_EQ(m.segments.size(), 1u);
  EXPECT_DOUBLE_EQ(m.segments[0].linear, 0.5);
  EXPECT_DOUBLE_EQ(m.segments[0].angular, 0.0);
  EXPECT_NEAR(m.segments[0].duration, 7.4, 1e-12);
}

TEST(MecoMotion, FacingAcrossTheCorridorItArcsOnTheAlignmentRadiusThenGoesStraight) {
  // Same corridor, the robot at the origin facing +x: 90 deg off the goal (0, 3.7), more than
  // atan((0.5 - 0.215 - 0.1) / 3.7) = 2.9 deg. It turns left (the goal is to its left). The
  // alignment radius: (0.5 - 0.315 + 0) / (1 - cos 90 deg) = 0.185 m (< 0.5 / 0.3). Circle
  // centre (0, 0.185); tangent to the goal: D = (0, 3.515), L = sqrt(3.515^2 - 0.185^2) =
  // 3.51013, heading 90 deg + atan2(0.185, L) = 1.623450 rad. Arc: v = 0.185 x 0.3 = 0.0555,
  // w = 0.3, 1.623450 / 0.3 = 5.41150 s; straight: 3.51013 / 0.5 = 7.02026 s.
  const MecoCorridor c = corridor({0, 2}, kPi / 2, 4.0, 1.0, {0, 0});
  const MecoManoeuvre m = planSingle(c, {0.0, 0.0, 0.0}, teamParams());
  ASSERT_EQ(m.segments.size(), 2u);
  const double length = std::sqrt(3.515 * 3.515 - 0.185 * 0.185);
  const double heading = kPi / 2 + std::atan2(0.185, length);
  EXPECT_NEAR(m.segments[0].linear, 0.0555, 1e-12);
  EXPECT_NEAR(m.segments[0].angular, 0.3, 1e-12);
  EXPECT_NEAR(m.segments[0].duration, heading / 0.3, 1e-9);
  EXPECT_NEAR(m.segments[1].linear, 0.5, 1e-12);
  EXPECT_NEAR(m.segments[1].angular, 0.0, 1e-12);
  EXPECT_NEAR(m.segments[1].duration, length / 0.5, 1e-9);
  // And it ends on the goal point.
  EXPECT_NEAR((m.poses.back().position() - V(0, 3.7)).norm(), 0.0, 1e-9);
}

TEST(MecoMotion, AGoalInsideTheTurningCircleIsFacedOnTheSpot) {
  // The robot at (0, 3.5) facing -x; the goal point (0, 3.7) lies 90 deg to its right. The
  // alignment radius: the heading is 90 deg left of the corridor's, so the arc drifts left:
  // (0.5 - 0.315 - 0) / (1 - cos 90 deg) = 0.185 m. The right-hand circle's centre, (0, 3.685),
  // is 0.015 m from the goal point: inside, so turn on the spot 90 deg right (-0.3 rad/s for
  // (pi / 2) / 0.3 s), then 0.2 m straight (0.4 s).
  const MecoCorridor c = corridor({0, 2}, kPi / 2, 4.0, 1.0, {0, 0});
  const MecoManoeuvre m = planSingle(c, {0.0, 3.5, kPi}, teamParams());
  ASSERT_EQ(m.segments.size(), 2u);
  EXPECT_DOUBLE_EQ(m.segments[0].linear, 0.0);
  EXPECT_NEAR(m.segments[0].angular, -0.3, 1e-12);
  EXPECT_NEAR(m.segments[0].duration, (kPi / 2) / 0.3, 1e-9);
  EXPECT_NEAR(m.segments[1].duration, 0.2 / 0.5, 1e-9);
}

TEST(MecoMotion, FindsTheInnerCornerOfATurn) {
  // An L: up from (0, 0) to y = 2 (x in [-0.5, 0.5]), then west along y in [1, 2] to x = -2.
  // The meeting points in both: (0, 2) (the second's back edge on the first's front) and
  // (-0.5, 1) (the second's left edge, y = 1, on the first's left edge): the inner corner is
  // the one farther left.
  const MecoCorridor up = corridor({0, 1}, kPi / 2, 2.0, 1.0, {0, 0});
  const MecoCorridor west = corridor({-1, 1.5}, kPi, 2.0, 1.0, {0, 1.5});
  const auto corner = cornerPoint(up, west, true);
  ASSERT_TRUE(corner.has_value());
  EXPECT_NEAR((*corner - V(-0.5, 1)).norm(), 0.0, 1e-12);
}

TEST(MecoMotion, TurnsIntoTheNextCorridorAndEndsOnItsGoalPoint) {
  // A wider L so the corner circle (R = 0.5 / 0.3) fits: up 6 m, then west.
  const MecoCorridor up = corridor({0, 3}, kPi / 2, 6.0, 2.0, {0, 0});
  const MecoCorridor west = corridor({-3, 5}, kPi, 6.0, 2.0, {0, 5});
  const core::Pose2 start{0.0, 0.5, kPi / 2};
  const MecoManoeuvre m = plan(up, &west, start, teamParams());
  ASSERT_GE(m.segments.size(), 3u);
  // Aligned with the first corridor: the alignment arc turns the corner's way (left), short;
  // then the tangent, then left around the corner.
  EXPECT_NEAR(m.segments[0].angular, 0.3, 1e-12);
  EXPECT_LT(m.segments[0].duration, 1.0);
  EXPECT_GT(m.segments[1].duration, 0.0);
  EXPECT_NEAR(m.segments[2].angular, 0.3, 1e-12);
  EXPECT_NEAR((m.poses.back().position() - west.frontPoint(0.3)).norm(), 0.0, 1e-6);
}

TEST(MecoMotion, PastTheCornerItReversesFirst) {
  // The robot at (0.5, 5) facing +y is past the L's inner corner (-1, 4) (bearing -146 deg, more
  // than 90 deg off its heading) and not yet in the second corridor (x > 0): it reverses along
  // the first toward (0, 0.8 x |(0, 0) - (-1, 4)|) = (0, 3.30), then turns in; the manoeuvre
  // still ends on the goal point.
  const MecoCorridor up = corridor({0, 3}, kPi / 2, 6.0, 2.0, {0, 0});
  const MecoCorridor west = corridor({-3, 5}, kPi, 6.0, 2.0, {0, 5});
  const MecoManoeuvre m = plan(up, &west, {0.5, 5.0, kPi / 2}, teamParams());
  ASSERT_FALSE(m.segments.empty());
  bool reversed = false;
  for (const MecoSegment& s : m.segments) reversed = reversed || s.linear < 0.0;
  EXPECT_TRUE(reversed);
  EXPECT_NEAR((m.poses.back().position() - west.frontPoint(0.3)).norm(), 0.0, 1e-6);
}

// ---------------------------------------------------------------------------------------------
// Navigator and controller

TEST(MecoNavigator, BacksOutOnceWithNegatedSpeedsThenRestartsFromTheCorridorReturnedTo) {
  MecoNavigator navigator{MecoNavigatorConfig{}};
  const MecoCorridor a = corridor({0, 1.5}, kPi / 2, 3.0, 1.0, {0, 0});
  const MecoCorridor b = corridor({0, 2.5}, kPi / 2, 5.0, 1.0, {0, 0});
  const std::vector<MecoMessage> back = {{MecoMessageKind::Backtrack, {b, a}}};
  navigator.receive(back);
  const auto m = navigator.tick({0.0, 4.8, kPi / 2}, {0, 10});
  ASSERT_TRUE(m.has_value());
  ASSERT_FALSE(m->segments.empty());
  // Robot at (0, 4.8) facing +y, backing to A's front moved 0.1 back, (0, 2.9): straight back,
  // 1.9 m at 0.75 x 0.5 m/s.
  ASSERT_EQ(m->segments.size(), 1u);
  EXPECT_NEAR(m->segments[0].linear, -0.375, 1e-12);
  EXPECT_NEAR(m->segments[0].duration, 1.9 / 0.375, 1e-9);
  EXPECT_FALSE(navigator.tick({0.0, 4.0, kPi / 2}, {0, 10}).has_value());  // planned once
  const MecoCorridor c = corridor({-1, 2.5}, kPi, 2.0, 1.0, {0, 2.5});
  const std::vector<MecoMessage> next = {{MecoMessageKind::Next, {c}}};
  navigator.receive(next);
  ASSERT_EQ(navigator.corridors().size(), 2u);
  EXPECT_NEAR(navigator.corridors()[0].maxCornerY(), 3.0, 1e-12);
  EXPECT_FALSE(navigator.backtracking());
}

TEST(MecoController, StretchesAShortFastFirstSegmentAndExpandsAtOneHundredHertz) {
  const MecoConfig config;
  std::vector<MecoSegment> segments = {{0.5, 0.0, 0.4}, {0.0, 0.3, 2.0}};
  stretchFirstSegment(segments, config);
  EXPECT_DOUBLE_EQ(segments[0].duration, 1.0);
  std::vector<MecoSegment> keep = {{0.5, 0.0, 0.4}, {0.5, 0.0, 1.0}};  // the next is not slow
  stretchFirstSegment(keep, config);
  EXPECT_DOUBLE_EQ(keep[0].duration, 0.4);
  // int(0.4 x 100) = 40, int(0.29 x 100) = int(28.999999999999996) = 28 (Python's truncation).
  const std::vector<MecoSegment> two = {{0.5, 0.0, 0.4}, {0.0, 0.3, 0.29}};
  const std::vector<core::Twist> ticks = expandSegments(two, 100.0);
  ASSERT_EQ(ticks.size(), 68u);
  EXPECT_DOUBLE_EQ(ticks[39].linear, 0.5);
  EXPECT_DOUBLE_EQ(ticks[40].angular, 0.3);
}

TEST(MecoController, FiltersAStepWithGainFivePercentAndStopsSlowTurns) {
  const MecoConfig config;
  // A step to 0.5 m/s from rest: v_n = 0.5 (1 - 0.95^n): 0.025 after one tick, 0.320757 after 20.
  core::Twist cmd;
  cmd = filterCommand(cmd, {0.5, 0.0}, config);
  EXPECT_NEAR(cmd.linear, 0.025, 1e-15);
  for (int n = 1; n < 20; ++n) cmd = filterCommand(cmd, {0.5, 0.0}, config);
  EXPECT_NEAR(cmd.linear, 0.5 * (1.0 - std::pow(0.95, 20)), 1e-12);
  EXPECT_NEAR(cmd.linear, 0.320757, 1e-6);
  // Turning at 0.3 rad/s while creeping at 0.05 m/s: |w| > 0.2 and v < 0.1, so v = 0; the zero
  // is what is sent and what the next tick filters from: 0.05 x 0.05 = 0.0025, again 0.
  core::Twist turn = filterCommand({0.05, 0.3}, {0.05, 0.3}, config);
  EXPECT_DOUBLE_EQ(turn.linear, 0.0);
  EXPECT_NEAR(turn.angular, 0.3, 1e-15);
  turn = filterCommand(turn, {0.05, 0.3}, config);
  EXPECT_DOUBLE_EQ(turn.linear, 0.0);
  // Reversing counts as slow too (v < 0.1).
  EXPECT_DOUBLE_EQ(filterCommand({-0.3, 0.25}, {-0.3, 0.25}, config).linear, 0.0);
}

TEST(MecoController, InTheOpenItDrivesStraightForTheFinalCorridorsGoalPoint) {
  // Nothing seen: the root is the final corridor (front at y 8), the goal point (0, 7.7) lies
  // dead ahead, so the manoeuvre is one straight segment at 0.5 m/s; through the filter the
  // speed after 60 ticks is 0.5 (1 - 0.95^60) and the turn rate 0.
  MecoController controller{MecoConfig{}};
  EpisodeInfo info;
  info.start = {0.0, 0.0, kPi / 2};
  info.goal = {0.0, 10.0};
  controller.reset(info);
  const core::LaserScan scan = uniformScan(info.lidar, kInf);
  Observation obs;
  obs.scan = &scan;
  obs.odom_pose = obs.scan_odom_pose = info.start;
  obs.goal = info.goal;
  core::Twist cmd;
  for (int n = 0; n < 60; ++n) {
    obs.time = 0.01 * n;
    cmd = controller.act(obs);
  }
  EXPECT_NEAR(cmd.linear, 0.5 * (1.0 - std::pow(0.95, 60)), 1e-12);
  EXPECT_NEAR(cmd.angular, 0.0, 1e-12);
  EXPECT_EQ(controller.stateLabel(), "Exploring");
  EXPECT_DOUBLE_EQ(controller.period(), 0.01);
}

TEST(MecoConfig, RejectsNodeRatesThatDoNotDivideTheControllerRate) {
  MecoConfig config;
  config.fitter.rate = 3.0;  // 100 / 3 is not whole
  config.navigator.max_turn_rate = 0.0;
  core::Errors errors;
  validate(config, errors, "meco");
  ASSERT_EQ(errors.messages().size(), 2u);
  EXPECT_NE(errors.messages()[0].find("meco.navigator.max_turn_rate"), std::string::npos);
  EXPECT_NE(errors.messages()[1].find("meco.fitter.rate"), std::string::npos);
}

}  // namespace
}  // namespace barn::controllers
