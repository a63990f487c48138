#include "barn/controllers/kulfm.hpp"

#include <cmath>
#include <limits>
#include <numbers>
#include <string>

#include <gtest/gtest.h>

#include "scan_fixtures.hpp"

namespace barn::controllers {
namespace {

constexpr double kInf = std::numeric_limits<double>::infinity();

// ---- Local goal ----

TEST(KulfmLocalGoal, WalksTheTubeLengthAlongThePlanAndLooksBackForItsOrientation) {
  // 0.125 m steps along x to (0.5, 0), then up: the arc length reaches 0.75 at point 6 (0.5, 0.25).
  const std::vector<Eigen::Vector2d> plan{{0.0, 0.0},   {0.125, 0.0}, {0.25, 0.0},  {0.375, 0.0},
                                          {0.5, 0.0},   {0.5, 0.125}, {0.5, 0.25},  {0.5, 0.375}};
  const LocalGoal goal = localGoalOnPlan(plan, 0.75, 3, 5);
  EXPECT_NEAR(goal.position.x(), 0.5, 1e-12);
  EXPECT_NEAR(goal.position.y(), 0.25, 1e-12);
  // Orientation from point 6 - 3 = 3 (0.375, 0): atan2(0.25, 0.125) = 1.107149.
  EXPECT_NEAR(goal.orientation, 1.107149, 1e-6);
  // Head from point 0 to point 5 (0.5, 0.125): atan2(0.125, 0.5) = 0.244979.
  EXPECT_NEAR(goal.head, 0.244979, 1e-6);
}

TEST(KulfmLocalGoal, AShortPlanUsesItsEnds) {
  // Three points, 0.2 m apart: the walk stops at the last; 10 back clamps to point 0, point 10 to 2.
  const std::vector<Eigen::Vector2d> plan{{0.0, 0.0}, {0.2, 0.0}, {0.2, 0.2}};
  const LocalGoal goal = localGoalOnPlan(plan, 0.75, 10, 10);
  EXPECT_NEAR(goal.position.y(), 0.2, 1e-12);
  EXPECT_NEAR(goal.orientation, std::numbers::pi / 4, 1e-12);  // (0, 0) -> (0.2, 0.2)
  EXPECT_NEAR(goal.head, std::numbers::pi / 4, 1e-12);
}

// ---- Goal distance ----

MotionTube endingAt(double x, double y, double heading) {
  MotionTube t;
  t.end = {x, y, heading};
  t.heading_change = heading;
  t.radius = 1e9;
  return t;
}

TEST(KulfmGoalDistance, IsMeasuredToTheEndBoxAndBinnedByTwentyCentimetres) {
  const core::Rect box{-0.2, 0.2, -0.125, 0.125};  // the 2025 code's end box: 0.4 x (0.5 / 2)
  const MotionTube straight = endingAt(0.75, 0.0, 0.0);
  // Inside, at the box centre: minus the distance to the nearest side, 0.125; bin 0.
  EXPECT_NEAR(endBoxDistance(straight, {0.75, 0.0}, box), -0.125, 1e-12);
  EXPECT_EQ(goalBin(-0.125, 0.2), 0);
  // 1.25 ahead: 1.25 - (0.75 + 0.2) = 0.3 past the front; floor(0.3 / 0.2) + 1 = 2.
  EXPECT_NEAR(endBoxDistance(straight, {1.25, 0.0}, box), 0.3, 1e-12);
  EXPECT_EQ(goalBin(0.3, 0.2), 2);
  // 0.5 to the side: 0.5 - 0.125 = 0.375; bin 2. The box turns with the tube's end: a tube
  // ending at (0.75, 0) facing +y has the same point 0.5 - 0.2 = 0.3 past its front.
  EXPECT_NEAR(endBoxDistance(straight, {0.75, 0.5}, box), 0.375, 1e-12);
  EXPECT_NEAR(endBoxDistance(endingAt(0.75, 0.0, std::numbers::pi / 2), {0.75, 0.5}, box), 0.3, 1e-12);
  EXPECT_EQ(goalBin(0.19, 0.2), 1);
}

// ---- Forward selection on constructed tubes ----

// A two-beam LiDAR: beam 0 sees nothing, beam 1 a return at 0.5 m. A sample set on beam 0 is
// free, one at 1 m on beam 1 is not.
core::LaserScan twoBeamScan() {
  core::LaserScan scan;
  scan.angle_min = -0.1;
  scan.angle_increment = 0.2;
  scan.range_min = 0.1;
  scan.range_max = 30.0;
  scan.ranges = {kInf, 0.5};
  return scan;
}
SampleSet set(bool free) { return {{free ? 0 : 1, 1.0}}; }

// The local goal sits at (1, 0) facing +x. End (1, 0): bin 0; (0.7, 0): 0.1 past -> bin 1;
// (0.5, 0): 0.3 -> bin 2; (0.3, 0): 0.5 -> bin 3.
MotionTube tube(double end_x, bool outer, bool front, bool inner, double heading = 0.0, double radius = 1e9) {
  MotionTube t = endingAt(end_x, 0.0, heading);
  t.radius = radius;
  t.edge = set(true);
  t.outer = set(outer);
  t.front = set(front);
  t.inner = set(inner);
  return t;
}
const LocalGoal kGoal{{1.0, 0.0}, 0.0, 0.0};

int choose(const std::vector<MotionTube>& tubes, core::Twist odom = {}) {
  return chooseForwardTube(tubes, twoBeamScan(), kGoal, odom, KulfmConfig{}).tube;
}

TEST(KulfmForwardChoice, SkipsBlockedTubesButCountsTheFreeOnesForTheRatio) {
  std::vector<MotionTube> tubes{tube(1.0, true, true, true), tube(0.7, true, true, true)};
  tubes[0].edge = set(false);  // the closest, but its edge is blocked
  const ForwardChoice c = chooseForwardTube(tubes, twoBeamScan(), kGoal, {}, KulfmConfig{});
  EXPECT_EQ(c.tube, 1);
  EXPECT_EQ(c.free_tubes, 1);
  EXPECT_DOUBLE_EQ(c.feasible_ratio, 0.5);
  EXPECT_EQ(c.goal_bin, 1);
}

TEST(KulfmForwardChoice, AFreeOuterWhiskerOutweighsOneGoalBinButNotTwo) {
  // Bin 1 with the outer whisker blocked vs bin 2 with it free: within one bin, the whisker wins.
  EXPECT_EQ(choose({tube(0.7, false, true, true), tube(0.5, true, true, true)}), 1);
  // vs bin 3: more than one bin worse, dropped before the whiskers are looked at.
  EXPECT_EQ(choose({tube(0.7, false, true, true), tube(0.3, true, true, true)}), 0);
  // A closer tube wins at once, whatever its whiskers.
  EXPECT_EQ(choose({tube(0.5, true, true, true), tube(0.7, false, false, false)}), 1);
}

TEST(KulfmForwardChoice, WhiskersCountOuterThenFrontThenInner) {
  // Same bin: outer free and front blocked beats outer blocked and front free, in either order.
  EXPECT_EQ(choose({tube(1.0, true, false, true), tube(1.0, false, true, true)}), 0);
  EXPECT_EQ(choose({tube(1.0, false, true, true), tube(1.0, true, false, true)}), 1);
  // Outer tied: front before inner.
  EXPECT_EQ(choose({tube(1.0, true, true, false), tube(1.0, true, false, true)}), 0);
  EXPECT_EQ(choose({tube(1.0, true, false, true), tube(1.0, true, true, false)}), 1);
}

TEST(KulfmForwardChoice, TubesEndingMoreThanNinetyDegreesOffAreDroppedAndTheRestBinnedByTwenty) {
  // 2.0 rad off the local goal's orientation: dropped although in bin 0.
  EXPECT_EQ(choose({tube(1.0, true, true, true, 2.0), tube(0.7, true, true, true)}), 1);
  // 0.4 rad = 22.9 deg (bin 1) loses to 0.1 rad (bin 0) in the same goal bin.
  EXPECT_EQ(choose({tube(1.0, true, true, true, 0.4), tube(1.0, true, true, true, 0.1)}), 1);
  // 0.1 and 0.3 rad share bin 0 (< 20 deg): a tie, the later tube wins.
  EXPECT_EQ(choose({tube(1.0, true, true, true, 0.3), tube(1.0, true, true, true, 0.1)}), 1);
  EXPECT_EQ(choose({tube(1.0, true, true, true, 0.1), tube(1.0, true, true, true, 0.3)}), 1);
}

TEST(KulfmForwardChoice, ThenTheSmallestChangeOfTurnRateThenTheGoalDistance) {
  // Driving at 0.5 m/s turning at 0.4 rad/s: radius +1 asks 0.5 rad/s (change 0.1), radius -1
  // asks -0.5 (change 0.9).
  const std::vector<MotionTube> pair{tube(1.0, true, true, true, 0.0, 1.0), tube(1.0, true, true, true, 0.0, -1.0)};
  EXPECT_EQ(choose(pair, {0.5, 0.4}), 0);
  // Standing: no change is counted, the later tube wins the tie.
  EXPECT_EQ(choose(pair, {0.0, 0.4}), 1);
  // The signed distance last: ending at 0.9 the goal is 0.1 inside the box's front (-0.1),
  // ending at 1.0 it is 0.125 inside its sides (-0.125): the deeper one wins, in either order.
  EXPECT_EQ(choose({tube(0.9, true, true, true), tube(1.0, true, true, true)}), 1);
  EXPECT_EQ(choose({tube(1.0, true, true, true), tube(0.9, true, true, true)}), 0);
}

// ---- Backward selection ----

TEST(KulfmBackwardChoice, TakesTheMiddleOfTheWidestRunOfFreeTubesByCurvature) {
  // Curvatures -3 ... 3 in a shuffled library order; by curvature free, free, blocked, free,
  // free, free, blocked: the run -> 0, 1, 2 is widest, 1 (depth min(2, 2)) its middle.
  const double curvatures[] = {2, -3, 0, 3, -1, 1, -2};
  const bool free[] = {true, true, true, false, false, true, true};  // by the library order above
  std::vector<MotionTube> tubes;
  for (int i = 0; i < 7; ++i) {
    MotionTube t = endingAt(-0.75, 0.0, 0.0);
    t.radius = curvatures[i] == 0 ? 1e9 : 1.0 / curvatures[i];
    t.edge = set(free[i]);
    tubes.push_back(t);
  }
  EXPECT_EQ(chooseBackwardTube(tubes, twoBeamScan(), kGoal, KulfmConfig{}), 5);  // curvature 1
}

TEST(KulfmBackwardChoice, KeepsToTubesWithinTwoBinsOfTheBest) {
  // All free; the goal (1, 0) is 1.75 - 0.2 = 1.55 past the box of a tube ending at -0.75
  // (bin floor(1.55 / 0.4) + 1 = 4); the tubes of curvature 2 and 3 end at -3 (3.8 away, bin 10)
  // and are not candidates: the run -3 ... 1 has its middle at -1.
  std::vector<MotionTube> tubes;
  for (int k = -3; k <= 3; ++k) {
    MotionTube t = endingAt(k >= 2 ? -3.0 : -0.75, 0.0, 0.0);
    t.radius = k == 0 ? 1e9 : 1.0 / k;
    t.edge = set(true);
    tubes.push_back(t);
  }
  EXPECT_EQ(chooseBackwardTube(tubes, twoBeamScan(), kGoal, KulfmConfig{}), 2);  // curvature -1
  // Nothing free: none.
  for (auto& t : tubes) t.edge = set(false);
  EXPECT_EQ(chooseBackwardTube(tubes, twoBeamScan(), kGoal, KulfmConfig{}), -1);
}

// ---- Speed rule ----

TEST(KulfmSpeed, MinBelowTenPercentFreeMaxAboveSeventyFiveBlendInBetween) {
  KulfmConfig c;
  c.min_speed = 0.3;
  c.max_speed = 0.9;
  EXPECT_DOUBLE_EQ(desiredSpeed(0.05, c), 0.3);
  EXPECT_DOUBLE_EQ(desiredSpeed(0.8, c), 0.9);
  // 0.4 * 0.3 + 0.6 * 0.9 = 0.66, from 0.1 to 0.75 inclusive.
  EXPECT_DOUBLE_EQ(desiredSpeed(0.1, c), 0.66);
  EXPECT_DOUBLE_EQ(desiredSpeed(0.5, c), 0.66);
  EXPECT_DOUBLE_EQ(desiredSpeed(0.75, c), 0.66);
}

TEST(KulfmSpeed, ChangesByAtMostOneMetrePerSecondSquaredAtTwentyHertz) {
  // 1 m/s^2 / 20 Hz = 0.05 m/s per tick.
  EXPECT_DOUBLE_EQ(limitAcceleration(0.0, 0.5, 0.05), 0.05);
  EXPECT_DOUBLE_EQ(limitAcceleration(0.48, 0.5, 0.05), 0.5);
  EXPECT_DOUBLE_EQ(limitAcceleration(0.5, 0.3, 0.05), 0.45);
}

// ---- State machine: every edge ----

KulfmState next(KulfmState s, const KulfmInputs& in) { return nextKulfmState(s, in, KulfmConfig{}); }

KulfmInputs resumable() {
  KulfmInputs in;
  in.forward_tube = true;
  in.feasible_ratio = 0.2;
  in.goal_bin = 1;
  return in;
}

TEST(KulfmFsm, NormalStopsWhenNoTubeIsFree) {
  KulfmInputs in;
  in.forward_tube = true;
  EXPECT_EQ(next(KulfmState::Normal, in), KulfmState::Normal);
  in.forward_tube = false;
  EXPECT_EQ(next(KulfmState::Normal, in), KulfmState::StopToRecover);
}

TEST(KulfmFsm, StopToRecoverWaitsUntilBothSpeedsAreBelow0025) {
  KulfmInputs in;
  in.speed = 0.03;
  in.turn_rate = 0.0;
  EXPECT_EQ(next(KulfmState::StopToRecover, in), KulfmState::StopToRecover);
  in.speed = 0.02;
  in.turn_rate = -0.03;
  EXPECT_EQ(next(KulfmState::StopToRecover, in), KulfmState::StopToRecover);
  in.turn_rate = -0.02;
  EXPECT_EQ(next(KulfmState::StopToRecover, in), KulfmState::StartRecover);
}

TEST(KulfmFsm, StartRecoverRotatesIfTheRingIsClearElseReversesOnATubeElseBlind) {
  KulfmInputs in;
  in.ring_clear = true;
  in.backward_tube = true;
  EXPECT_EQ(next(KulfmState::StartRecover, in), KulfmState::Rotate);
  in.ring_clear = false;
  EXPECT_EQ(next(KulfmState::StartRecover, in), KulfmState::MoveBackward);
  in.backward_tube = false;
  EXPECT_EQ(next(KulfmState::StartRecover, in), KulfmState::Blind);
}

TEST(KulfmFsm, RotateAndBlindLastUntilTwentyPercentAreFreeAndATubeReachesTheLocalGoal) {
  for (KulfmState s : {KulfmState::Rotate, KulfmState::Blind}) {
    KulfmInputs in = resumable();
    EXPECT_EQ(next(s, in), KulfmState::StopToNormal);
    in.feasible_ratio = 0.19;
    EXPECT_EQ(next(s, in), s);
    in = resumable();
    in.goal_bin = 2;
    EXPECT_EQ(next(s, in), s);
  }
}

TEST(KulfmFsm, MoveBackwardResumesFirstThenRotatesOnAClearRingThenStopsWithoutATube) {
  KulfmInputs in = resumable();
  in.ring_clear = true;
  EXPECT_EQ(next(KulfmState::MoveBackward, in), KulfmState::StopToNormal);
  in.goal_bin = 3;  // not resumable: the clear ring sends it to rotate (through the stop)
  EXPECT_EQ(next(KulfmState::MoveBackward, in), KulfmState::StopToRecover);
  in.ring_clear = false;
  in.backward_tube = true;
  EXPECT_EQ(next(KulfmState::MoveBackward, in), KulfmState::MoveBackward);
  in.backward_tube = false;
  EXPECT_EQ(next(KulfmState::MoveBackward, in), KulfmState::StopToNormal);
}

TEST(KulfmFsm, StopToNormalResumesWhenEitherSpeedIsBelow005) {
  KulfmInputs in;
  in.speed = -0.3;
  in.turn_rate = 0.4;
  EXPECT_EQ(next(KulfmState::StopToNormal, in), KulfmState::StopToNormal);
  in.turn_rate = 0.04;  // the 2025 code's "or": the reverse speed may still be high
  EXPECT_EQ(next(KulfmState::StopToNormal, in), KulfmState::Normal);
}

TEST(KulfmFsm, StatesHaveLabels) {
  EXPECT_EQ(core::enumName(KulfmState::MoveBackward), "MoveBackward");
  EXPECT_EQ(core::enumName(KulfmState::StopToNormal), "StopToNormal");
}

// ---- The controller ----

struct Drive {
  KulfmController controller{KulfmConfig{}};
  EpisodeInfo info;
  double time = 0.0;
  Drive() {
    info.goal = {2.5, 0.0};  // the robot at the origin facing +x
    controller.reset(info);
  }
  core::Twist tick(core::LaserScan scan, core::Twist odom = {}) {
    scan.stamp = time;
    Observation obs;
    obs.time = time;
    obs.scan = &scan;
    obs.goal = info.goal;
    obs.odom_twist = odom;
    time += controller.period();
    return controller.act(obs);
  }
};

TEST(KulfmController, InTheOpenItDrivesStraightAtTheAcceleratingSpeed) {
  Drive run;
  const core::LaserScan open = uniformScan(run.info.lidar, kInf);
  // All 362 tubes free (ratio 1 -> max_speed 0.5), the straight ones reach the local goal: 0.05
  // m/s the first tick, 0.10 the next; w = v / 900.
  core::Twist c = run.tick(open);
  EXPECT_EQ(run.controller.stateLabel(), "Normal");
  EXPECT_NEAR(c.linear, 0.05, 1e-12);
  EXPECT_LT(std::abs(c.angular), 1e-3);
  c = run.tick(open, {0.05, 0.0});
  EXPECT_NEAR(c.linear, 0.10, 1e-12);
}

TEST(KulfmController, FacingAWallItStopsThenReversesWhenTheRingIsBlocked) {
  Drive run;
  run.tick(uniformScan(run.info.lidar, kInf));  // the first plan, straight ahead
  // A wall 0.3 m ahead: every tube's front crosses it, and it is inside the 0.4 m ring.
  const core::LaserScan wall = wallScan(run.info.lidar, 0.3);
  core::Twist c = run.tick(wall, {0.05, 0.0});
  EXPECT_EQ(run.controller.stateLabel(), "StopToRecover");
  EXPECT_EQ(c.linear, 0.0);
  run.tick(wall);
  EXPECT_EQ(run.controller.stateLabel(), "StartRecover");
  c = run.tick(wall);
  EXPECT_EQ(run.controller.stateLabel(), "MoveBackward");
  EXPECT_EQ(c.linear, -0.5);
}

TEST(KulfmController, FacingAWallBeyondTheRingItTurnsTowardThePlan) {
  Drive run;
  run.tick(uniformScan(run.info.lidar, kInf));
  // 0.5 m ahead: outside the ring (0.445 from the sensor straight ahead, against 0.345), still
  // across every tube (their outer corners reach at least 0.709 m ahead of the centre).
  const core::LaserScan wall = wallScan(run.info.lidar, 0.5);
  run.tick(wall, {0.05, 0.0});
  run.tick(wall);
  const core::Twist c = run.tick(wall);
  EXPECT_EQ(run.controller.stateLabel(), "Rotate");
  EXPECT_EQ(c.linear, 0.0);
  // The wall, marked at 0.1 s, sends the plan around its open end (+y, the map stops at y = -3):
  // the head points left, the turn is counter-clockwise at pi / 4.
  EXPECT_NEAR(c.angular, std::numbers::pi / 4, 1e-12);
}

TEST(KulfmConfig, ValidationNamesTheField) {
  KulfmConfig c;
  c.high_ratio = 0.05;  // below low_ratio 0.1
  c.tubes.length = 0.0;
  core::Errors errors;
  validate(c, errors, "kulfm");
  std::string all;
  for (const auto& m : errors.messages()) all += m + "\n";
  EXPECT_NE(all.find("kulfm.high_ratio"), std::string::npos) << all;
  EXPECT_NE(all.find("kulfm.tubes.length"), std::string::npos) << all;
}

}  // namespace
}  // namespace barn::controllers
