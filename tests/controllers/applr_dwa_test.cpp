#include "barn/controllers/applr_dwa.hpp"

#include <cmath>
#include <numbers>
#include <string>
#include <vector>

#include <gmock/gmock.h>
#include <gtest/gtest.h>

#include "barn/core/errors.hpp"
#include "scan_fixtures.hpp"

namespace barn::controllers {
namespace {

using ::testing::HasSubstr;
using ::testing::StartsWith;
constexpr double kPi = std::numbers::pi;

// ---- The Savitzky-Golay smoothing of the plan ----

TEST(SavitzkyGolay, AnImpulseGivesTheCubicWindowsWeights) {
  // Window 19 (m = 9), cubic: the centre weights are (3 (3 m^2 + 3 m - 1) - 15 k^2) /
  // ((2 m - 1)(2 m + 1)(2 m + 3)) = (807 - 15 k^2) / 6783 for k = -9 .. 9. An impulse at index 20
  // of 41 zeros gives at index 20 + k the weight of -k (symmetric): 807 / 6783 at 20,
  // (807 - 15 x 81) / 6783 = -408 / 6783 at 11 and 29, and nothing 10 away.
  std::vector<double> impulse(41, 0.0);
  impulse[20] = 1.0;
  const std::vector<double> out = savitzkyGolay(impulse, 19, 3);
  ASSERT_EQ(out.size(), 41u);
  EXPECT_NEAR(out[20], 807.0 / 6783.0, 1e-12);
  EXPECT_NEAR(out[11], -408.0 / 6783.0, 1e-12);
  EXPECT_NEAR(out[29], -408.0 / 6783.0, 1e-12);
  EXPECT_NEAR(out[19], (807.0 - 15.0) / 6783.0, 1e-12);
  EXPECT_NEAR(out[10], 0.0, 1e-12);
  EXPECT_NEAR(out[30], 0.0, 1e-12);
}

TEST(SavitzkyGolay, ACubicComesBackExactlyEndsIncluded) {
  // The least-squares cubic through any window of a cubic is the cubic itself, so the interior
  // and both end fits reproduce it.
  std::vector<double> cubic;
  for (int i = 0; i < 25; ++i) cubic.push_back(0.01 * i * i * i - 0.3 * i * i + 2.0 * i - 1.0);
  const std::vector<double> out = savitzkyGolay(cubic, 19, 3);
  for (std::size_t i = 0; i < cubic.size(); ++i) EXPECT_NEAR(out[i], cubic[i], 1e-9) << i;
}

TEST(SavitzkyGolay, FewerPointsThanTheWindowAreLeftAsTheyAre) {
  // scipy raises for 18 points and a window of 19; APPLR then keeps the raw path.
  std::vector<double> values(18);
  for (std::size_t i = 0; i < values.size(); ++i) values[i] = (i % 3 == 0) ? 1.0 : 0.0;
  EXPECT_EQ(savitzkyGolay(values, 19, 3), values);
}

// ---- The local goal's angle ----

TEST(ApplrGoalAngle, IsTheAngleOfTheFirstPlanPointFartherThanLosInTheRobotFrame) {
  // Unsmoothed: (0, 0), (0.5, 0), (0.5, 0.5), (0.5, 1) are 0, 0.5, 0.707 and 1.118 m from the
  // robot at the origin: the first beyond 1 m is (0.5, 1), at atan2(1, 0.5) = 1.1071 rad.
  const nav::Path l_shape = {{0.0, 0.0}, {0.5, 0.0}, {0.5, 0.5}, {0.5, 1.0}};
  EXPECT_NEAR(applrGoalAngle(l_shape, {0.0, 0.0, 0.0}, 1.0, 0, 3), std::atan2(1.0, 0.5), 1e-12);
  // The robot facing +y (yaw pi / 2): the same point is at atan2(1, 0.5) - pi / 2 = -0.4636 rad.
  EXPECT_NEAR(applrGoalAngle(l_shape, {0.0, 0.0, kPi / 2.0}, 1.0, 0, 3), std::atan2(1.0, 0.5) - kPi / 2.0, 1e-12);
  // No point farther than 1.5 m: the last one.
  EXPECT_NEAR(applrGoalAngle(l_shape, {0.0, 0.0, 0.0}, 1.5, 0, 3), std::atan2(1.0, 0.5), 1e-12);
  // No plan yet: the local goal stays (0, 0), atan2(0, 0) = 0.
  EXPECT_EQ(applrGoalAngle({}, {1.0, 2.0, 0.3}, 1.0, 19, 3), 0.0);
}

TEST(ApplrGoalAngle, ASmoothedStraightPlanStaysStraight) {
  // 41 points 0.05 m apart straight ahead along +x (a line survives the cubic smoothing): the
  // first beyond 1 m from the robot at the origin is dead ahead.
  nav::Path straight;
  for (int i = 0; i <= 40; ++i) straight.push_back({0.05 * i, 0.0});
  EXPECT_NEAR(applrGoalAngle(straight, {0.0, 0.0, 0.0}, 1.0, 19, 3), 0.0, 1e-12);
  // From (0, 0.2): sqrt(x^2 + 0.04) > 1 first at x = 1.0 (1.0198 m): atan2(-0.2, 1.0).
  EXPECT_NEAR(applrGoalAngle(straight, {0.0, 0.2, 0.0}, 1.0, 19, 3), std::atan2(-0.2, 1.0), 1e-9);
}

// ---- The controller ----

// The published actions and ranges (docs/systems/applr_dwa.md).
std::vector<learning::ApplrAction> publishedActions() {
  return {{"max_vel_x", 0.2, 2.0},          {"max_vel_theta", 0.314, 3.14},   {"vx_samples", 4.0, 12.0},
          {"vtheta_samples", 8.0, 40.0},    {"path_distance_bias", 0.1, 1.5}, {"goal_distance_bias", 0.1, 2.0},
          {"inflation_radius", 0.1, 0.6}};
}

// An actor of 720 beams whose tanh outputs are always `u`: zero weights, output bias atanh(u).
std::shared_ptr<const learning::ApplrPolicy> constantActor(const std::vector<double>& u,
                                                           std::vector<learning::ApplrAction> actions = publishedActions()) {
  learning::ApplrPolicyInfo info;
  info.actions = std::move(actions);
  info.name = "constant";
  learning::MlpParameters<float> weights = learning::MlpParameters<float>::zeros(721, 2, static_cast<int>(u.size()));
  for (std::size_t i = 0; i < u.size(); ++i) weights.b3[static_cast<Eigen::Index>(i)] = static_cast<float>(std::atanh(u[i]));
  return std::make_shared<const learning::ApplrPolicy>(info, weights);
}

// The robot at the odom origin facing +y, the goal 8 m ahead, nothing in sight.
struct Drive {
  explicit Drive(std::shared_ptr<const learning::ApplrPolicy> actor) : controller(ApplrDwaConfig{}, std::move(actor)) {
    info.goal = {0.0, 8.0};
    info.start = {0.0, 0.0, kPi / 2.0};
    controller.reset(info);
  }
  // One control tick at time 0.05 k with a fresh scan.
  void tick(int k) {
    scan = uniformScan(info.lidar, std::numeric_limits<double>::infinity());
    scan.stamp = 0.05 * k;
    Observation obs;
    obs.time = 0.05 * k;
    obs.scan = &scan;
    obs.odom_pose = obs.scan_odom_pose = info.start;
    obs.goal = info.goal;
    controller.act(obs);
  }
  EpisodeInfo info;
  core::LaserScan scan;
  ApplrDwaController controller;
};

TEST(ApplrDwa, SetsTheParametersAtTheFirstTickAndEverySecondAfter) {
  Drive drive(constantActor({0, 0, 0, 0, 0, 0, 0}));
  std::vector<int> updated;
  for (int k = 0; k <= 50; ++k) {
    drive.tick(k);
    if (!drive.controller.parameterChanges().empty()) updated.push_back(k);
  }
  // Ticks every 0.05 s: the updates at 0, 1 and 2 s are ticks 0, 20 and 40.
  EXPECT_EQ(updated, (std::vector<int>{0, 20, 40}));
}

TEST(ApplrDwa, PutsTheMidRangeParametersOnTheDwaAndBothCostmaps) {
  // u = 0 everywhere: each parameter at its range's middle (float32 arithmetic):
  // max_vel_x 1.1, max_vel_theta 1.727, vx_samples 8, vtheta_samples 24, pdist 0.8, gdist 1.05,
  // inflation 0.35 (in float32: (0.6f + 0.1f) / 2 = 0.350000024).
  Drive drive(constantActor({0, 0, 0, 0, 0, 0, 0}));
  drive.tick(0);
  const DwaConfig& p = drive.controller.dwa().parameters();
  EXPECT_NEAR(p.max_vel_x, 1.1, 1e-6);
  EXPECT_NEAR(p.max_vel_theta, 1.727, 1e-6);
  EXPECT_EQ(p.vx_samples, 8);
  EXPECT_EQ(p.vtheta_samples, 24);
  EXPECT_NEAR(p.pdist_scale, 0.8, 1e-6);
  EXPECT_NEAR(p.gdist_scale, 1.05, 1e-6);
  EXPECT_THAT(std::string(drive.controller.parameterChanges()), StartsWith("max_vel_x=1.100000023841858;"));
  EXPECT_THAT(std::string(drive.controller.parameterChanges()), HasSubstr(";vx_samples=8;vtheta_samples=24;"));
  EXPECT_THAT(std::string(drive.controller.parameterChanges()),
              HasSubstr(";global_costmap.inflation_radius=0.3500000238418579;local_costmap.inflation_radius=0.3500000238418579"));
  // The inflation radius reaches each costmap at its next update: the local map's (20 Hz) at
  // tick 1, the global map's (10 Hz) at tick 2.
  drive.tick(1);
  drive.tick(2);
  EXPECT_NEAR(drive.controller.dwa().navStack().globalCostmap().config().inflation_radius, 0.35, 1e-6);
  EXPECT_NEAR(drive.controller.dwa().navStack().localCostmap().config().inflation_radius, 0.35, 1e-6);
}

TEST(ApplrDwa, TruncatesTheSampleCountsAsDynamicReconfiguresIntDoes) {
  // vx_samples: 8 + 4 u with u = -0.025 -> 7.9 -> 7; vtheta_samples: 24 + 16 u with u = 0.99 ->
  // 39.84 -> 39.
  Drive drive(constantActor({0, 0, -0.025, 0.99, 0, 0, 0}));
  drive.tick(0);
  EXPECT_EQ(drive.controller.dwa().parameters().vx_samples, 7);
  EXPECT_EQ(drive.controller.dwa().parameters().vtheta_samples, 39);
  EXPECT_DOUBLE_EQ(drive.controller.lastParameters()[2], 7.0);
}

TEST(ApplrDwa, ResetRestoresTheConfiguredDwaAndUpdatesAgainAtTheStart) {
  Drive drive(constantActor({0.5, 0.5, 0.5, 0.5, 0.5, 0.5, 0.5}));
  drive.tick(0);
  drive.tick(1);
  ASSERT_NE(drive.controller.dwa().parameters().vx_samples, 6);
  drive.controller.reset(drive.info);
  // BARN's DWA values: max_vel_x 0.5, vx_samples 6, vtheta_samples 20, inflation 0.3.
  EXPECT_EQ(drive.controller.dwa().parameters().max_vel_x, 0.5);
  EXPECT_EQ(drive.controller.dwa().parameters().vx_samples, 6);
  EXPECT_EQ(drive.controller.dwa().parameters().vtheta_samples, 20);
  EXPECT_EQ(drive.controller.dwa().navStack().localCostmap().config().inflation_radius, 0.3);
  EXPECT_TRUE(drive.controller.lastParameters().empty());
  drive.tick(0);
  EXPECT_FALSE(drive.controller.parameterChanges().empty());
}

TEST(ApplrDwa, AnActorWithAnActionItCannotSetIsAnInputError) {
  std::vector<learning::ApplrAction> actions = publishedActions();
  actions[0].name = "max_speed";
  EXPECT_THAT([&] { ApplrDwaController(ApplrDwaConfig{}, constantActor({0, 0, 0, 0, 0, 0, 0}, actions)); },
              ::testing::ThrowsMessage<core::InputError>(HasSubstr("action max_speed is not a parameter applr_dwa sets")));
  // vx_samples down to 1: the DWA needs at least 2 samples.
  actions = publishedActions();
  actions[2].lo = 1.0;
  EXPECT_THAT([&] { ApplrDwaController(ApplrDwaConfig{}, constantActor({0, 0, 0, 0, 0, 0, 0}, actions)); },
              ::testing::ThrowsMessage<core::InputError>(HasSubstr("the DWA refuses 1")));
}

TEST(ApplrDwa, ALidarOfAnotherBeamCountIsRefusedBeforeTheRun) {
  const ApplrDwaController controller(ApplrDwaConfig{}, constantActor({0, 0, 0, 0, 0, 0, 0}));
  core::LidarConfig lidar;
  EXPECT_NO_THROW(controller.checkLidar(lidar));
  lidar.beams = 360;
  EXPECT_THROW(controller.checkLidar(lidar), core::InputError);
}

TEST(ApplrDwa, AMissingActorNamesTheImportCommand) {
  EXPECT_THAT([] { loadApplrPolicy("/nonexistent/applr_dwa.policy", ""); },
              ::testing::ThrowsMessage<core::InputError>(
                  HasSubstr("tools/import_applr_weights.py policy_actor --out /nonexistent/applr_dwa.policy")));
}

TEST(ApplrDwaConfig, ValidateNamesEachBadField) {
  ApplrDwaConfig config;
  config.period = 0.0;
  config.smoothing_window = 18;
  config.dwa.vx_samples = 1;
  core::Errors errors;
  validate(config, errors, "applr_dwa");
  ASSERT_EQ(errors.messages().size(), 3u);
  EXPECT_THAT(errors.messages()[0], HasSubstr("applr_dwa.period"));
  EXPECT_THAT(errors.messages()[1], HasSubstr("applr_dwa.smoothing_window"));
  EXPECT_THAT(errors.messages()[2], HasSubstr("applr_dwa.dwa.vx_samples"));
}

}  // namespace
}  // namespace barn::controllers
