#include "barn/controllers/almeria_tps.hpp"

#include <cmath>
#include <limits>
#include <memory>
#include <numbers>
#include <vector>

#include <gtest/gtest.h>

#include "scan_fixtures.hpp"

namespace barn::controllers {
namespace {

constexpr double kPi = std::numbers::pi;
constexpr double kInf = std::numeric_limits<double>::infinity();

// ---- FullEval ----

// Eleven directions (alpha_i = pi (-1 + (2i + 1) / 11): i = 5 straight, i = 4 and 6 at -+2pi/11,
// i = 7 at 4pi/11), the target 0.6 ahead (k_t = 5), direction 5 blocked at 0.3 and direction 4
// at 0.5, the rest free to 1, every path 1 long.
struct Scene {
  std::vector<double> obstacles = std::vector<double>(11, 1.0);
  std::vector<double> unlooped = std::vector<double>(11, 1.0);
  TpSpaceInput input() const {
    TpSpaceInput in;
    in.obstacles = obstacles;
    in.unlooped = unlooped;
    in.target = {0.6, 0.0};
    in.ref_distance = 3.0;
    return in;
  }
};

Scene blockedAhead() {
  Scene s;
  s.obstacles[5] = 0.3;
  s.obstacles[4] = 0.5;
  return s;
}

TEST(FullEval, ScoresEachDirectionsFactors) {
  const Scene scene = blockedAhead();
  FullEval eval{FullEvalConfig{}};
  eval.navigate(scene.input());
  const auto& f = eval.factors();
  ASSERT_EQ(f.size(), 11u);
  // [6] direction 6, one path from the target: 1 / (1 + (4 / 11)^2) = 0.883212.
  EXPECT_NEAR(f[6][6], 0.883212, 1e-6);
  // [6] direction 5 is the target's, but the target (0.6) lies beyond its free space
  // (0.3 < 1.01 x 0.6): 1 x 0.1.
  EXPECT_NEAR(f[5][6], 0.1, 1e-12);
  // [0] direction 6 is next to the target, which lies inside its free space (1 > 1.05 x 0.6):
  // max(0.6, 1) / (1.05 x 0.6) = 1.587, capped by the path's length 1.
  EXPECT_DOUBLE_EQ(f[6][0], 1.0);
  // [0] direction 2: 1 - 0.15 = 0.85.
  EXPECT_NEAR(f[2][0], 0.85, 1e-12);
  // [4] direction 6: its segment runs to 0.57 (cos, sin)(2pi/11) = (0.479515, 0.308165); the
  // obstacle of direction 5 at (0.3, 0) lies 0.3 sin(2pi/11) = 0.162192 from it.
  EXPECT_NEAR(f[6][4], 0.162192, 1e-6);
  // [4] direction 4 ends at its own obstacle: 0.
  EXPECT_DOUBLE_EQ(f[4][4], 0.0);
  // [2] direction 7: P = 0.57 (cos, sin)(4pi/11) = (0.236786, 0.518490), |T - P| = 0.633059,
  // sqrt(1.01 - 0.633059) = 0.613960.
  EXPECT_NEAR(f[7][2], 0.613960, 1e-6);
}

TEST(FullEval, NarrowsTheChoicePhaseByPhase) {
  const Scene scene = blockedAhead();
  FullEval eval{FullEvalConfig{}};
  const FullEvalChoice choice = eval.navigate(scene.input());
  const auto& phases = eval.phaseScores();
  ASSERT_EQ(phases.size(), 3u);
  // Phase 1 ([6] alone): threshold 0.5 x 0.883212 + 0.5 x 0.088321 (direction 4) = 0.485767,
  // passed by directions 3, 6 and 7 (0.654054, 0.883212, 0.654054).
  // Phase 2 ([4] alone): 3 -> 0.270320, 6 -> 0.162192, 7 -> 1 (nothing near); threshold
  // 0.7 x 1 + 0.3 x 0 = 0.7: only 7 goes on.
  EXPECT_NEAR(phases[1][3], 0.270320, 1e-6);
  EXPECT_NEAR(phases[1][6], 0.162192, 1e-6);
  EXPECT_NEAR(phases[1][7], 1.0, 1e-12);
  EXPECT_DOUBLE_EQ(phases[1][2], 0.0);  // failed phase 1
  // Phase 3 ([0] weight 0.25, [2] weight 1): exp((0.25 ln 0.85 + ln 0.613960) / 1.25) = 0.655233.
  EXPECT_NEAR(phases[2][7], 0.655233, 1e-6);
  EXPECT_EQ(choice.direction, 7);
  EXPECT_NEAR(choice.evaluation, 0.655233, 1e-6);
  // Free (1 > too_close) and the target 0.6 x 3 = 1.8 m away (> 0.1 m): full speed.
  EXPECT_DOUBLE_EQ(choice.speed, 1.0);
  EXPECT_EQ(eval.lastSelected(), 7);
}

TEST(FullEval, PrefersTheTargetDirectionWhenItIsFree) {
  Scene scene;
  FullEval eval{FullEvalConfig{}};
  // Nothing in the way: direction 5 has [0] = max(0.6, 1) / 0.63 capped to 1, [2] =
  // sqrt(1.01 - |0.6 - 0.57|) = 0.989949, the best of phase 3.
  EXPECT_EQ(eval.navigate(scene.input()).direction, 5);
}

TEST(FullEval, DampsSwitchingAwayFromTheLastChoice) {
  Scene scene;
  FullEval eval{FullEvalConfig{}};
  eval.navigate(scene.input());  // chooses 5
  // [3]: within 5 paths of 5, 1; direction 0 (5 away) also 1; direction 10 (5 away) 1: with 11
  // paths everything is within reach. A wider count: the same config with count 2 gives
  // direction 0 (1 - (5 - 2) / 11)^2 = 0.528926.
  FullEvalConfig narrow;
  narrow.hysteresis_sector_count = 2;
  FullEval damped(narrow);
  damped.navigate(scene.input());
  damped.navigate(scene.input());
  EXPECT_NEAR(damped.factors()[0][3], 0.528926, 1e-6);
  EXPECT_DOUBLE_EQ(damped.factors()[4][3], 1.0);
  EXPECT_DOUBLE_EQ(eval.factors()[0][3], 1.0);
}

TEST(FullEval, FindsNoWayWhenEveryDirectionIsTooClose) {
  Scene scene;
  scene.obstacles.assign(11, 0.1);  // below too_close 0.15 everywhere
  FullEval eval{FullEvalConfig{}};
  const FullEvalChoice choice = eval.navigate(scene.input());
  EXPECT_EQ(choice.direction, -1);
  EXPECT_DOUBLE_EQ(choice.speed, 0.0);
  EXPECT_EQ(eval.lastSelected(), -1);
}

TEST(FullEval, SlowsDownOnlyWithinTheApproachDistanceOfTheTarget) {
  Scene scene;
  TpSpaceInput in = scene.input();
  in.target = {0.02, 0.0};  // 0.06 m away: 0.02 / (0.1 / 3) = 0.6
  FullEval eval{FullEvalConfig{}};
  EXPECT_NEAR(eval.navigate(in).speed, 0.6, 1e-12);
  in.slow_down_at_target = false;  // an intermediate waypoint
  EXPECT_DOUBLE_EQ(eval.navigate(in).speed, 1.0);
}

// ---- Speed law ----

TEST(AlmeriaSpeed, RampsWithTheFreeDistanceOfTheChosenPath) {
  // 0 up to 0.05, 1 from 0.15: 0.1 is half way.
  EXPECT_DOUBLE_EQ(secureDistanceScale(0.04, 0.05, 0.15), 0.0);
  EXPECT_NEAR(secureDistanceScale(0.10, 0.05, 0.15), 0.5, 1e-12);
  EXPECT_DOUBLE_EQ(secureDistanceScale(0.20, 0.05, 0.15), 1.0);
}

TEST(AlmeriaSpeed, ScalesBothSpeedsToTheRobotLimitsKeepingTheCurvature) {
  // (1.5, 0.6) under 1.2 m/s: x 0.8 -> (1.2, 0.48); then 0.48 > 0.4 rad/s: x 0.833 -> (1.0, 0.4).
  core::Twist cmd{1.5, 0.6};
  const double scale = limitToRobot(cmd, 1.2, 0.4);
  EXPECT_NEAR(cmd.linear, 1.0, 1e-12);
  EXPECT_NEAR(cmd.angular, 0.4, 1e-12);
  EXPECT_NEAR(scale, 2.0 / 3.0, 1e-12);
}

// ---- The controller ----

struct Tick {
  core::LaserScan scan;
  Observation obs;
};

Tick openSpace(const core::LidarConfig& lidar, const Eigen::Vector2d& goal, double time = 0.0) {
  Tick t;
  t.scan = uniformScan(lidar, kInf);
  t.obs.time = time;
  t.obs.scan = &t.scan;
  t.obs.goal = goal;
  return t;
}

// The BARN goal as the only target (`target: goal`).
AlmeriaTpsConfig goalOnly() {
  AlmeriaTpsConfig c;
  c.target = AlmeriaTarget::Goal;
  return c;
}

class AlmeriaController : public ::testing::Test {
 protected:
  static void SetUpTestSuite() { ptg_ = std::make_shared<const ArcPtg>(PtgConfig{}); }
  static std::shared_ptr<const ArcPtg> ptg_;
  EpisodeInfo info_;
};
std::shared_ptr<const ArcPtg> AlmeriaController::ptg_;

TEST_F(AlmeriaController, DrivesTheStraightPathAtFullSpeedTowardANearGoalInOpenSpace) {
  AlmeriaTpsController c(goalOnly(), ptg_);
  info_.goal = {2.0, 0.0};
  c.reset(info_);
  Tick t = openSpace(info_.lidar, info_.goal);
  const core::Twist cmd = c.act(t.obs);
  // Target (2, 0): path 75 at 2 / 3 = 0.667; it wins phase 3 ([0] capped 1, [2] 0.988), free
  // space and 2 m to go leave the speed at 1: (1.2, 0).
  EXPECT_EQ(c.lastChoice().direction, 75);
  EXPECT_DOUBLE_EQ(cmd.linear, 1.2);
  EXPECT_DOUBLE_EQ(cmd.angular, 0.0);
  EXPECT_EQ(c.state(), AlmeriaTpsState::Navigating);
}

TEST_F(AlmeriaController, AimingAtAFarGoalInOpenSpaceTheChoiceGoesToTheEdgeOfThePhaseOneWindow) {
  // The goal 10 m ahead, beyond the PTG's 3 m: every end point is >= 1 (normalised) from it, so
  // [2] = sqrt(1.01 - 1) = 0.1 everywhere, and [0] = 1 - 0.15 = 0.85 on every path free to 3 m.
  // Phase 1 keeps 1 / (1 + (4 |i - 75| / 151)^2) >= 0.5 x 1 + 0.5 x 0.202 (paths 0 and 150):
  // |i - 75| <= 30; all of them tie in phases 2 and 3, and the last of the tie wins: path 105,
  // alpha = 60 pi / 151 = 1.248 rad off the goal's direction.
  AlmeriaTpsController c(goalOnly(), ptg_);
  info_.goal = {10.0, 0.0};
  c.reset(info_);
  Tick t = openSpace(info_.lidar, info_.goal);
  c.act(t.obs);
  EXPECT_EQ(c.lastChoice().direction, 105);
}

TEST_F(AlmeriaController, CommandsTheChosenArcScaledByTheSpeed) {
  AlmeriaTpsController c(goalOnly(), ptg_);
  info_.goal = {1.0, 1.0};
  c.reset(info_);
  Tick t = openSpace(info_.lidar, info_.goal);
  const core::Twist cmd = c.act(t.obs);
  // Whatever path k it chose, the command is (v_k, w_k) at speed 1 (nothing near, 1.41 m to go).
  const int k = c.lastChoice().direction;
  ASSERT_GE(k, 0);
  EXPECT_GT(k, 75);  // the goal is to the left
  EXPECT_DOUBLE_EQ(cmd.linear, ptg_->linearSpeed(k));
  EXPECT_DOUBLE_EQ(cmd.angular, ptg_->angularSpeed(k));
}

TEST_F(AlmeriaController, StopsWhenEveryPathIsBlockedAndAbortsAfterTheTimeout) {
  AlmeriaTpsController c(goalOnly(), ptg_);
  info_.goal = {10.0, 0.0};
  c.reset(info_);
  // A ring of returns 0.42 m around the robot (the LiDAR at the centre): every path meets one
  // within 0.45 m (too_close 0.15 x 3 m), spinning included (the polygon's corners reach 0.404).
  info_.lidar = centredLidar();
  c.reset(info_);
  Tick t = openSpace(info_.lidar, info_.goal);
  t.scan = uniformScan(info_.lidar, 0.42);
  t.obs.scan = &t.scan;
  EXPECT_DOUBLE_EQ(c.act(t.obs).linear, 0.0);
  EXPECT_EQ(c.state(), AlmeriaTpsState::NoWay);
  // Still blocked, no nearer to the goal: 30 s later navigation is aborted for good.
  t.obs.time = 29.95;
  c.act(t.obs);
  EXPECT_EQ(c.state(), AlmeriaTpsState::NoWay);
  t.obs.time = 30.05;
  c.act(t.obs);
  EXPECT_EQ(c.state(), AlmeriaTpsState::Aborted);
  t.scan = uniformScan(info_.lidar, kInf);
  EXPECT_DOUBLE_EQ(c.act(t.obs).linear, 0.0);
  EXPECT_EQ(c.state(), AlmeriaTpsState::Aborted);
}

TEST_F(AlmeriaController, EndsNavigationWhenItsLastMovePassesTheGoal) {
  AlmeriaTpsController c(goalOnly(), ptg_);
  info_.goal = {0.5, 0.3};
  c.reset(info_);
  Tick t = openSpace(info_.lidar, info_.goal);
  c.act(t.obs);  // 0.58 m away: navigating
  EXPECT_EQ(c.state(), AlmeriaTpsState::Navigating);
  // Moved from (0, 0) to (1, 0): the segment passes 0.3 m from the goal (< 0.4).
  t.obs.odom_pose = {1.0, 0.0, 0.0};
  t.obs.time = 0.1;
  EXPECT_DOUBLE_EQ(c.act(t.obs).linear, 0.0);
  EXPECT_EQ(c.state(), AlmeriaTpsState::Reached);
}

TEST_F(AlmeriaController, SkipsToTheFarthestPlanWaypointSeenReachableTwice) {
  AlmeriaTpsController c(AlmeriaTpsConfig{}, ptg_);  // target: plan_waypoints
  // BARN's odom frame: the robot at the origin facing +y, the goal 10 m ahead (the global
  // costmap covers that corridor).
  info_.goal = {0.0, 10.0};
  c.reset(info_);
  Tick t = openSpace(info_.lidar, info_.goal);
  t.obs.odom_pose = t.obs.scan_odom_pose = {0.0, 0.0, kPi / 2};
  // Tick 1: the first plan becomes the sequence (a waypoint every 0.5 m, the goal last); there
  // is no current waypoint to skip from yet, so the first one becomes current.
  c.act(t.obs);
  ASSERT_GT(c.waypoints().size(), 15u);
  EXPECT_EQ(c.currentWaypoint(), 0);
  EXPECT_NEAR(c.waypoints()[0].norm(), 0.5, 0.1);
  // Tick 2: the waypoints within the straight path's reach (free to 3 m: d < 3 / 1.01) are seen
  // reachable once; skipping needs more than min_timesteps_confirm_skip_waypoints (1).
  t.obs.time = t.scan.stamp = 0.1;
  c.act(t.obs);
  EXPECT_EQ(c.currentWaypoint(), 0);
  // Tick 3: seen twice: the farthest of them, about 2.5 m ahead, becomes current.
  t.obs.time = t.scan.stamp = 0.2;
  c.act(t.obs);
  const double ahead = c.waypoints()[static_cast<std::size_t>(c.currentWaypoint())].norm();
  EXPECT_GT(ahead, 2.0);
  EXPECT_LT(ahead, 3.0 / 1.01);
}

TEST(AlmeriaWaypoints, PlacesOneEverySpacingAlongThePlanAndEndsAtTheGoal) {
  // A plan in 0.25 m steps to (2.25, 0): arc length reaches 0.5, 1.0, 1.5 and 2.0 at plan
  // points; the goal comes last (2.0 is 0.25 from it, not nearer than spacing / 2).
  std::vector<Eigen::Vector2d> plan;
  for (int i = 0; i <= 9; ++i) plan.emplace_back(0.25 * i, 0.0);
  const auto wps = planWaypoints(plan, {2.25, 0.0}, 0.5);
  ASSERT_EQ(wps.size(), 5u);
  EXPECT_DOUBLE_EQ(wps[0].x(), 0.5);
  EXPECT_DOUBLE_EQ(wps[3].x(), 2.0);
  EXPECT_DOUBLE_EQ(wps[4].x(), 2.25);
  // Coarse steps: 1.2 passes 0.5 (next due 1.5), 2.4 passes 1.5; 2.4 is the goal itself, which
  // replaces it.
  const auto coarse = planWaypoints({{0.0, 0.0}, {1.2, 0.0}, {2.4, 0.0}}, {2.4, 0.0}, 0.5);
  ASSERT_EQ(coarse.size(), 2u);
  EXPECT_DOUBLE_EQ(coarse[0].x(), 1.2);
  EXPECT_DOUBLE_EQ(coarse[1].x(), 2.4);
}

TEST(AlmeriaConfig, RejectsPhasesNamingNoFactor) {
  AlmeriaTpsConfig c;
  c.full_eval.phases[1].factors = {7};
  c.full_eval.factor_weights.pop_back();
  c.secure_distance_end = 0.01;
  core::Errors errors;
  validate(c, errors, "controller.almeria_tps");
  std::string all;
  for (const auto& m : errors.messages()) all += m + "\n";
  EXPECT_NE(all.find("controller.almeria_tps.secure_distance_end"), std::string::npos) << all;
  EXPECT_NE(all.find("controller.almeria_tps.full_eval.factor_weights: must have 7 values"), std::string::npos) << all;
  EXPECT_NE(all.find("controller.almeria_tps.full_eval.phases[1].factors"), std::string::npos) << all;
}

}  // namespace
}  // namespace barn::controllers
