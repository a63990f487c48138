// The LiCS-KI controller as the team's simulation code ran it: the dynamic inflation, the front
// multiplier, the local goal on the smoothed plan, the callback race, and (with your copy of the
// published weights) the whole pipeline.
#include "barn/controllers/lics.hpp"

#include <cmath>
#include <filesystem>
#include <limits>
#include <memory>
#include <numbers>
#include <string>

#include <gmock/gmock.h>
#include <gtest/gtest.h>

#include "barn/controllers/registry.hpp"
#include "barn/core/config.hpp"
#include "scan_fixtures.hpp"

namespace barn::controllers {
namespace {

using ::testing::HasSubstr;

constexpr double kInf = std::numeric_limits<double>::infinity();

// ---- Step 1: the global inflation radius from the odometry speed ----

TEST(LicsInflation, TheSpeedIsDividedByMaxSpeedTwice) {
  const LicsConfig c;
  // r = 0.3 + (v / 1.5) / 1.5 x 0.7 = 0.3 + 0.3111 v.
  EXPECT_NEAR(licsInflationRadius(1.5, c), 0.3 + 0.7 / 1.5, 1e-12);  // 0.7667, not the 1.0 the names suggest
  EXPECT_NEAR(licsInflationRadius(0.75, c), 0.3 + 0.5 / 1.5 * 0.7, 1e-12);  // 0.5333
  EXPECT_NEAR(licsInflationRadius(0.9, c), 0.58, 1e-12);                  // 0.3 + 0.6 / 1.5 x 0.7
  // Standing or reversing: the minimum.
  EXPECT_EQ(licsInflationRadius(0.0, c), 0.3);
  EXPECT_EQ(licsInflationRadius(-0.4, c), 0.3);
}

TEST(LicsInflation, AThresholdShiftsTheRamp) {
  LicsConfig c;
  c.inflation_speed_threshold = 0.25;
  // v = 0.3 m/s: 0.3 / 1.5 = 0.2 <= 0.25, the minimum; v = 0.75: (0.5 - 0.25) / 1.25 x 0.7 = 0.14.
  EXPECT_EQ(licsInflationRadius(0.3, c), 0.3);
  EXPECT_NEAR(licsInflationRadius(0.75, c), 0.44, 1e-12);
}

// ---- Step 4: the front multiplier ----

TEST(LicsFrontMultiplier, IsTheNearestFrontRangeOverTwoAndAHalfMetres) {
  const LicsConfig c;
  const core::LidarConfig lidar;
  EXPECT_NEAR(licsFrontMultiplier(uniformScan(lidar, 1.0), 5.0, c), 0.4, 1e-12);  // 1.0 / 2.5
  EXPECT_EQ(licsFrontMultiplier(uniformScan(lidar, 2.5), 5.0, c), 1.0);           // not below 2.5
  EXPECT_EQ(licsFrontMultiplier(uniformScan(lidar, kInf), 5.0, c), 1.0);          // nothing seen: the 5 m clip
}

TEST(LicsFrontMultiplier, ReadsBeams253To466Only) {
  const LicsConfig c;
  const core::LidarConfig lidar;
  core::LaserScan scan = uniformScan(lidar, kInf);
  scan.ranges[252] = 0.5;  // -40.1 deg: outside the window
  scan.ranges[467] = 0.5;  // +40.1 deg: outside
  EXPECT_EQ(licsFrontMultiplier(scan, 5.0, c), 1.0);
  scan.ranges[253] = 0.5;  // -40.0 deg: inside, 0.5 / 2.5
  EXPECT_NEAR(licsFrontMultiplier(scan, 5.0, c), 0.2, 1e-12);
  scan.ranges[253] = kInf;
  scan.ranges[466] = 1.25;  // the last beam of the window: 1.25 / 2.5
  EXPECT_NEAR(licsFrontMultiplier(scan, 5.0, c), 0.5, 1e-12);
}

// ---- Step 3: the local goal on the smoothed plan ----

TEST(LicsLocalGoal, IsTheDirectionToTheFirstPointFartherThanTwoMetres) {
  const LicsConfig c;
  // An L: (0.1, 0) ... (1.6, 0) in 0.1 m steps, then up (1.6, 0.1) ... (1.6, 3.0). The first
  // point is 0.1 > 0.05 from the robot, so it is the origin. (1.6, y) lies farther than 2 from
  // it once 1.5^2 + y^2 > 4, y > 1.3229: the first such point is (1.6, 1.4), and the goal is
  // (1.5, 1.4) / 2.0518 = (0.7311, 0.6823).
  std::vector<Eigen::Vector2d> plan;
  for (int i = 1; i <= 16; ++i) plan.emplace_back(0.1 * i, 0.0);
  for (int i = 1; i <= 30; ++i) plan.emplace_back(1.6, 0.1 * i);
  const Eigen::Vector2d goal = licsLocalGoal(plan, c);
  EXPECT_NEAR(goal.x(), 1.5 / std::hypot(1.5, 1.4), 1e-12);
  EXPECT_NEAR(goal.y(), 1.4 / std::hypot(1.5, 1.4), 1e-12);
}

TEST(LicsLocalGoal, MeasuresFromTheRobotWhenThePlanStartsUnderIt) {
  const LicsConfig c;
  // First point (0.03, 0.03): 0.042 <= 0.05 from the robot, so the robot is the origin; the
  // first point farther than 2 is (2.03, 0.03): direction atan2(0.03, 2.03).
  std::vector<Eigen::Vector2d> plan;
  for (int i = 0; i <= 30; ++i) plan.emplace_back(0.03 + 0.1 * i, 0.03);
  const Eigen::Vector2d goal = licsLocalGoal(plan, c);
  EXPECT_NEAR(std::atan2(goal.y(), goal.x()), std::atan2(0.03, 2.03), 1e-12);
  EXPECT_NEAR(goal.norm(), 1.0, 1e-12);
}

TEST(LicsLocalGoal, AShortPlanGivesItsLastPointAndAnEmptyOneNothing) {
  const LicsConfig c;
  // Nothing farther than 2: the last point, (1, 1) / sqrt 2.
  const Eigen::Vector2d goal = licsLocalGoal({{0.0, 0.0}, {0.5, 0.5}, {1.0, 1.0}}, c);
  EXPECT_NEAR(goal.x(), std::sqrt(0.5), 1e-12);
  EXPECT_NEAR(goal.y(), std::sqrt(0.5), 1e-12);
  EXPECT_EQ(licsLocalGoal({}, c), Eigen::Vector2d::Zero());
  // The last point is the origin itself: the original divides 0 by 0; here (0, 0).
  EXPECT_EQ(licsLocalGoal({{0.5, 0.0}, {0.5, 0.0}}, c), Eigen::Vector2d::Zero());
}

TEST(LicsLocalGoal, OnASmoothedZigzagPlan) {
  // A plan along x in 0.1 m steps with a +-0.04 m zigzag: raw, the first point farther than 2 is
  // (2.0, +0.04), 0.020 rad off the axis. Smoothed (19, 3), point 20's y is 0.04 x 181/2261
  // (SavitzkyGolay test: the interior response to (-1)^i) and x stays (a line is kept), so the
  // goal is atan2(0.0032021, 2.0) = 0.0016 rad off. Point 0 smooths to y = 0.04 x 37/133 =
  // 0.0111, within 0.05 of the robot: the robot is the origin.
  const LicsConfig c;
  std::vector<Eigen::Vector2d> plan;
  for (int i = 0; i <= 40; ++i) plan.emplace_back(0.1 * i, i % 2 == 0 ? 0.04 : -0.04);
  const Eigen::Vector2d raw = licsLocalGoal(plan, c);
  EXPECT_NEAR(std::atan2(raw.y(), raw.x()), std::atan2(0.04, 2.0), 1e-12);
  const nav::SavitzkyGolay sg(c.smoothing_window, c.smoothing_order);
  const Eigen::Vector2d smoothed = licsLocalGoal(sg.smoothPath(plan), c);
  EXPECT_NEAR(std::atan2(smoothed.y(), smoothed.x()), std::atan2(0.04 * 181.0 / 2261.0, 2.0), 1e-12);
}

// ---- The race between the plan and scan callbacks ----

TEST(LicsRace, TheLaterCallbackWinsAndATieGoesToThePlan) {
  // Tick at 1.00 s with a plan made then; the scan it reads is stamped 1.00 or 0.99.
  EXPECT_TRUE(licsPlanWritesLast(1.00, 1.00, 0.0));    // tie: the plan
  EXPECT_TRUE(licsPlanWritesLast(1.00, 0.99, 0.0));
  EXPECT_FALSE(licsPlanWritesLast(1.00, 1.00, 0.005)); // plan at 0.995, scan at 1.00
  EXPECT_TRUE(licsPlanWritesLast(1.00, 0.99, 0.005));  // plan at 0.995, scan at 0.99
  EXPECT_FALSE(licsPlanWritesLast(1.00, 0.99, 0.02));  // plan at 0.98: the scan always
}

// ---- The controller, with a network whose output is fixed ----

/// A transformer of the published input shape (720 beams, 36 patches) whose weights are zero but
/// the head's bias: every LayerNorm gives 0, so the output is (v_hat, w_hat) whatever it reads.
std::shared_ptr<const learning::TransformerPolicy> constantTransformer(double v_hat, double w_hat) {
  learning::TransformerPolicyInfo info;
  info.shape.model_dim = 4;
  info.shape.heads = 1;
  info.shape.ffn_dim = 4;
  info.shape.encoder_layers = 1;
  info.shape.decoder_layers = 1;
  info.name = "constant";
  learning::TransformerWeights weights = learning::TransformerWeights::zeros(info.shape);
  weights.head_b << static_cast<float>(v_hat), static_cast<float>(w_hat);
  return std::make_shared<const learning::TransformerPolicy>(info, weights);
}

EpisodeInfo barnEpisode() {
  EpisodeInfo info;
  info.start = {0.0, 0.0, std::numbers::pi / 2};  // BARN: facing +y in the odom frame
  info.goal = {0.0, 10.0};
  return info;
}

/// A tick at `time` reading `scan` (stamped by the caller), the robot at the start.
Observation observationAt(double time, const core::LaserScan& scan, double speed = 0.0) {
  Observation obs;
  obs.time = time;
  obs.scan = &scan;
  obs.odom_pose = obs.scan_odom_pose = {0.0, 0.0, std::numbers::pi / 2};
  obs.odom_twist = {speed, 0.0};
  obs.goal = {0.0, 10.0};
  return obs;
}

/// Linear speeds of three ticks at 0, 0.05 and 0.10 s reading scans stamped 0, 0.04 and 0.10
/// (the 50 Hz LiDAR under a 20 Hz controller: 0, 10 and 0 ms old).
std::vector<double> threeTicks(double plan_phase, core::LaserScan scan, const EpisodeInfo& info = barnEpisode()) {
  LicsConfig c;
  c.plan_phase = plan_phase;
  LicsController controller(c, constantTransformer(1.0, 0.0));
  controller.reset(info);
  std::vector<double> v;
  const double times[3][2] = {{0.0, 0.0}, {0.05, 0.04}, {0.10, 0.10}};
  for (const auto& t : times) {
    scan.stamp = t[1];
    v.push_back(controller.act(observationAt(t[0], scan)).linear);
  }
  return v;
}

TEST(LicsController, ThePlanPhaseDecidesOnWhichTicksTheSlowDownIsLost) {
  // A post 1 m ahead (radius 0.1, the LiDAR 0.055 m ahead of the centre): nearest front range
  // about 0.845 m, multiplier about 0.338; a plan around it is found every tick, and its
  // callback writes 1. v_hat = 1, so v = 1.5 m.
  const core::LidarConfig lidar;
  const core::LaserScan scan = withPost(uniformScan(lidar, kInf), lidar, {1.0, 0.0}, 0.1);
  const double m = licsFrontMultiplier(scan, 5.0, LicsConfig{});
  EXPECT_NEAR(m, 0.845 / 2.5, 1e-3);
  EXPECT_EQ(threeTicks(0.0, scan), (std::vector<double>{1.5, 1.5, 1.5}));            // the plan always
  EXPECT_EQ(threeTicks(0.005, scan), (std::vector<double>{1.5 * m, 1.5, 1.5 * m}));  // on the 10 ms old scan
  EXPECT_EQ(threeTicks(0.02, scan), (std::vector<double>{1.5 * m, 1.5 * m, 1.5 * m}));  // the scan always
}

TEST(LicsController, AFailedPlanWritesThreeTenthsAndKeepsTheGoal) {
  // A goal off the global costmap (6 x 15 m): no plan. When the plan callback wins, m = 0.3:
  // v = 1.5 x 0.3; when the scan's does, nothing is in front and m = 1.
  const core::LidarConfig lidar;
  const core::LaserScan scan = uniformScan(lidar, kInf);
  EpisodeInfo far = barnEpisode();
  far.goal = {0.0, 100.0};
  for (double v : threeTicks(0.0, scan, far)) EXPECT_NEAR(v, 0.45, 1e-12);
  EXPECT_EQ(threeTicks(0.02, scan, far), (std::vector<double>{1.5, 1.5, 1.5}));
  LicsController controller(LicsConfig{}, constantTransformer(1.0, 0.0));
  controller.reset(far);
  controller.act(observationAt(0.0, scan));
  EXPECT_FALSE(controller.navStack().lastPlanFound());
  EXPECT_EQ(controller.localGoal(), Eigen::Vector2d::Zero());  // robot.py's initial value, kept
}

TEST(LicsController, TheGoalStraightAheadIsTheFirstLocalGoalAndTheCommandIsScaledAndClipped) {
  // Nothing in sight: the plan runs straight to the goal, the local goal is (1, 0) in the robot
  // frame. v_hat 2 -> 3 m/s clipped to 1.5; w_hat -0.5 -> -0.6; w_hat -2 -> -2.4 clipped to -1.2.
  const core::LidarConfig lidar;
  core::LaserScan scan = uniformScan(lidar, kInf);
  LicsController controller(LicsConfig{}, constantTransformer(2.0, -0.5));
  controller.reset(barnEpisode());
  const core::Twist command = controller.act(observationAt(0.0, scan));
  EXPECT_NEAR(controller.localGoal().x(), 1.0, 1e-6);
  EXPECT_NEAR(controller.localGoal().y(), 0.0, 1e-3);
  EXPECT_EQ(command.linear, 1.5);
  EXPECT_NEAR(command.angular, -0.6, 1e-6);
  LicsController turning(LicsConfig{}, constantTransformer(-2.0, -2.0));
  turning.reset(barnEpisode());
  const core::Twist back = turning.act(observationAt(0.0, scan));
  EXPECT_EQ(back.linear, -0.5);  // -3 clipped to min_speed
  EXPECT_EQ(back.angular, -1.2);
}

TEST(LicsController, TheRadiusFromTheSpeedReachesTheGlobalCostmapAtItsNextUpdate) {
  const core::LidarConfig lidar;
  core::LaserScan scan = uniformScan(lidar, kInf);
  LicsController controller(LicsConfig{}, constantTransformer(1.0, 0.0));
  controller.reset(barnEpisode());
  // t = 0: 1.5 m/s, the map's first update: r = 0.3 + 0.7 / 1.5 = 0.7667.
  controller.act(observationAt(0.0, scan, 1.5));
  EXPECT_EQ(controller.parameterChanges(), "global_costmap.inflation_radius=0.7667");
  EXPECT_NEAR(controller.navStack().globalCostmap().config().inflation_radius, 0.3 + 0.7 / 1.5, 1e-12);
  // t = 0.05: standing; the global map updates at 10 Hz, so the radius waits.
  scan.stamp = 0.04;
  controller.act(observationAt(0.05, scan, 0.0));
  EXPECT_EQ(controller.parameterChanges(), "global_costmap.inflation_radius=0.3000");
  EXPECT_NEAR(controller.navStack().globalCostmap().config().inflation_radius, 0.3 + 0.7 / 1.5, 1e-12);
  scan.stamp = 0.10;
  controller.act(observationAt(0.10, scan, 0.0));
  EXPECT_EQ(controller.navStack().globalCostmap().config().inflation_radius, 0.3);
  // Off: the configured radius throughout, and no parameter changes to record.
  LicsConfig still;
  still.dynamic_inflation = false;
  LicsController fixed(still, constantTransformer(1.0, 0.0));
  fixed.reset(barnEpisode());
  scan.stamp = 0.0;
  fixed.act(observationAt(0.0, scan, 1.5));
  EXPECT_EQ(fixed.parameterChanges(), "");
  EXPECT_EQ(fixed.navStack().globalCostmap().config().inflation_radius, 0.3);
}

TEST(LicsController, RefusesALidarOfAnotherBeamCount) {
  LicsController controller(LicsConfig{}, constantTransformer(1.0, 0.0));
  core::LidarConfig lidar;
  lidar.beams = 1081;
  EXPECT_THROW(controller.checkLidar(lidar), core::InputError);
  EXPECT_NO_THROW(controller.checkLidar(core::LidarConfig{}));
}

// ---- The policy file ----

TEST(LicsPolicyFile, AMissingFileTellsTheUserHowToMakeIt) {
  try {
    loadLicsPolicy("/nonexistent/lics_transformer_99.policy");
    FAIL() << "no InputError";
  } catch (const core::InputError& e) {
    EXPECT_THAT(e.what(), HasSubstr("/nonexistent/lics_transformer_99.policy"));
    EXPECT_THAT(e.what(), HasSubstr("tools/import_lics_weights.py transformer_99.pth --out"));
  }
  // Through the registry, with the path resolved against the config file's folder.
  try {
    makeControllerFactory(core::ConfigNode::parseString("type: lics\nlics: {policy: /nonexistent/x.policy}", "run.yaml"));
    FAIL() << "no InputError";
  } catch (const core::InputError& e) {
    EXPECT_THAT(e.what(), HasSubstr("import_lics_weights.py"));
  }
}

// ---- With your copy of the published weights ----

/// The imported policy: $BARN_LICS_POLICY, else the shipped config's path (tools/import_lics_weights.py
/// writes it); empty if neither exists.
std::string publishedPolicy() {
  if (const char* env = std::getenv("BARN_LICS_POLICY")) return env;
  const std::string path = std::string(BARN_SOURCE_DIR) + "/configs/policies/lics_transformer_99.policy";
  return std::filesystem::exists(path) ? path : "";
}
#define SKIP_WITHOUT_PUBLISHED_WEIGHTS(path)                                                                  \
  if ((path).empty())                                                                                       \
  GTEST_SKIP() << "no configs/policies/lics_transformer_99.policy: convert your copy of the published "     \
                  "transformer_99.pth with /usr/bin/python3 tools/import_lics_weights.py transformer_99.pth " \
                  "--out configs/policies/lics_transformer_99.policy (or set BARN_LICS_POLICY)"

TEST(LicsPublished, OnAnEmptyScanFacingTheGoalItDrivesAtFullSpeedAndVeersRight) {
  const std::string path = publishedPolicy();
  SKIP_WITHOUT_PUBLISHED_WEIGHTS(path);
  // docs/systems/lics.md: the network gives (2.00218964, -0.560057998) for an empty scan and the
  // goal (1, 0). v = clip(1.5 x 2.0022, ...) = 1.5; w = 1.2 x -0.560058 = -0.67207.
  const core::LidarConfig lidar;
  const core::LaserScan scan = uniformScan(lidar, kInf);
  LicsController controller(LicsConfig{}, loadLicsPolicy(path));
  controller.reset(barnEpisode());
  const core::Twist command = controller.act(observationAt(0.0, scan));
  EXPECT_NEAR(controller.localGoal().x(), 1.0, 1e-6);
  EXPECT_EQ(command.linear, 1.5);
  EXPECT_NEAR(command.angular, 1.2 * -0.560057998, 2e-5);  // the local goal's y is 0 to 1e-3
}

TEST(LicsPublished, TheShippedConfigHoldsTheCodesDefaults) {
  const std::string path = publishedPolicy();
  SKIP_WITHOUT_PUBLISHED_WEIGHTS(path);
  if (std::getenv("BARN_LICS_POLICY")) GTEST_SKIP() << "the shipped config names its own path";
  const std::string file = std::string(BARN_SOURCE_DIR) + "/configs/controllers/lics.yaml";
  const core::ConfigNode shipped = core::ConfigNode::parseFile(file);
  // The bare type resolves the default path against the working folder, the repository root.
  EXPECT_EQ(effectiveControllerConfig(shipped), effectiveControllerConfig(core::ConfigNode::parseString("type: lics", "defaults")));
}

}  // namespace
}  // namespace barn::controllers
