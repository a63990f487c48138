// graph_navigation's local planner as UT AMRL ran it: an arc's free path length and clearance
// against points, the linear evaluator, 1-D time-optimal control and the turn in place.
#include "barn/controllers/arc_planner.hpp"

#include <cmath>
#include <numbers>
#include <vector>

#include <gtest/gtest.h>

namespace barn::controllers {
namespace {

using V = Eigen::Vector2d;

// The team's box: front 0.25 + 0.05 = 0.30 ahead of the base link, half width 0.22 + 0.05 = 0.27.
const ArcPlannerConfig kTeam;
constexpr double kDecel = 0.5;  // [m/s^2]

// ---- Free path length ----

TEST(ArcFreePath, APointOnTheCentreLineIsHitByTheFrontAtTheAnalyticAngle) {
  // Curvature 1: turn centre (0, 1). A point on the centre line a quarter turn on, (1, 1),
  // radius 1, beyond the inner front corner's radius |(0.3, 0.27) - (0, 1)| = 0.789: the front
  // face reaches it when it is asin(0.30 / 1) = 0.3047 rad ahead of the robot's radial, after
  // a turn of pi/2 - 0.3047 = 1.2661 rad, i.e. 1.2661 m along the arc.
  // The target (3, 1.5) is atan2(3, 0.5) = 1.406 rad round, so the arc starts at 1.406 m.
  const std::vector<V> points = {{1.0, 1.0}};
  const Arc arc = evaluateArc(1.0, {3.0, 1.5}, points, 0.0, kDecel, kTeam);
  EXPECT_NEAR(arc.length, std::numbers::pi / 2.0 - std::asin(0.3), 1e-12);
  // It ends there: r (sin a, 1 - cos a) with a = 1.2661.
  EXPECT_NEAR(arc.end.x(), std::sin(arc.length), 1e-12);
  EXPECT_NEAR(arc.end.y(), 1.0 - std::cos(arc.length), 1e-12);
}

TEST(ArcFreePath, APointJustInsideTheTurnIsHitByTheInnerSide) {
  // Radius 0.75 from the centre (0, 1), between the inner side's 1 - 0.27 = 0.73 and the inner
  // corner's 0.789, 60 degrees round: (0.75 sin 60, 1 - 0.75 cos 60) = (0.6495, 0.625). The side
  // (0.73 from the centre) reaches it acos(0.73 / 0.75) = 0.2315 rad before the point's radial:
  // after pi/3 - 0.2315 = 0.8157 m.
  const V p(0.75 * std::sin(std::numbers::pi / 3.0), 1.0 - 0.75 * std::cos(std::numbers::pi / 3.0));
  const std::vector<V> points = {p};
  const Arc arc = evaluateArc(1.0, {3.0, 1.5}, points, 0.0, kDecel, kTeam);
  EXPECT_NEAR(arc.length, std::numbers::pi / 3.0 - std::acos(0.73 / 0.75), 1e-12);
}

TEST(ArcFreePath, AStraightArcStopsItsFrontAtTheFirstPointInItsBand) {
  // Straight to the target 5 m ahead; (1.0, 0.1) is in the band |y| <= 0.27: 1.0 - 0.30 = 0.70.
  // (0.6, 0.4) is beside it, outside the band; (-0.5, 0) is behind.
  const std::vector<V> points = {{1.0, 0.1}, {0.6, 0.4}, {-0.5, 0.0}};
  const Arc arc = evaluateArc(0.0, {5.0, 0.0}, points, 0.0, kDecel, kTeam);
  EXPECT_NEAR(arc.length, 0.70, 1e-12);
  EXPECT_EQ(arc.end, V(0.70, 0.0));
}

TEST(ArcFreePath, ALengthIsCappedByAQuarterCircleAndTheClosestApproach) {
  // Curvature 2.5 (radius 0.4, centre (0, 0.4)) in the open. Toward (3, 0.4), level with the
  // centre, the closest approach is a quarter turn on: the quarter circle, 0.4 pi / 2 = 0.628 m.
  // Toward (3, 0) it comes earlier: atan2(3, 0.4) = 1.438 rad round, 0.575 m.
  EXPECT_NEAR(evaluateArc(2.5, {3.0, 0.4}, {}, 0.0, kDecel, kTeam).length, 0.4 * std::numbers::pi / 2.0, 1e-12);
  EXPECT_NEAR(evaluateArc(2.5, {3.0, 0.0}, {}, 0.0, kDecel, kTeam).length, 0.4 * std::atan2(3.0, 0.4), 1e-12);
  // Curvature 0.5 toward (2, 0): the target is atan2(2, 2) = pi/4 round the centre (0, 2),
  // the arc's nearest point to it: 2 x pi/4 = 1.571 m (the quarter circle is 3.14).
  const Arc wide = evaluateArc(0.5, {2.0, 0.0}, {}, 0.0, kDecel, kTeam);
  EXPECT_NEAR(wide.length, std::numbers::pi / 2.0, 1e-12);
  // Straight: to abeam the target, capped at 6 m.
  EXPECT_NEAR(evaluateArc(0.0, {2.5, 1.0}, {}, 0.0, kDecel, kTeam).length, 2.5, 1e-12);
  EXPECT_NEAR(evaluateArc(0.0, {9.0, 0.0}, {}, 0.0, kDecel, kTeam).length, 6.0, 1e-12);
}

TEST(ArcFreePath, AnArcShorterThanTheStoppingDistanceIsNotDrivable) {
  // At 1 m/s the robot needs 1 / (2 x 0.5) = 1 m to stop. Straight, a point 1.2 m ahead leaves
  // 0.9 m: not enough. At 0.9 m/s (0.81 m) it is.
  const std::vector<V> points = {{1.2, 0.0}};
  EXPECT_EQ(evaluateArc(0.0, {5.0, 0.0}, points, 1.0, kDecel, kTeam).length, 0.0);
  EXPECT_NEAR(evaluateArc(0.0, {5.0, 0.0}, points, 0.9, kDecel, kTeam).length, 0.9, 1e-12);
  // With nothing ahead, the stopping distance lengthens the arc past the closest approach:
  // the target 0.5 m ahead, yet 1 m.
  EXPECT_NEAR(evaluateArc(0.0, {0.5, 0.0}, {}, 1.0, kDecel, kTeam).length, 1.0, 1e-12);
}

TEST(ArcFreePath, APointInsideTheBoxPlusMarginStopsEveryTurningArc) {
  // (0.2, -0.25): ahead of the base link, inside the 0.30 x 0.27 half-box. Every arc is cut to 0.
  const std::vector<V> points = {{0.2, -0.25}};
  for (double k : {-2.5, -1.0, 1.0, 2.5}) EXPECT_EQ(evaluateArc(k, {3.0, 0.0}, points, 0.0, kDecel, kTeam).length, 0.0) << k;
  EXPECT_EQ(evaluateArc(0.0, {3.0, 0.0}, points, 0.0, kDecel, kTeam).length, 0.0);
}

// ---- Clearance ----

TEST(ArcClearance, AStraightArcsClearanceIsTheNearestPointBesideItsFirstPart) {
  // Free to the target 5 m ahead. Clearance counts points from the base link to 0.8 x 5 + 0.30
  // = 4.3 m ahead: |y| of (0.5, 0.6), (2.0, -0.4), (3.0, 0.35) -> 0.35; (4.5, 0.28) is past it.
  const std::vector<V> points = {{0.5, 0.6}, {2.0, -0.4}, {3.0, 0.35}, {4.5, 0.28}};
  const Arc arc = evaluateArc(0.0, {5.0, 0.0}, points, 0.0, kDecel, kTeam);
  EXPECT_NEAR(arc.length, 5.0, 1e-12);
  EXPECT_NEAR(arc.clearance, 0.35, 1e-12);
  // A point in the band at 4.0 cuts it to 3.7: now 0.8 x 3.7 + 0.3 = 3.26, still past (3.0, 0.35).
  std::vector<V> blocked = points;
  blocked.emplace_back(4.0, 0.0);
  const Arc cut = evaluateArc(0.0, {5.0, 0.0}, blocked, 0.0, kDecel, kTeam);
  EXPECT_NEAR(cut.length, 3.7, 1e-12);
  EXPECT_NEAR(cut.clearance, 0.35, 1e-12);
  // Nothing near: the cap, 1 m.
  EXPECT_EQ(evaluateArc(0.0, {5.0, 0.0}, {}, 0.0, kDecel, kTeam).clearance, 1.0);
}

TEST(ArcClearance, ACurvedArcsClearanceIsTheRadialDistanceFromItsCentreLine) {
  // Curvature 0.5 (centre (0, 2)) to the target (2, 0): 1.571 m, a 45 degree turn, so points
  // up to 0.8 x 45 = 36 degrees round count. One at radius 2.6, 30 degrees round: 0.6 from the
  // centre line. One at radius 1.5 but 40 degrees round (past 36) does not count. Neither is in
  // the swept annulus (2 - 0.27 = 1.73 to |(0.3, -0.27) - (0, 2)| = 2.29).
  auto at = [](double r, double deg) {
    const double a = deg * std::numbers::pi / 180.0;
    return V(r * std::sin(a), 2.0 - r * std::cos(a));
  };
  const std::vector<V> points = {at(2.6, 30.0), at(1.5, 40.0)};
  const Arc arc = evaluateArc(0.5, {2.0, 0.0}, points, 0.0, kDecel, kTeam);
  EXPECT_NEAR(arc.length, std::numbers::pi / 2.0, 1e-12);
  EXPECT_NEAR(arc.clearance, 0.6, 1e-12);
}

// ---- The linear evaluator ----

TEST(ArcEvaluator, PositiveWeightsPreferLessFreePathAndLessClearance) {
  // Target (3, 0). A: 2 m free, clearance 0.5, ends at (2, 0); B: 1 m, 0.2, at (1, 0). Both
  // path lengths are 3 (2 + 1, 1 + 2): A, first, is the baseline, 10 x 1.5 x 3 + 0.1 x 2 +
  // 0.2 x 0.5 = 45.3. A costs 30 + 0.2 + 0.1 = 30.3, B 30 + 0.1 + 0.04 = 30.14: B.
  const std::vector<Arc> arcs = {{0.0, 2.0, 0.5, {2.0, 0.0}}, {0.0, 1.0, 0.2, {1.0, 0.0}}};
  EXPECT_EQ(chooseArc(arcs, {3.0, 0.0}, {}, kTeam), 1);
  // graph_navigation's own defaults (dw 1, cw -0.5, fw -1) reward both: A 3 - 2 - 0.25 = 0.75
  // against B 3 - 1 - 0.1 = 1.9: A.
  ArcPlannerConfig defaults = kTeam;
  defaults.dw = 1.0;
  defaults.cw = -0.5;
  defaults.fw = -1.0;
  EXPECT_EQ(chooseArc(arcs, {3.0, 0.0}, {}, defaults), 0);
}

TEST(ArcEvaluator, AnArcWhoseEndCannotSeeTheTargetIsNotChosen) {
  // A point on the line from A's end (2, 0) to the target (3, 0) hides it; B (1 m free, ending
  // at (1, 0.5)) sees past it. Only B has a finite path length.
  const std::vector<Arc> arcs = {{0.0, 2.0, 0.5, {2.0, 0.0}}, {0.5, 1.0, 0.5, {1.0, 0.5}}};
  const std::vector<V> points = {{2.5, 0.0}};
  EXPECT_EQ(chooseArc(arcs, {3.0, 0.0}, points, kTeam), 1);
  // Length 0 never counts; none left: -1.
  const std::vector<Arc> stopped = {{0.0, 0.0, 0.5, {0.0, 0.0}}};
  EXPECT_EQ(chooseArc(stopped, {3.0, 0.0}, {}, kTeam), -1);
}

TEST(ArcEvaluator, InTheOpenTheStraightArcToATargetAheadWins) {
  const std::vector<Arc> arcs = sampleArcs({3.0, 0.0}, {}, 0.0, kDecel, kTeam);
  ASSERT_EQ(arcs.size(), 31u);
  EXPECT_EQ(arcs.front().curvature, -2.5);
  EXPECT_EQ(arcs[15].curvature, 0.0);
  EXPECT_EQ(arcs.back().curvature, 2.5);
  EXPECT_EQ(chooseArc(arcs, {3.0, 0.0}, {}, kTeam), 15);
}

TEST(ArcEvaluator, StraightLineClearanceCountsOnlyPointsAlongsideTheSegment) {
  // From (0, 0) to (4, 0): (2, 0.3) is 0.3 beside it; (5, 0.1) projects past its end.
  EXPECT_NEAR(straightLineClearance({0, 0}, {4, 0}, std::vector<V>{{2, 0.3}, {5, 0.1}}), 0.3, 1e-12);
  EXPECT_TRUE(std::isinf(straightLineClearance({0, 0}, {4, 0}, std::vector<V>{{5, 0.1}, {-1, 0.0}})));
}

// ---- 1-D time-optimal control ----

const MotionLimits kLinear{2.0, 0.5, 0.5};
constexpr double kDt = 0.025;

TEST(TimeOptimalControl, EachPhaseTakesOneStep) {
  // From rest, 1 m to go: a stop after accelerating one step needs 0.0003 m: accelerate to 0.0125.
  EXPECT_DOUBLE_EQ(timeOptimalSpeed(kLinear, 0.0, 1.0, kDt), 0.0125);
  // 1 m/s with 0.5 m left needs 0.025 + 1 m to stop: brake to 0.9875.
  EXPECT_DOUBLE_EQ(timeOptimalSpeed(kLinear, 1.0, 0.5, kDt), 0.9875);
  // At the limit with room: cruise.
  EXPECT_DOUBLE_EQ(timeOptimalSpeed(kLinear, 2.0, 10.0, kDt), 2.0);
  // Over the limit: brake.
  EXPECT_DOUBLE_EQ(timeOptimalSpeed(kLinear, 2.5, 10.0, kDt), 2.4875);
  // Nothing left: brake; at rest: stay.
  EXPECT_DOUBLE_EQ(timeOptimalSpeed(kLinear, 0.3, 0.0, kDt), 0.2875);
  EXPECT_EQ(timeOptimalSpeed(kLinear, 0.0, 0.0, kDt), 0.0);
}

/// Drives `distance` from rest at the commands of timeOptimalSpeed; the peak speed and the
/// distance covered when it stops.
std::pair<double, double> drive(double distance) {
  double x = 0.0, v = 0.0, peak = 0.0;
  for (int i = 0; i < 100000; ++i) {
    v = timeOptimalSpeed(kLinear, v, distance - x, kDt);
    peak = std::max(peak, v);
    x += v * kDt;
    if (v == 0.0 && i > 0) break;
  }
  return {peak, x};
}

TEST(TimeOptimalControl, AcceleratesCruisesAndBrakesToAStopWithinTheDistance) {
  // 4 m: too short for 2 m/s (which needs 4 m to reach and 4 to stop); a triangle peaking near
  // sqrt(0.5 x 4) = 1.41 m/s, stopping inside the 4 m.
  const auto [peak4, x4] = drive(4.0);
  EXPECT_GT(peak4, 1.35);
  EXPECT_LT(peak4, 1.42);
  EXPECT_LE(x4, 4.0);
  EXPECT_GT(x4, 3.9);
  // 20 m: reaches 2 m/s, cruises, stops inside.
  const auto [peak20, x20] = drive(20.0);
  EXPECT_EQ(peak20, 2.0);
  EXPECT_LE(x20, 20.0);
  EXPECT_GT(x20, 19.9);
}

// ---- Turning in place ----

TEST(TurnInPlace, BrakesFirstThenTurnsTheRightWay) {
  const MotionLimits angular{5.0, 5.0, 5.0};
  // Moving at 0.5 m/s (> 0.1): Halt, 0.5 - 0.5 x 0.025 = 0.4875 and no turn.
  ArcCommand c = turnInPlaceCommand(1.0, 0.5, 0.0, kLinear, angular, 0.1, kDt);
  EXPECT_DOUBLE_EQ(c.linear, 0.4875);
  EXPECT_EQ(c.angular, 0.0);
  // Slow enough: turn toward +1 rad, one angular step 5 x 0.025 = 0.125 at a time.
  c = turnInPlaceCommand(1.0, 0.05, 0.0, kLinear, angular, 0.1, kDt);
  EXPECT_EQ(c.linear, 0.0);
  EXPECT_DOUBLE_EQ(c.angular, 0.125);
  EXPECT_DOUBLE_EQ(turnInPlaceCommand(-1.0, 0.0, 0.0, kLinear, angular, 0.1, kDt).angular, -0.125);
  // Turning the wrong way (-1 rad/s for +0.5 rad): slow the turn by one step, -0.875; once
  // slower than a step, stop turning.
  EXPECT_DOUBLE_EQ(turnInPlaceCommand(0.5, 0.0, -1.0, kLinear, angular, 0.1, kDt).angular, -0.875);
  EXPECT_EQ(turnInPlaceCommand(0.5, 0.0, -0.1, kLinear, angular, 0.1, kDt).angular, 0.0);
}

TEST(TurnInPlace, HaltSlowsByOneStepAndStopsBelowOne) {
  EXPECT_DOUBLE_EQ(haltCommand(-0.5, kLinear, kDt).linear, -0.4875);
  EXPECT_EQ(haltCommand(0.011, kLinear, kDt).linear, 0.0);  // within one step (0.0125): 0
  EXPECT_EQ(haltCommand(0.005, kLinear, kDt).linear, 0.0);  // below 0.01: 0
}

}  // namespace
}  // namespace barn::controllers
