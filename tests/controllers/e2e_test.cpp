#include "barn/controllers/e2e.hpp"

#include <gmock/gmock.h>
#include <gtest/gtest.h>

#include <cmath>
#include <limits>
#include <numbers>

#include "barn/bench/episode.hpp"
#include "barn/core/config.hpp"
#include "barn/controllers/registry.hpp"
#include "../bench/empty_world.hpp"

namespace barn::controllers {
namespace {

using ::testing::HasSubstr;

TEST(E2e, AFrameIsTheClippedScaledScanThePlanEndAndThePreviousAction) {
  // Clip 5 m: (r - 2.5) / 2.5, so 0.5 -> -0.8, 5 -> 1, +inf -> 1, 7.5 -> 1, NaN -> 1, 2.5 -> 0.
  const double ranges[6] = {0.5, 5.0, std::numeric_limits<double>::infinity(), 7.5, std::nan(""), 2.5};
  // The robot at (1, 2) facing +y (yaw pi/2), the plan ending at (1, 7) in the odom frame:
  // 5 m straight ahead, (5, 0) in the robot frame -> (5 / 5 - 1, 0 / 5 - 1) = (0, -1).
  const core::Pose2 pose{1.0, 2.0, std::numbers::pi / 2};
  const Eigen::Vector2d end = pose.inverseTransform({1.0, 7.0});
  EXPECT_NEAR(end.x(), 5.0, 1e-12);
  EXPECT_NEAR(end.y(), 0.0, 1e-12);
  // The previous action (0.5, 1.57): v in [-1, 2] has bias 0.5, scale 1.5 -> 0; w in
  // [-3.14, 3.14] has bias 0, scale 3.14 -> 0.5.
  float frame[10];
  encodeE2eFrame(ranges, 6, end, core::Twist{0.5, 1.57}, E2eEncoding{}, frame);
  const float expected[10] = {-0.8f, 1.0f, 1.0f, 1.0f, 1.0f, 0.0f, 0.0f, -1.0f, 0.0f, 0.5f};
  for (int k = 0; k < 10; ++k) EXPECT_NEAR(frame[k], expected[k], 1e-6) << k;
  // The same ranges as float32 (what VecEnv's scan holds) encode to the same values.
  const float narrow[6] = {0.5f, 5.0f, std::numeric_limits<float>::infinity(), 7.5f, std::nanf(""), 2.5f};
  float again[10];
  encodeE2eFrame(narrow, 6, end, core::Twist{0.5, 1.57}, E2eEncoding{}, again);
  for (int k = 0; k < 10; ++k) EXPECT_FLOAT_EQ(again[k], frame[k]) << k;
  // Standing still at the start: v 0 -> (0 - 0.5) / 1.5 = -1/3.
  encodeE2eFrame(ranges, 6, end, core::Twist{0.0, 0.0}, E2eEncoding{}, frame);
  EXPECT_NEAR(frame[8], -1.0 / 3.0, 1e-7);
}

TEST(E2e, TheInputTextNamesTheEncoding) {
  EXPECT_EQ(e2eInputText(E2eEncoding{}), "e2e frames=4 range_clip=5 goal_scale=5 v=-1,2 w=-3.14,3.14");
}

// A tiny actor on `beams` ranges x 4 frames: hidden unit 0 = relu(newest frame's previous-v
// input + 1) drives v; unit 1 = relu(oldest frame's previous-v input + 1) drives w.
std::shared_ptr<const learning::MlpPolicy> probePolicy(int beams) {
  const int frame = e2eFrameSize(beams);
  const int inputs = 4 * frame;
  learning::MlpPolicyInfo info;
  info.layers = {inputs, 2, 2};
  info.output_low = {-1.0, -3.14};
  info.output_high = {2.0, 3.14};
  info.input = e2eInputText(E2eEncoding{});
  learning::MlpLayer l1, l2;
  l1.weight = Eigen::MatrixXf::Zero(2, inputs);
  l1.weight(0, 3 * frame + beams + 2) = 1.0f;  // the newest frame's previous v
  l1.weight(1, beams + 2) = 1.0f;              // the oldest frame's previous v
  l1.bias = Eigen::VectorXf::Ones(2);
  l2.weight = Eigen::MatrixXf::Identity(2, 2);
  l2.bias = Eigen::VectorXf::Zero(2);
  return std::make_shared<const learning::MlpPolicy>(info, std::vector<learning::MlpLayer>{l1, l2});
}

TEST(E2e, TheActorSeesFourFramesOldestFirstAndItsOwnLastCommand) {
  E2eController controller(E2eConfig{}, probePolicy(720));
  EpisodeInfo info;
  info.goal = {0.0, 10.0};
  controller.reset(info);
  core::LaserScan scan;
  scan.ranges.assign(720, std::numeric_limits<double>::infinity());
  Observation obs;
  obs.scan = &scan;
  obs.odom_pose = {0.0, 0.0, std::numbers::pi / 2};
  obs.scan_odom_pose = obs.odom_pose;
  obs.goal = info.goal;
  // f(v) = (v - 0.5) / 1.5 is the encoded previous v; v_t = -1 + 1.5 (tanh(relu(f(v_(t-1)) + 1)) + 1)
  // from the newest frame, w_t = 3.14 tanh(relu(f(v_(t-4)) + 1)) from the oldest (v_(-k) = 0: the
  // first frame, repeated, has the previous action 0).
  const auto f = [](double v) { return (v - 0.5) / 1.5; };
  std::vector<double> v = {0.0};  // v_(-1)
  for (int t = 0; t < 7; ++t) {
    obs.time = 0.2 * t;
    const core::Twist command = controller.act(obs);
    const double expected_v = -1.0 + 1.5 * (std::tanh(std::max(f(v.back()), -1.0) + 1.0) + 1.0);
    const double oldest = t >= 4 ? v[static_cast<std::size_t>(t - 3)] : 0.0;
    const double expected_w = 3.14 * std::tanh(f(oldest) + 1.0);
    EXPECT_NEAR(command.linear, expected_v, 1e-5) << t;
    EXPECT_NEAR(command.angular, expected_w, 1e-5) << t;
    v.push_back(command.linear);
  }
  // reset() forgets the frames and the last command: the first command again.
  controller.reset(info);
  obs.time = 0.0;
  EXPECT_NEAR(controller.act(obs).linear, v[1], 1e-6);
}

TEST(E2e, APolicyForAnotherEncodingOrBeamCountIsRefused) {
  const auto policy = probePolicy(720);
  EXPECT_NO_THROW(checkE2ePolicy(*policy, E2eEncoding{}, 720, "p"));
  try {
    checkE2ePolicy(*policy, E2eEncoding{}, 360, "p");
    FAIL();
  } catch (const core::InputError& e) {
    EXPECT_THAT(e.what(), HasSubstr("2896 inputs"));
  }
  E2eEncoding clip;
  clip.range_clip = 2.0;
  try {
    checkE2ePolicy(*policy, clip, 720, "p");
    FAIL();
  } catch (const core::InputError& e) {
    EXPECT_THAT(e.what(), HasSubstr("range_clip=2"));
  }
}

TEST(E2e, TheShippedConfigIsTheDefaultsAndDrivesAnEpisode) {
  const core::ConfigNode node = core::ConfigNode::parseFile(std::string(BARN_SOURCE_DIR) + "/configs/controllers/e2e.yaml");
  E2eConfig shipped = core::readConfig<E2eConfig>(node.child("e2e"));
  E2eConfig defaults;
  defaults.policy = shipped.policy;  // relative to the file; the default is relative to the repository
  EXPECT_EQ(shipped.policy, "../policies/e2e.policy");
  core::ConfigWriter a(2), b(2);
  shipped.visit(a);
  defaults.visit(b);
  EXPECT_EQ(a.text(), b.text());
  // The shipped actor on the empty world: the episode runs to an outcome without an error.
  const ControllerFactory factory = makeControllerFactory(node);
  auto controller = factory();
  const core::WorldSpec world = bench::emptyWorld();
  const sim::ObstacleField field = sim::ObstacleField::fromWorld(world);
  const bench::EpisodeResult r = bench::runEpisode(world, field, *controller, bench::EpisodeConfig{}, 5);
  EXPECT_NE(r.outcome, bench::Outcome::Error) << r.error;
}

}  // namespace
}  // namespace barn::controllers
