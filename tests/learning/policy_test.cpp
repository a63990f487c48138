#include "barn/learning/policy.hpp"

#include <cmath>
#include <filesystem>
#include <limits>
#include <optional>
#include <string>

#include <gmock/gmock.h>
#include <gtest/gtest.h>
#include <sys/stat.h>

#include "barn/core/errors.hpp"
#include "barn/core/text_io.hpp"
#include "barn/learning/exploration.hpp"
#include "barn/learning/hallucination.hpp"
#include "barn/learning/lflh_config.hpp"
#include "tests/scratch_dir.hpp"

namespace barn::learning {
namespace {

namespace fs = std::filesystem;
using ::testing::HasSubstr;
using test::ScratchDir;

// A 722-8-8-2 network with random weights.
MlpParameters<float> smallWeights() {
  Mlp<float> net(722, 8, 2);
  core::Rng rng(5);
  net.initialise(rng);
  return net.parameters();
}

PolicyInfo smallInfo() {
  PolicyInfo info;
  info.hidden = 8;
  info.name = "small";
  info.config_hash = 0xabcdef0123456789ull;
  info.plant_hash = 0x1122334455667788ull;
  info.trained = "2026-01-01T00:00:00Z";
  info.seed = 3;
  info.epochs = 10;
  info.train_loss = 0.125;
  info.validation_loss = 0.25;
  info.mean_predictor_loss = 0.5;
  return info;
}

core::LaserScan scanOf(const std::vector<double>& ranges) {
  core::LaserScan scan;
  scan.ranges = ranges;
  return scan;
}

TEST(PolicyFile, RoundTripKeepsEveryWeightAndHeaderField) {
  const ScratchDir scratch("barn_policy_test_roundtrip");
  const fs::path path = scratch.path() / "small.policy";
  writePolicyFile(path, smallInfo(), smallWeights());
  const Policy policy = Policy::load(path);
  EXPECT_EQ(policy.weights().w1, smallWeights().w1);
  EXPECT_EQ(policy.weights().b3, smallWeights().b3);
  EXPECT_EQ(policy.info().config_hash, 0xabcdef0123456789ull);
  EXPECT_EQ(policy.info().plant_hash, 0x1122334455667788ull);
  EXPECT_EQ(policy.info().name, "small");
  EXPECT_EQ(policy.info().trained, "2026-01-01T00:00:00Z");
  EXPECT_EQ(policy.info().validation_loss, 0.25);
  EXPECT_EQ(policy.info().range_clip, 2.0);
  // Header + (722*8 + 8 + 8*8 + 8 + 8*2 + 2) * 4 = header + 5874 * 4 = header + 23496 bytes.
  const std::string text = core::readTextFile(path);
  EXPECT_EQ(text.size() - (text.find("end_header\n") + 11), 23496u);
}

// Every way a file can be wrong, each with the message that names it.
class PolicyLoadErrors : public ::testing::Test {
 protected:
  void SetUp() override {
    scratch_.emplace("barn_policy_test_errors");
    dir_ = scratch_->path();
    writePolicyFile(dir_ / "good.policy", smallInfo(), smallWeights());
    good_ = core::readTextFile(dir_ / "good.policy");
  }
  std::string errorOf(const std::string& content) {
    const fs::path path = dir_ / "bad.policy";
    core::writeFileAtomic(path, content);
    try {
      Policy::load(path);
    } catch (const core::InputError& e) {
      return e.what();
    }
    return "no error";
  }
  std::string replaced(const std::string& from, const std::string& to) {
    std::string text = good_;
    text.replace(text.find(from), from.size(), to);
    return text;
  }
  std::optional<ScratchDir> scratch_;
  fs::path dir_;
  std::string good_;
};

TEST_F(PolicyLoadErrors, WrongMagic) {
  EXPECT_THAT(errorOf("PK\x03\x04 a zip file\n"), HasSubstr("bad.policy: wrong magic"));
  EXPECT_THAT(errorOf(replaced("format: barnbench-lflh-policy", "format: something-else")), HasSubstr("wrong magic"));
  EXPECT_THAT(errorOf(""), HasSubstr("wrong magic"));
}

TEST_F(PolicyLoadErrors, TruncatedWeightsOrHeader) {
  EXPECT_THAT(errorOf(good_.substr(0, good_.size() - 4)), HasSubstr("truncated: expected 23496 bytes of weights, found 23492"));
  EXPECT_THAT(errorOf(good_.substr(0, good_.find("end_header"))), HasSubstr("truncated header"));
  EXPECT_THAT(errorOf(good_ + "xx"), HasSubstr("2 bytes after the weights"));
}

TEST_F(PolicyLoadErrors, WrongShape) {
  EXPECT_THAT(errorOf(replaced("architecture: 722-8-8-2", "architecture: 362-8-8-2")),
              HasSubstr("wrong shape: architecture 362-8-8-2 has 362 inputs, the input layout needs beams + 2 = 722"));
  EXPECT_THAT(errorOf(replaced("architecture: 722-8-8-2", "architecture: 722-8-8-3")), HasSubstr("3 outputs, expected 2"));
  EXPECT_THAT(errorOf(replaced("architecture: 722-8-8-2", "architecture: 722-16-16-2")),
              HasSubstr("wrong shape: payload_bytes 23496 does not match architecture 722-16-16-2"));
  EXPECT_THAT(errorOf(replaced("architecture: 722-8-8-2", "architecture: 722x8")), HasSubstr("expected inputs-hidden-hidden-outputs"));
  // Four sizes, each >= 1, nothing after the fourth.
  for (const char* bad : {"722-8-8", "722-8-8-2-2", "722-0-0-2", "722-8-8-2-", "-722-8-8-2"})
    EXPECT_THAT(errorOf(replaced("architecture: 722-8-8-2", std::string("architecture: ") + bad)),
                HasSubstr(std::string("architecture '") + bad + "': expected inputs-hidden-hidden-outputs, e.g. 722-256-256-2"))
        << bad;
}

TEST_F(PolicyLoadErrors, HeaderContractFields) {
  EXPECT_THAT(errorOf(replaced("version: 3", "version: 4")), HasSubstr("unsupported version 4 (this build reads versions 1 to 3)"));
  EXPECT_THAT(errorOf(replaced("activation: relu", "activation: tanh")),
              HasSubstr("activation 'tanh': expected 'relu' or 'leaky_relu S' with the slope S in (0, 1)"));
  EXPECT_THAT(errorOf(replaced("activation: relu", "activation: leaky_relu")), HasSubstr("activation 'leaky_relu'"));
  EXPECT_THAT(errorOf(replaced("activation: relu", "activation: leaky_relu 1.5")), HasSubstr("activation 'leaky_relu 1.5'"));
  EXPECT_THAT(errorOf(replaced("activation: relu", "activation: leaky_relu 0")), HasSubstr("activation 'leaky_relu 0'"));
  EXPECT_THAT(errorOf(replaced("output: v [m/s], w [rad/s]", "output: w, v")), HasSubstr("header: output"));
  EXPECT_THAT(errorOf(replaced("seed: 3\n", "")), HasSubstr("missing key 'seed'"));
  EXPECT_THAT(errorOf(replaced("seed: 3\n", "seed: 3\ncolour: red\n")), HasSubstr("unknown key 'colour'"));
  EXPECT_THAT(errorOf(replaced("range_clip: 2", "range_clip: two")), HasSubstr("range_clip 'two': expected a number"));
  EXPECT_THAT(errorOf(replaced("train_loss: 0.125", "train_loss: lots")), HasSubstr("train_loss 'lots': expected a number"));
  EXPECT_THAT(errorOf(replaced("beams: 720", "beams: 0")), HasSubstr("header: beams '0': expected an integer in [1, 100000]"));
  EXPECT_THAT(errorOf(replaced("config_hash: 0x", "config_hash: 0xg")), HasSubstr("header: config_hash '0xg"));
  EXPECT_THAT(errorOf(replaced("plant_hash: 0x1122334455667788", "plant_hash: 0x0")), HasSubstr("write 'unknown' for an unknown plant"));
  EXPECT_THAT(errorOf(replaced("plant_hash: 0x1122334455667788", "plant_hash: default")), HasSubstr("header: plant_hash 'default'"));
  EXPECT_THAT(errorOf(replaced("plant_hash: 0x1122334455667788\n", "")), HasSubstr("missing key 'plant_hash'"));
  EXPECT_THAT(errorOf(replaced("layout: float32", "layout: float64")), HasSubstr("header: layout is 'float64"));
}

// ---- Format versions: 1 (relu only) and 2 still load; 2 records the activation, 3 the plant ----

TEST_F(PolicyLoadErrors, AnUnknownPlantAndTheVersionsBeforeThePlantLoadWithPlantZero) {
  EXPECT_EQ(Policy::parse(replaced("plant_hash: 0x1122334455667788", "plant_hash: unknown"), "u.policy").info().plant_hash, 0u);
  // Version 2 had no plant_hash line; its plant is unknown (a line it has anyway is read).
  std::string v2 = replaced("version: 3", "version: 2");
  EXPECT_EQ(Policy::parse(v2, "v2.policy").info().plant_hash, 0x1122334455667788ull);
  const std::string plant_line = "plant_hash: 0x1122334455667788\n";
  v2.replace(v2.find(plant_line), plant_line.size(), "");
  const Policy old = Policy::parse(v2, "v2.policy");
  EXPECT_EQ(old.info().plant_hash, 0u);
  EXPECT_EQ(old.weights().w1, smallWeights().w1);
}

TEST_F(PolicyLoadErrors, VersionOneLoadsAsRelu) {
  // A version 1 file is this one with "version: 1" (its activation line was always "relu").
  const fs::path path = dir_ / "v1.policy";
  const std::string v1 = replaced("version: 3", "version: 1");
  core::writeFileAtomic(path, v1);
  const Policy policy = Policy::load(path);
  EXPECT_EQ(policy.info().activation, Activation::Relu);
  EXPECT_EQ(policy.weights().w2, smallWeights().w2);
  // Version 1 knew no other activation.
  std::string leaky = v1;
  leaky.replace(leaky.find("activation: relu"), 16, "activation: leaky_relu 0.01");
  EXPECT_THAT(errorOf(leaky), HasSubstr("activation is 'leaky_relu 0.01', expected 'relu'"));
}

TEST(PolicyFile, RoundTripKeepsTheLeakyReluAndItsSlope) {
  const ScratchDir scratch("barn_policy_test_leaky");
  const fs::path path = scratch.path() / "leaky.policy";
  PolicyInfo info = smallInfo();
  info.activation = Activation::LeakyRelu;
  info.slope = 0.01;
  info.train_loss = std::numeric_limits<double>::quiet_NaN();  // unknown, as for an imported policy
  writePolicyFile(path, info, smallWeights());
  const std::string text = core::readTextFile(path);
  EXPECT_THAT(text, HasSubstr("\nversion: 3\n"));
  EXPECT_THAT(text, HasSubstr("\nactivation: leaky_relu 0.01\n"));
  EXPECT_THAT(text, HasSubstr("\ntrain_loss: unknown\n"));
  const Policy policy = Policy::load(path);
  EXPECT_EQ(policy.info().activation, Activation::LeakyRelu);
  EXPECT_EQ(policy.info().slope, 0.01);
  EXPECT_TRUE(std::isnan(policy.info().train_loss));
  EXPECT_EQ(policy.info().validation_loss, 0.25);
  EXPECT_EQ(policy.weights().w1, smallWeights().w1);

  // act() is the leaky network: Mlp's forward pass with the same activation (to float
  // rounding: act() sums the first layer in another order, beams at the clip skipped), and not
  // the relu network's output. Beams below the clip, at it (+inf, NaN, far) and mixed.
  Mlp<float> leaky(smallWeights(), Activation::LeakyRelu, 0.01);
  Mlp<float> relu(smallWeights());
  const double inf = std::numeric_limits<double>::infinity(), nan = std::numeric_limits<double>::quiet_NaN();
  std::vector<double> below(720, 1.5), mixed(720, inf), far(720, 7.0);
  for (std::size_t i = 0; i < 720; i += 7) below[i] = 0.3;
  for (std::size_t i = 0; i < 720; i += 3) mixed[i] = i % 2 ? nan : 0.1 + 0.002 * static_cast<double>(i);
  for (const std::vector<double>& ranges : {below, mixed, far}) {
    Eigen::MatrixXf x(722, 1);
    encodeInput(ranges, {1.0, -0.5}, 2.0, x.data());
    const Eigen::MatrixXf y = leaky.forward(x);
    const core::Twist twist = policy.act(scanOf(ranges), {1.0, -0.5});
    EXPECT_NEAR(twist.linear, y(0, 0), 1e-6 * std::max(1.0f, std::abs(y(0, 0))));
    EXPECT_NEAR(twist.angular, y(1, 0), 1e-6 * std::max(1.0f, std::abs(y(1, 0))));
    EXPECT_GT(std::abs(static_cast<float>(twist.linear) - relu.forward(x)(0, 0)), 5e-5);
    // Another clip than the file's: the same network on the other clip.
    const core::Twist clipped = policy.act(scanOf(ranges), {1.0, -0.5}, 1.0);
    encodeInput(ranges, {1.0, -0.5}, 1.0, x.data());
    EXPECT_NEAR(clipped.linear, leaky.forward(x)(0, 0), 1e-6 * std::max(1.0f, std::abs(leaky.forward(x)(0, 0))));
  }
}

TEST_F(PolicyLoadErrors, NonFiniteWeight) {
  std::string text = good_;
  const std::size_t payload = text.find("end_header\n") + 11;
  const float nan = std::numeric_limits<float>::quiet_NaN();
  std::memcpy(text.data() + payload + 4 * (722 * 8 + 8), &nan, 4);  // w2[0]
  EXPECT_THAT(errorOf(text), HasSubstr("block w2 holds a non-finite value"));
}

TEST_F(PolicyLoadErrors, AHugeArchitectureInAShortFileIsRefusedBeforeAllocating) {
  // 100002-4096-4096-2: 4 * (4096 * 100002 + 4096 + 4096 * 4096 + 4096 + 2 * 4096 + 2) bytes
  // = 1.7 GB claimed by a file of a few hundred bytes.
  std::string text = replaced("architecture: 722-8-8-2", "architecture: 100002-4096-4096-2");
  text.replace(text.find("beams: 720"), 10, "beams: 100000");
  text.replace(text.find("payload_bytes: 23496"), 20, "payload_bytes: 1705607176");
  text.resize(text.find("end_header\n") + 11);
  EXPECT_THAT(errorOf(text), HasSubstr("bad.policy: truncated: expected 1705607176 bytes of weights, found 0"));
}

TEST(PolicyLoad, MissingFileNamesIt) {
  EXPECT_THROW(Policy::load("/nonexistent/x.policy"), core::InputError);
}

std::string loadError(const fs::path& path) {
  try {
    Policy::load(path);
  } catch (const core::InputError& e) {
    return e.what();
  }
  return "no error";
}

TEST(PolicyLoad, AFolderIsRefusedNamingIt) {
  const ScratchDir scratch("barn_policy_test_folder");
  const fs::path& dir = scratch.path();
  EXPECT_THAT(loadError(dir), HasSubstr(dir.string() + ": is a folder, expected a file"));
}

TEST(PolicyLoad, ADeviceIsRefusedInsteadOfReadForever) {
  EXPECT_THAT(loadError("/dev/zero"), HasSubstr("/dev/zero: not a regular file"));
}

TEST(PolicyLoad, AFifoIsRefusedInsteadOfBlocking) {
  const ScratchDir scratch("barn_policy_test_fifo");
  const fs::path fifo = scratch.path() / "weights.policy";
  ASSERT_EQ(::mkfifo(fifo.c_str(), 0600), 0);
  EXPECT_THAT(loadError(fifo), HasSubstr(fifo.string() + ": not a regular file"));
}

TEST(Policy, ActClipsLikeTrainingAndMatchesTheNetwork) {
  const Policy policy(smallInfo(), smallWeights());
  std::vector<double> ranges(720, std::numeric_limits<double>::infinity());
  for (std::size_t i = 0; i < 720; i += 3) ranges[i] = 0.01 * static_cast<double>(i % 400);
  // The network on the training encoding of the same scan and goal.
  Mlp<float> net(smallWeights());
  Eigen::MatrixXf x(722, 1);
  encodeInput(ranges, {1.0, 2.0}, 2.0, x.data());
  const Eigen::MatrixXf& y = net.forward(x);
  const core::Twist twist = policy.act(scanOf(ranges), {1.0, 2.0});
  EXPECT_NEAR(twist.linear, y(0, 0), 1e-6);
  EXPECT_NEAR(twist.angular, y(1, 0), 1e-6);
  // Any goal length: only the direction counts. A range beyond the clip is the clip.
  EXPECT_EQ(policy.act(scanOf(ranges), {10.0, 20.0}).angular, twist.angular);
  std::vector<double> farther = ranges;
  farther[1] = 25.0;  // was +inf: both read as 2.0
  EXPECT_EQ(policy.act(scanOf(farther), {1.0, 2.0}).linear, twist.linear);
  // A clip given by the caller replaces the file's: the network on the input clipped at 2.5.
  encodeInput(ranges, {1.0, 2.0}, 2.5, x.data());
  const Eigen::MatrixXf& y25 = net.forward(x);
  const core::Twist at25 = policy.act(scanOf(ranges), {1.0, 2.0}, 2.5);
  EXPECT_NEAR(at25.linear, y25(0, 0), 1e-6);
  EXPECT_NEAR(at25.angular, y25(1, 0), 1e-6);
  EXPECT_NE(at25.linear, twist.linear);
}

TEST(Policy, ScanWithTheWrongBeamCountIsAnInputError) {
  const Policy policy(smallInfo(), smallWeights());
  EXPECT_THROW(policy.act(scanOf(std::vector<double>(360, 1.0)), {1.0, 0.0}), core::InputError);
}

// CI never retrains: it loads the committed weights and checks they belong to the configs.
TEST(ShippedPolicies, WriteBackByteForByte) {
  // Loading and writing a policy gives its file again, header and weights.
  const ScratchDir scratch("barn_policy_test_shipped");
  const fs::path& dir = scratch.path();
  for (const std::string name : {"lflh_1ms", "lflh_2ms"}) {
    const fs::path file = fs::path(BARN_SOURCE_DIR) / "configs" / "policies" / (name + ".policy");
    const Policy policy = Policy::load(file);
    writePolicyFile(dir / "back.policy", policy.info(), policy.weights());
    EXPECT_EQ(core::readTextFile(dir / "back.policy"), core::readTextFile(file)) << file;
  }
}

TEST(PolicyFile, TheFuzzSeedsLoadAndTheVersionThreeOneWritesBackByteForByte) {
  const fs::path seeds = fs::path(BARN_SOURCE_DIR) / "tests" / "fuzz" / "seeds" / "policy";
  EXPECT_EQ(Policy::load(seeds / "tiny.policy").info().activation, Activation::Relu);  // version 1
  const Policy leaky = Policy::load(seeds / "tiny_v2_leaky.policy");
  EXPECT_EQ(leaky.info().activation, Activation::LeakyRelu);
  EXPECT_EQ(leaky.info().plant_hash, 0u);
  const Policy planted = Policy::load(seeds / "tiny_v3_plant.policy");
  EXPECT_NE(planted.info().plant_hash, 0u);
  const ScratchDir scratch("barn_policy_test_seeds");
  const fs::path back = scratch.path() / "back.policy";
  writePolicyFile(back, planted.info(), planted.weights());
  EXPECT_EQ(core::readTextFile(back), core::readTextFile(seeds / "tiny_v3_plant.policy"));
}

TEST(ShippedPolicies, TheVersionOneFormOfAShippedPolicyLoadsTheSameWeightsAsRelu) {
  // Version 1 files differ only in their version line and their activation, always relu.
  const fs::path file = fs::path(BARN_SOURCE_DIR) / "configs" / "policies" / "lflh_1ms.policy";
  const std::string v3 = core::readTextFile(file);
  std::string v1 = v3;
  v1.replace(v1.find("\nversion: 3\n"), 12, "\nversion: 1\n");
  // A version 1 header cannot name another activation.
  ASSERT_NE(v1.find("\nactivation: leaky_relu 0.01\n"), std::string::npos);
  EXPECT_THROW(Policy::parse(v1, "v1.policy"), core::InputError);
  v1.replace(v1.find("\nactivation: leaky_relu 0.01\n"), 29, "\nactivation: relu\n");
  const Policy old = Policy::parse(v1, "v1.policy");
  const Policy current = Policy::load(file);
  EXPECT_EQ(old.weights().w1, current.weights().w1);
  EXPECT_EQ(old.weights().b3, current.weights().b3);
  EXPECT_EQ(old.info().activation, Activation::Relu);
  EXPECT_EQ(current.info().activation, Activation::LeakyRelu);
  EXPECT_EQ(old.info().config_hash, current.info().config_hash);
  EXPECT_EQ(old.info().validation_loss, current.info().validation_loss);
}

TEST(ShippedPolicies, LoadAndMatchTheirTrainingConfigs) {
  for (const std::string name : {"1ms", "2ms"}) {
    const fs::path file = fs::path(BARN_SOURCE_DIR) / "configs" / "policies" / ("lflh_" + name + ".policy");
    const Policy policy = Policy::load(file);
    const LflhPipelineConfig config = readLflhPipelineConfig(fs::path(BARN_SOURCE_DIR) / "configs" / "lflh" / (name + ".yaml"));
    EXPECT_EQ(policy.info().config_hash, configHash(config)) << file << " was trained with another config";
    EXPECT_EQ(policy.info().plant_hash, sim::plantHash({}, {})) << file << " was trained on another plant than the default";
    EXPECT_EQ(policy.info().hidden, 256);
    EXPECT_LT(policy.info().validation_loss, policy.info().mean_predictor_loss);
    // Goal ahead: drive forward, and steer away from a circle (r 0.3 m) 1 m ahead and 0.3 m
    // to one side: right (w < 0) when it is on the left, left when it is on the right.
    const core::LidarConfig lidar;
    const core::Twist open = policy.act(scanOf(renderScan({}, lidar, nullptr)), {1.0, 0.0});
    const core::Twist left = policy.act(scanOf(renderScan({makeObstacle({1.0, 0.3}, 0.3, 0.3, 0.0)}, lidar, nullptr)), {1.0, 0.0});
    const core::Twist right = policy.act(scanOf(renderScan({makeObstacle({1.0, -0.3}, 0.3, 0.3, 0.0)}, lidar, nullptr)), {1.0, 0.0});
    EXPECT_GT(open.linear, 0.5) << name;
    EXPECT_LT(left.angular, -0.2) << name;
    EXPECT_GT(right.angular, 0.2) << name;
    EXPECT_GT(left.linear, 0.3) << name;
  }
}

}  // namespace
}  // namespace barn::learning
