#include "barn/bench/episode.hpp"

#include <gmock/gmock.h>
#include <gtest/gtest.h>

#include <cmath>
#include <limits>
#include <numbers>
#include <stdexcept>
#include <string>
#include <vector>

#include "barn/controllers/registry.hpp"
#include "tests/bench/empty_world.hpp"
#include "tests/scratch_dir.hpp"
#include "barn/core/config.hpp"
#include "barn/core/protocol.hpp"
#include "barn/core/rng.hpp"
#include "barn/core/world_file.hpp"
#include "barn/core/world_geometry.hpp"
#include "barn/learning/applr_policy.hpp"
#include "barn/learning/mlp.hpp"
#include "barn/sim/lidar.hpp"

namespace barn::bench {
namespace {

using ::testing::HasSubstr;
using ::testing::IsEmpty;

// ---------------------------------------------------------------------------------------------
// Worlds

// emptyWorld plus a wall across the robot's line: cells (13..17, 5), cylinders at
// x = -4.425 + 0.15 r = -2.475, -2.325, -2.175, -2.025, -1.875 and y = 5.175 + 0.15 * 5 = 5.925.
// A one-column wall has no hollow interior, so every cell gets a cylinder.
core::WorldSpec blockedWorld() {
  core::WorldSpec w = emptyWorld();
  for (int r = 13; r <= 17; ++r) w.grid.at(r, 5) = 1;
  return w;
}

// ---------------------------------------------------------------------------------------------
// Test controllers (20 Hz, like the real ones)

class ConstantController : public controllers::Controller {
 public:
  explicit ConstantController(core::Twist cmd) : cmd_(cmd) {}
  void reset(const controllers::EpisodeInfo& /*info*/) override {}
  core::Twist act(const controllers::Observation& /*observation*/) override { return cmd_; }
  double period() const override { return 0.05; }

 private:
  core::Twist cmd_;
};

// Waits `delay` seconds without moving, then drives straight ahead at `speed`.
class DelayedController : public controllers::Controller {
 public:
  DelayedController(double delay, double speed) : delay_(delay), speed_(speed) {}
  void reset(const controllers::EpisodeInfo& /*info*/) override {}
  core::Twist act(const controllers::Observation& observation) override {
    return {observation.time < delay_ ? 0.0 : speed_, 0.0};
  }
  double period() const override { return 0.05; }

 private:
  double delay_;
  double speed_;
};

class NanController : public controllers::Controller {
 public:
  void reset(const controllers::EpisodeInfo& /*info*/) override {}
  core::Twist act(const controllers::Observation& observation) override {
    // Drives for half a second, then breaks.
    if (observation.time < 0.5) return {0.5, 0.0};
    return {std::numeric_limits<double>::quiet_NaN(), 0.0};
  }
  double period() const override { return 0.05; }
};

class ThrowingController : public controllers::Controller {
 public:
  void reset(const controllers::EpisodeInfo& /*info*/) override {}
  core::Twist act(const controllers::Observation& observation) override {
    if (observation.time >= 1.0) throw std::runtime_error("planner lost its costmap");
    return {0.5, 0.0};
  }
  double period() const override { return 0.05; }
};

class ThrowingResetController : public controllers::Controller {
 public:
  void reset(const controllers::EpisodeInfo& /*info*/) override { throw std::runtime_error("no map server"); }
  core::Twist act(const controllers::Observation& /*observation*/) override { return {1.0, 0.0}; }
  double period() const override { return 0.05; }
};

// Drives ahead and steers to the middle between the side returns at +-90 degrees, so the
// scan noise reaches the commands. Also remembers the seed it was given.
class CorridorController : public controllers::Controller {
 public:
  void reset(const controllers::EpisodeInfo& info) override { seed = info.seed; }
  core::Twist act(const controllers::Observation& observation) override {
    const core::LaserScan& scan = *observation.scan;
    const double left = scan.ranges[beamAt(scan, std::numbers::pi / 2)];
    const double right = scan.ranges[beamAt(scan, -std::numbers::pi / 2)];
    // Past the walls (y > 9.6) both sides are open: +inf, no steering.
    if (!std::isfinite(left) || !std::isfinite(right)) return {1.0, 0.0};
    return {1.0, 0.5 * (left - right)};
  }
  double period() const override { return 0.05; }

  std::uint64_t seed = 0;

 private:
  static std::size_t beamAt(const core::LaserScan& scan, double angle) {
    return static_cast<std::size_t>(std::lround((angle - scan.angle_min) / scan.angle_increment));
  }
};

// ---------------------------------------------------------------------------------------------

EpisodeResult run(const core::WorldSpec& world, controllers::Controller& controller,
                  const EpisodeConfig& config = {}, std::uint64_t seed = 1, bool record = false) {
  const sim::ObstacleField field = sim::ObstacleField::fromWorld(world);
  return runEpisode(world, field, controller, config, seed, record);
}

EpisodeConfig configFor(core::ProtocolName protocol) {
  EpisodeConfig config;
  config.protocol = protocol;
  return config;
}

// ---------------------------------------------------------------------------------------------
// Success, timeout, never moving

TEST(EpisodeConfig, TheShippedSimConfigHoldsExactlyTheCodesDefaults) {
  // configs/sim/barn.yaml says "every value is the default in the code": written back, it and
  // a default-constructed config give the same text, so neither can drift from the other.
  const std::string file = std::string(BARN_SOURCE_DIR) + "/configs/sim/barn.yaml";
  const EpisodeConfig shipped = validatedEpisodeConfig(core::ConfigNode::parseFile(file), file);
  EXPECT_EQ(core::writeConfig(shipped), core::writeConfig(EpisodeConfig{}));
}

TEST(EpisodeConfig, TheIsotropicFrictionConfigChangesOnlyTheTurnInPlace) {
  // configs/sim/isotropic_friction.yaml: the pivot and turn rate of the isotropic-friction
  // solution, every other value the default.
  const std::string file = std::string(BARN_SOURCE_DIR) + "/configs/sim/isotropic_friction.yaml";
  const EpisodeConfig shipped = validatedEpisodeConfig(core::ConfigNode::parseFile(file), file);
  EXPECT_DOUBLE_EQ(shipped.robot.icr_offset, 0.037);
  EXPECT_DOUBLE_EQ(shipped.robot.turn_efficiency, 1.037);
  EpisodeConfig expected;
  expected.robot.icr_offset = shipped.robot.icr_offset;
  expected.robot.turn_efficiency = shipped.robot.turn_efficiency;
  EXPECT_EQ(core::writeConfig(shipped), core::writeConfig(expected));
}

TEST(EpisodeConfig, TheProtocolIsReadByNameAndWrittenBackByName) {
  const EpisodeConfig config =
      validatedEpisodeConfig(core::ConfigNode::parseString("protocol: barn2024\n", "sim.yaml"), "sim.yaml");
  EXPECT_EQ(config.protocol, core::ProtocolName::Barn2024);
  EXPECT_THAT(core::writeConfig(config), HasSubstr("protocol: barn2024\n"));
}

TEST(EpisodeConfig, AnOutOfRangeFieldNamesTheFileTheKeyTheRangeAndTheUnit) {
  try {
    validatedEpisodeConfig(
        core::ConfigNode::parseString("success_radius: 4\nodometry: {position_stddev: 20}\nlatency: {command: -1}\n", "sim.yaml"),
        "sim.yaml");
    FAIL() << "every value is out of range";
  } catch (const core::InputError& e) {
    EXPECT_THAT(e.what(), HasSubstr("sim.yaml: success_radius: must be in (0, 3] m, got 4 m"));
    EXPECT_THAT(e.what(), HasSubstr("sim.yaml: odometry.position_stddev: must be in [0, 10] m, got 20 m"));
    EXPECT_THAT(e.what(), HasSubstr("sim.yaml: latency.command: must be in [0, 1] s, got -1 s"));
  }
}

TEST(EpisodeConfig, AnUnknownProtocolIsAnErrorNamingTheFieldAndTheKnownNames) {
  try {
    validatedEpisodeConfig(core::ConfigNode::parseString("protocol: barn2099\n", "sim.yaml"), "sim.yaml");
    FAIL() << "barn2099 is no protocol";
  } catch (const core::InputError& e) {
    EXPECT_THAT(std::string(e.what()), HasSubstr("protocol"));
    EXPECT_THAT(std::string(e.what()), HasSubstr("barn2023, barn2024"));
  }
}

TEST(Episode, DrivingStraightAtOneMeterPerSecondSucceedsAtTheExpectedTime) {
  ConstantController controller({1.0, 0.0});
  const EpisodeResult r = run(emptyWorld(), controller);
  ASSERT_EQ(r.outcome, Outcome::Success) << r.error;
  // Traction limits the acceleration to mu g = 0.5 * 9.81 = 4.905 m/s^2 (the wheel set-point
  // ramps at 20 m/s^2, faster). Reaching 1 m/s takes 1 / 4.905 = 0.204 s over
  // 1^2 / (2 * 4.905) = 0.102 m. The timer starts at 0.1 m: sqrt(2 * 0.1 / 4.905) = 0.202 s.
  // Success needs 9 m of travel (goal 10 m ahead, radius 1 m): reached at
  // 0.204 + (9 - 0.102) / 1 = 9.102 s, i.e. 9.102 - 0.202 = 8.90 s after the timer started.
  // AT is the next 0.1 s check: 8.9 (or 9.0 if the discrete steps land just past it).
  EXPECT_NEAR(r.actual_time, 8.9, 0.2);
  const double checks = r.actual_time / 0.1;
  EXPECT_NEAR(checks, std::round(checks), 1e-9) << "AT is a whole number of 0.1 s checks";
  EXPECT_EQ(r.score, core::barnScore(true, r.actual_time, r.optimal_time, core::protocolPreset("barn2023")));
  // OT = (hypot(0.325, 2.075) + 29 * 0.15 + hypot(0.325, 3.575)) / 2 = 10.04 / 2 = 5.02 s;
  // AT 8.9 < 4 OT = 20.08, so the score is the cap 1/4.
  EXPECT_NEAR(r.optimal_time, 5.0200, 1e-4);
  EXPECT_DOUBLE_EQ(r.score, 0.25);
  EXPECT_FALSE(r.collision.has_value());
  EXPECT_THAT(r.error, IsEmpty());
  // Sim time: the timer start (0.2 s) plus AT.
  EXPECT_NEAR(r.sim_time, r.actual_time + 0.2, 0.02);
  // Path: about 9 m + the overshoot to the check (<= 0.1 m at 1 m/s).
  EXPECT_NEAR(r.path_length, 9.05, 0.1);
}

TEST(Episode, AConfiguredSuccessRadiusMovesTheFinishLine) {
  // At 1 m/s a 0.5 m radius is reached 0.5 m later than the 1 m one: 0.5 s, five checks.
  ConstantController full({1.0, 0.0});
  const EpisodeResult at_one_metre = run(emptyWorld(), full);
  EpisodeConfig config;
  config.success_radius = 0.5;
  ConstantController half({1.0, 0.0});
  const EpisodeResult at_half_metre = run(emptyWorld(), half, config);
  ASSERT_EQ(at_half_metre.outcome, Outcome::Success) << at_half_metre.error;
  EXPECT_NEAR(at_half_metre.actual_time - at_one_metre.actual_time, 0.5, 0.1 + 1e-9);
  EXPECT_NEAR(at_half_metre.path_length - at_one_metre.path_length, 0.5, 0.1);
  // The optimal time is the reference path's, whatever the radius.
  EXPECT_DOUBLE_EQ(at_half_metre.optimal_time, at_one_metre.optimal_time);
}

TEST(EpisodeConfig, ASuccessRadiusOutsideZeroToThreeMetresIsAnErrorNamingTheField) {
  for (const char* text : {"success_radius: 0\n", "success_radius: -1\n", "success_radius: .nan\n", "success_radius: 3.5\n"}) {
    try {
      validatedEpisodeConfig(core::ConfigNode::parseString(text, "sim.yaml"), "sim.yaml");
      FAIL() << text << " was accepted";
    } catch (const core::InputError& e) {
      EXPECT_THAT(std::string(e.what()), HasSubstr("sim.yaml"));
      EXPECT_THAT(std::string(e.what()), HasSubstr("success_radius"));
    }
  }
  const EpisodeConfig config =
      validatedEpisodeConfig(core::ConfigNode::parseString("success_radius: 0.5\n", "sim.yaml"), "sim.yaml");
  EXPECT_EQ(episodeProtocol(config).success_radius, 0.5);
  EXPECT_EQ(episodeProtocol(config).start_x, core::protocolPreset("barn2023").start_x);
}

TEST(Episode, SlowRobotTimesOutOneHundredSecondsAfterTheTimerStarts) {
  ConstantController controller({0.05, 0.0});
  const EpisodeResult r = run(emptyWorld(), controller);
  // 0.05 m/s * 100 s = 5 m < 9 m: never within 1 m of the goal.
  EXPECT_EQ(r.outcome, Outcome::Timeout);
  EXPECT_DOUBLE_EQ(r.actual_time, 100.0);
  EXPECT_EQ(r.score, 0.0);
  // The timer starts once the robot is 0.1 m out: 0.1 m / 0.05 m/s = 2 s; then 100 s more.
  EXPECT_NEAR(r.sim_time, 102.0, 0.05);
  // 0.05 m/s * 102 s = 5.1 m.
  EXPECT_NEAR(r.path_length, 5.1, 0.02);
}

TEST(Episode, RobotThatNeverMovesTimesOutAfterOneHundredSeconds) {
  ConstantController controller({0.0, 0.0});
  const EpisodeResult r = run(emptyWorld(), controller);
  EXPECT_EQ(r.outcome, Outcome::Timeout);
  EXPECT_DOUBLE_EQ(r.actual_time, 100.0);
  EXPECT_EQ(r.score, 0.0);
  EXPECT_NEAR(r.sim_time, 100.0, 0.01);
  EXPECT_EQ(r.path_length, 0.0);
  EXPECT_EQ(r.mean_speed, 0.0);
}

TEST(Episode, LateStarterStillGetsOneHundredSecondsFromItsFirstMove) {
  // run.py waits for the first 0.1 m (no limit), then allows 100 s. A robot that sits for
  // 30 s (e.g. turning in place, which does not start the timer) and then drives at 0.1 m/s
  // needs (9 - 0.1) m / 0.1 m/s = 89 s after its timer started: a success, although the
  // sim clock reads about 30 + 1 + 89 = 120 s at the end.
  DelayedController slow(30.0, 0.1);
  const EpisodeResult success = run(emptyWorld(), slow);
  EXPECT_EQ(success.outcome, Outcome::Success);
  EXPECT_NEAR(success.actual_time, 89.0, 0.2);
  EXPECT_NEAR(success.sim_time, 120.0, 0.3);
  // 8 OT = 8 * 5.02 = 40.16 s < 89 s: the lowest success score, OT / (8 OT) = 1/8.
  EXPECT_DOUBLE_EQ(success.score, 0.125);

  // One that sits for 20 s and crawls at 0.05 m/s times out 100 s after moving 0.1 m:
  // 20 + 0.1 / 0.05 + 100 = 122 s of sim time.
  DelayedController crawl(20.0, 0.05);
  const EpisodeResult timeout = run(emptyWorld(), crawl);
  EXPECT_EQ(timeout.outcome, Outcome::Timeout);
  EXPECT_DOUBLE_EQ(timeout.actual_time, 100.0);
  EXPECT_NEAR(timeout.sim_time, 122.0, 0.1);
}

// ---------------------------------------------------------------------------------------------
// Controller failures

TEST(Episode, NanCommandEndsTheEpisodeWithAnError) {
  NanController controller;
  const EpisodeResult r = run(emptyWorld(), controller);
  EXPECT_EQ(r.outcome, Outcome::Error);
  EXPECT_THAT(r.error, HasSubstr("non-finite"));
  EXPECT_EQ(r.score, 0.0);
  // The first NaN comes at the 0.5 s tick.
  EXPECT_NEAR(r.sim_time, 0.5, 1e-6);
}

TEST(Episode, ThrowingControllerEndsTheEpisodeWithItsMessage) {
  ThrowingController controller;
  const EpisodeResult r = run(emptyWorld(), controller);
  EXPECT_EQ(r.outcome, Outcome::Error);
  EXPECT_THAT(r.error, HasSubstr("planner lost its costmap"));
  EXPECT_EQ(r.score, 0.0);
  EXPECT_NEAR(r.sim_time, 1.0, 1e-6);
  // The robot did drive before the throw: about 0.5 m/s * 1 s.
  EXPECT_GT(r.path_length, 0.3);
}

TEST(Episode, ControllerThatThrowsOnResetEndsWithAnError) {
  ThrowingResetController controller;
  const EpisodeResult r = run(emptyWorld(), controller);
  EXPECT_EQ(r.outcome, Outcome::Error);
  EXPECT_THAT(r.error, HasSubstr("no map server"));
  EXPECT_EQ(r.sim_time, 0.0);
}

// ---------------------------------------------------------------------------------------------
// Collision

TEST(Episode, DrivingIntoAWallIsACollisionAtTheTimeOfContact) {
  ConstantController controller({1.0, 0.0});
  const EpisodeResult r = run(blockedWorld(), controller);
  ASSERT_EQ(r.outcome, Outcome::Collision);
  ASSERT_TRUE(r.collision.has_value());
  EXPECT_EQ(r.score, 0.0);

  std::vector<Eigen::Vector2d> block;
  for (int row = 13; row <= 17; ++row) block.push_back(core::cellCentre({row, 5}));
  bool in_block = false;
  for (const auto& centre : block) in_block = in_block || centre == r.collision->point;
  EXPECT_TRUE(in_block) << r.collision->point.transpose();

  // Which part touches first: the front wheels reach 0.131 + 0.098 = 0.229 m ahead of the
  // centre, the chassis only 0.21 m. The front-left wheel (robot y = +0.188, world
  // x = -2 - 0.188 = -2.188, spanning x -2.208 .. -2.168) is straight behind the cylinder at
  // x = -2.175, whose near side is at y = 5.925 - 0.075 = 5.85: contact when the robot centre
  // reaches y = 5.85 - 0.229 = 5.621, after 2.621 m. (The chassis would touch the cylinder at
  // x = -2.025 only at y = 5.64; the front-right wheel the one at -1.875 at about y = 5.634.)
  EXPECT_EQ(r.collision->point, core::cellCentre({15, 5}));
  EXPECT_EQ(r.collision->rect_index, 1);  // front-left wheel
  // The pose at contact, where plots draw the robot's outline: straight ahead of the start.
  EXPECT_NEAR(r.collision->pose.x, -2.0, 0.01);
  EXPECT_NEAR(r.collision->pose.y, 5.621, 0.01);

  // Time: 0.204 s to reach 1 m/s over 0.102 m, then (2.621 - 0.102) / 1 = 2.519 s: 2.723 s.
  EXPECT_NEAR(r.collision->time, 2.723, 0.015);
  // AT for a collision is the time of contact since the timer start (0.2 s), not quantised.
  EXPECT_NEAR(r.actual_time, r.collision->time - 0.2, 0.01);
  EXPECT_NEAR(r.sim_time, r.collision->time, 1e-12);
}

// ---------------------------------------------------------------------------------------------
// Determinism

void expectSameTrajectory(const EpisodeResult& a, const EpisodeResult& b) {
  ASSERT_EQ(a.trajectory.size(), b.trajectory.size());
  for (std::size_t i = 0; i < a.trajectory.size(); ++i) {
    const TrajectorySample& s = a.trajectory[i];
    const TrajectorySample& t = b.trajectory[i];
    ASSERT_EQ(s.time, t.time) << i;
    ASSERT_EQ(s.pose.x, t.pose.x) << i;
    ASSERT_EQ(s.pose.y, t.pose.y) << i;
    ASSERT_EQ(s.pose.yaw, t.pose.yaw) << i;
    ASSERT_EQ(s.command.linear, t.command.linear) << i;
    ASSERT_EQ(s.command.angular, t.command.angular) << i;
    ASSERT_EQ(s.state, t.state) << i;
  }
}

TEST(Episode, SameSeedGivesABitIdenticalTrajectory) {
  CorridorController first;
  CorridorController second;
  const EpisodeResult a = run(emptyWorld(), first, {}, 77, true);
  const EpisodeResult b = run(emptyWorld(), second, {}, 77, true);
  ASSERT_FALSE(a.trajectory.empty());
  expectSameTrajectory(a, b);
  EXPECT_EQ(a.outcome, b.outcome);
  EXPECT_EQ(a.actual_time, b.actual_time);
  EXPECT_EQ(a.path_length, b.path_length);
  EXPECT_EQ(a.seed, 77u);
  EXPECT_EQ(first.seed, second.seed);
}

TEST(Episode, SameControllerObjectRunsTwoEpisodesIdentically) {
  CorridorController controller;  // reset() must start it afresh
  const EpisodeResult a = run(emptyWorld(), controller, {}, 5, true);
  const EpisodeResult b = run(emptyWorld(), controller, {}, 5, true);
  expectSameTrajectory(a, b);
}

TEST(Episode, EveryBuiltInControllerObjectReusedGivesWhatAFreshOneGives) {
  // reset() must forget everything of the previous episode, planner caches included (a new
  // costmap may sit at the old one's address with the same version and goal).
  const std::string root = BARN_SOURCE_DIR;
  const core::WorldSpec first_world = core::readWorldFile(root + "/worlds/world_000.yaml");
  const core::WorldSpec second_world = core::readWorldFile(root + "/worlds/world_010.yaml");
  for (const std::string name : {"pure_pursuit", "dwa", "eband", "lflh", "lflh_raw", "inventec_fi", "inventec_mpc"}) {
    const controllers::ControllerFactory factory =
        controllers::makeControllerFactory(core::ConfigNode::parseFile(root + "/configs/controllers/" + name + ".yaml"));
    const auto reused = factory();
    run(first_world, *reused, {}, 3);
    const EpisodeResult again = run(second_world, *reused, {}, 4, true);
    const auto fresh = factory();
    const EpisodeResult expected = run(second_world, *fresh, {}, 4, true);
    SCOPED_TRACE(name);
    EXPECT_EQ(again.outcome, expected.outcome);
    expectSameTrajectory(again, expected);
  }
}

TEST(Episode, AReusedApplrDwaGivesWhatAFreshOneGivesAndRecordsItsParameters) {
  // A random actor of the published shape stands in for the published one (not shipped): its
  // parameters change every second, and reset() must put the DWA's and the costmaps' back.
  const test::ScratchDir scratch("barn_episode_applr");
  learning::Mlp<float> actor(721, 16, 7);
  core::Rng rng(3);
  actor.initialise(rng);
  learning::ApplrPolicyInfo info;
  info.actions = {{"max_vel_x", 0.2, 2.0},          {"max_vel_theta", 0.314, 3.14},   {"vx_samples", 4.0, 12.0},
                  {"vtheta_samples", 8.0, 40.0},    {"path_distance_bias", 0.1, 1.5}, {"goal_distance_bias", 0.1, 2.0},
                  {"inflation_radius", 0.1, 0.6}};
  info.name = "random";
  learning::writeApplrPolicyFile(scratch.path() / "random.policy", info, actor.parameters());
  const controllers::ControllerFactory factory = controllers::makeControllerFactory(core::ConfigNode::parseString(
      "type: applr_dwa\napplr_dwa: {policy: " + (scratch.path() / "random.policy").string() + "}\n", "applr.yaml"));
  const std::string root = BARN_SOURCE_DIR;
  const core::WorldSpec first_world = core::readWorldFile(root + "/worlds/world_000.yaml");
  const core::WorldSpec second_world = core::readWorldFile(root + "/worlds/world_010.yaml");
  const auto reused = factory();
  run(first_world, *reused, {}, 3);
  const EpisodeResult again = run(second_world, *reused, {}, 4, true);
  const auto fresh = factory();
  const EpisodeResult expected = run(second_world, *fresh, {}, 4, true);
  EXPECT_EQ(again.outcome, expected.outcome);
  expectSameTrajectory(again, expected);
  // The trajectory records the parameters at the ticks that set them: 0 s, 1 s, ...
  ASSERT_GT(again.trajectory.size(), 21u);
  EXPECT_THAT(again.trajectory[0].parameters, ::testing::HasSubstr(";vx_samples="));
  EXPECT_EQ(again.trajectory[1].parameters, "");
  EXPECT_THAT(again.trajectory[20].parameters, ::testing::StartsWith("max_vel_x="));
}

TEST(Episode, SteppingByHandGivesWhatRunEpisodeGives) {
  // The steppable episode driven by a caller's own loop, as Python or an external program
  // drives it, with odometry noise on so that a tick's observation must be drawn only once.
  EpisodeConfig config;
  config.odometry.position_stddev = 0.01;
  CorridorController controller;
  const EpisodeResult expected = run(emptyWorld(), controller, config, 9, true);
  const sim::ObstacleField field = sim::ObstacleField::fromWorld(emptyWorld());
  Episode episode(emptyWorld(), field, config, 9, controller.period());
  CorridorController mine;
  mine.reset(episode.info());
  std::size_t tick = 0;
  while (!episode.done()) {
    const controllers::Observation first = episode.observation();
    const controllers::Observation& again = episode.observation();
    ASSERT_EQ(first.odom_pose.x, again.odom_pose.x);  // reading twice draws nothing new
    ASSERT_LT(tick, expected.trajectory.size());
    EXPECT_EQ(episode.tickPose().x, expected.trajectory[tick].pose.x) << tick;
    episode.step(mine.act(first));
    ++tick;
  }
  EXPECT_EQ(tick, expected.trajectory.size());
  const EpisodeResult r = episode.result();
  EXPECT_EQ(r.outcome, expected.outcome);
  EXPECT_EQ(r.actual_time, expected.actual_time);
  EXPECT_EQ(r.score, expected.score);
  EXPECT_EQ(r.path_length, expected.path_length);
  EXPECT_EQ(r.sim_time, expected.sim_time);
}

TEST(Episode, StepAfterTheEndChangesNothing) {
  const sim::ObstacleField field = sim::ObstacleField::fromWorld(emptyWorld());
  Episode episode(emptyWorld(), field, {}, 2, 0.05);
  while (!episode.done()) episode.step({2.0, 0.0});
  const EpisodeResult done = episode.result();
  episode.step({2.0, 0.0});
  EXPECT_EQ(episode.result().sim_time, done.sim_time);
  EXPECT_EQ(done.outcome, Outcome::Success);
}

TEST(Episode, RejectsANonPositiveControlPeriod) {
  const sim::ObstacleField field = sim::ObstacleField::fromWorld(emptyWorld());
  EXPECT_THROW(Episode(emptyWorld(), field, {}, 2, 0.0), core::InputError);
  EXPECT_THROW(Episode(emptyWorld(), field, {}, 2, std::nan("")), core::InputError);
}

TEST(Episode, DifferentSeedGivesDifferentScanNoise) {
  CorridorController first;
  CorridorController second;
  const EpisodeResult a = run(emptyWorld(), first, {}, 1, true);
  const EpisodeResult b = run(emptyWorld(), second, {}, 2, true);
  // The noise (sigma 1 mm) reaches the steering command at the very first tick.
  ASSERT_FALSE(a.trajectory.empty());
  ASSERT_FALSE(b.trajectory.empty());
  EXPECT_NE(a.trajectory.front().command.angular, b.trajectory.front().command.angular);
  // The controller's own seed differs too.
  EXPECT_NE(first.seed, second.seed);
  // The noise is far too small to change what happens in an empty corridor.
  EXPECT_EQ(a.outcome, Outcome::Success);
  EXPECT_EQ(b.outcome, Outcome::Success);
}

TEST(Episode, AScanIsTheSameWhetherOrNotTheScansBeforeItWereRead) {
  // Scans no controller reads are never cast, so each scan's noise must not depend on how
  // many were cast before it. The same open-loop drive (so the same poses) stepped at the
  // LiDAR's 50 Hz, which reads every scan, and at 10 Hz, which reads one in five: at every
  // time both read, the ranges agree bit for bit, noise included.
  const core::WorldSpec world = blockedWorld();
  const sim::ObstacleField field = sim::ObstacleField::fromWorld(world);
  const core::Twist drive{0.4, 0.3};
  Episode every_scan(world, field, {}, 4, 0.02);
  Episode every_fifth(world, field, {}, 4, 0.1);
  const core::LidarConfig lidar;
  sim::LidarCaster caster(lidar, field);
  std::vector<double> clean;
  int compared = 0;
  int noisy_beams = 0;
  while (!every_fifth.done() && compared < 20) {
    const controllers::Observation& sparse = every_fifth.observation();
    while (every_scan.observation().time < sparse.time - 1e-9) every_scan.step(drive);
    const controllers::Observation& dense = every_scan.observation();
    ASSERT_EQ(dense.time, sparse.time);
    ASSERT_EQ(dense.scan->stamp, sparse.scan->stamp);
    ASSERT_EQ(dense.scan->ranges, sparse.scan->ranges) << "at t = " << sparse.time;
    caster.cast(lidar.sensorPose(every_fifth.tickPose()), clean);  // the scan's pose: same step
    for (std::size_t i = 0; i < clean.size(); ++i)
      if (std::isfinite(clean[i]) && sparse.scan->ranges[i] != clean[i]) ++noisy_beams;
    ++compared;
    every_fifth.step(drive);
  }
  EXPECT_EQ(compared, 20);
  EXPECT_GT(noisy_beams, 1000);  // and they carry noise
}

TEST(Episode, TheScanComesWithTheOdometryOfItsCapture) {
  // At 20 Hz every other tick reads a scan taken 10 ms earlier (the LiDAR runs at 50 Hz). Its
  // pose must be the odometry of that moment, as tf gives a ROS node at the scan's stamp: the
  // pose the same drive reports at that time when stepped at the LiDAR's own rate.
  const core::WorldSpec world = blockedWorld();
  const sim::ObstacleField field = sim::ObstacleField::fromWorld(world);
  const core::Twist drive{0.4, 0.3};
  Episode at_20hz(world, field, {}, 4, 0.05);
  Episode at_50hz(world, field, {}, 4, 0.02);
  int older_scans = 0;
  for (int tick = 0; tick < 20 && !at_20hz.done(); ++tick) {
    const controllers::Observation& obs = at_20hz.observation();
    while (at_50hz.observation().time < obs.scan->stamp - 1e-9) at_50hz.step(drive);
    const controllers::Observation& at_capture = at_50hz.observation();
    ASSERT_EQ(at_capture.time, obs.scan->stamp);
    EXPECT_EQ(obs.scan_odom_pose.x, at_capture.odom_pose.x) << "at t = " << obs.time;
    EXPECT_EQ(obs.scan_odom_pose.y, at_capture.odom_pose.y);
    EXPECT_EQ(obs.scan_odom_pose.yaw, at_capture.odom_pose.yaw);
    if (obs.scan->stamp < obs.time - 1e-9) {
      ++older_scans;
      EXPECT_GT((obs.odom_pose.position() - obs.scan_odom_pose.position()).norm(), 0.001);  // moved since
    } else {
      EXPECT_EQ(obs.scan_odom_pose.x, obs.odom_pose.x);
    }
    at_20hz.step(drive);
  }
  EXPECT_EQ(older_scans, 10);
}

TEST(Episode, TrajectoryIsOnlyRecordedWhenAsked) {
  ConstantController controller({1.0, 0.0});
  EXPECT_TRUE(run(emptyWorld(), controller, {}, 1, false).trajectory.empty());
  const EpisodeResult r = run(emptyWorld(), controller, {}, 1, true);
  // One sample per 0.05 s control tick: about 9.1 s / 0.05 = 182.
  EXPECT_NEAR(static_cast<double>(r.trajectory.size()), r.sim_time / 0.05, 1.5);
  EXPECT_EQ(r.trajectory.front().time, 0.0);
  EXPECT_EQ(r.trajectory.front().command.linear, 1.0);
}

// ---------------------------------------------------------------------------------------------
// Protocols

TEST(Episode, Barn2023StartsAtMinusTwo) {
  ConstantController controller({1.0, 0.0});
  const EpisodeResult r = run(emptyWorld(), controller, configFor(core::ProtocolName::Barn2023), 1, true);
  ASSERT_FALSE(r.trajectory.empty());
  EXPECT_EQ(r.trajectory.front().pose.x, -2.0);
  EXPECT_EQ(r.trajectory.front().pose.y, 3.0);
  EXPECT_EQ(r.trajectory.front().pose.yaw, 1.57);
}

TEST(Episode, Barn2024StartsOnTheCorridorCentreAndClipsAtTwiceOt) {
  ConstantController controller({2.0, 0.0});
  const core::Protocol protocol = core::protocolPreset("barn2024");
  const EpisodeResult r = run(emptyWorld(), controller, configFor(core::ProtocolName::Barn2024), 1, true);
  ASSERT_FALSE(r.trajectory.empty());
  EXPECT_EQ(r.trajectory.front().pose.x, -2.25);
  EXPECT_EQ(r.trajectory.front().pose.y, 3.0);
  ASSERT_EQ(r.outcome, Outcome::Success) << r.error;
  // OT from x = -2.25: (hypot(0.075, 2.075) + 4.35 + hypot(0.075, 3.575)) / 2
  //   = (2.07635 + 4.35 + 3.57579) / 2 = 5.00107 s.
  EXPECT_NEAR(r.optimal_time, 5.00107, 1e-5);
  // At 2 m/s: 2 / 4.905 = 0.408 s to reach speed over 2^2 / (2 * 4.905) = 0.408 m, then
  // (9 - 0.408) / 2 = 4.296 s; the timer starts at 0.202 s, so the goal radius is reached
  // 0.408 + 4.296 - 0.202 = 4.502 s in, just after the 4.5 s check: AT = 4.6 s.
  EXPECT_NEAR(r.actual_time, 4.6, 0.15);
  // AT 4.5 < 2 OT = 10.0: clipped to 2 OT, score OT / (2 OT) = 0.5 (barn2023 would give 0.25).
  EXPECT_DOUBLE_EQ(r.score, 0.5);
  EXPECT_EQ(r.score, core::barnScore(true, r.actual_time, r.optimal_time, protocol));
  EXPECT_DOUBLE_EQ(core::barnScore(true, r.actual_time, r.optimal_time, core::protocolPreset("barn2023")), 0.25);
}

TEST(Episode, ReferencePathIsInTheOdomFrame) {
  // Cell (15, c) centre: (-4.425 + 2.25, 5.175 + 0.15 c) = (-2.175, 5.175 + 0.15 c); minus the
  // start (-2, 3): (-0.175, 2.175 + 0.15 c). The duplicated start cell appears once.
  const auto path = referencePathInOdom(emptyWorld(), core::protocolPreset("barn2023"));
  ASSERT_EQ(path.size(), 30u);
  EXPECT_NEAR(path.front().x(), -0.175, 1e-12);
  EXPECT_NEAR(path.front().y(), 2.175, 1e-12);
  EXPECT_NEAR(path.back().y(), 2.175 + 0.15 * 29, 1e-12);
}

// ---------------------------------------------------------------------------------------------
// State labels: bounded for every route (runEpisode, the Python Env, external programs)

// Stands still, labelling its n-th tick "s<n mod cycle>" (cycle 0: never repeating), or with a
// `width`-byte label when width > 0.
class LabellingController : public controllers::Controller {
 public:
  LabellingController(int cycle, std::size_t width) : cycle_(cycle), width_(width) {}
  void reset(const controllers::EpisodeInfo&) override { tick_ = 0; }
  core::Twist act(const controllers::Observation&) override {
    const int n = tick_++;
    label_ = width_ > 0 ? std::string(width_, 'y') : "s" + std::to_string(cycle_ > 0 ? n % cycle_ : n);
    return {0.0, 0.0};
  }
  double period() const override { return 0.05; }
  std::string_view stateLabel() const override { return label_; }

 private:
  int cycle_;
  std::size_t width_;
  int tick_ = 0;
  std::string label_;
};

TEST(Episode, TheSixtyFifthDistinctStateLabelEndsTheEpisodeAsAnError) {
  // A new label every tick (0.05 s): labels s0..s63 are counted, the 65th (tick 64, t = 3.2 s)
  // ends the episode; the row keeps 64 entries.
  LabellingController controller(0, 0);
  const EpisodeResult r = run(emptyWorld(), controller, {}, 1, true);
  EXPECT_EQ(r.outcome, Outcome::Error);
  EXPECT_THAT(r.error, HasSubstr("more than 64 distinct state labels"));
  EXPECT_EQ(r.state_entries.size(), kMaxStateLabels);
  EXPECT_NEAR(r.sim_time, 64 * 0.05, 1e-9);
  // Re-entering known labels is no breach: 50 labels in turn until the 100 s timeout, ticks at
  // t = 0, 0.05, ..., 100: 2001 entries, s0 41 times (ticks 0, 50, ..., 2000), s49 40 times.
  LabellingController cycling(50, 0);
  const EpisodeResult ok = run(emptyWorld(), cycling);
  EXPECT_EQ(ok.outcome, Outcome::Timeout) << ok.error;
  ASSERT_EQ(ok.state_entries.size(), 50u);
  EXPECT_EQ(ok.state_entries.front().second, 41);
  EXPECT_EQ(ok.state_entries.back().second, 40);
}

TEST(Episode, AStateLabelLongerThanTheBoundEndsTheEpisodeAsAnError) {
  LabellingController at_bound(0, kMaxStateLabelBytes);
  LabellingController wide(0, kMaxStateLabelBytes + 1);
  EXPECT_NE(run(emptyWorld(), at_bound).outcome, Outcome::Error);
  const EpisodeResult r = run(emptyWorld(), wide, {}, 1, true);
  EXPECT_EQ(r.outcome, Outcome::Error);
  EXPECT_THAT(r.error, HasSubstr("state label of 65 bytes (the limit is 64 bytes)"));
  EXPECT_TRUE(r.state_entries.empty());
  ASSERT_EQ(r.trajectory.size(), 1u);  // the first tick, its label cut to the bound
  EXPECT_EQ(r.trajectory.front().state.size(), kMaxStateLabelBytes);
}

}  // namespace
}  // namespace barn::bench
