#include "barn/learning/applr_policy.hpp"

#include <cmath>
#include <cstring>
#include <limits>
#include <numbers>
#include <string>
#include <vector>

#include <gmock/gmock.h>
#include <gtest/gtest.h>

#include "barn/core/errors.hpp"
#include "barn/core/text_io.hpp"
#include "tests/scratch_dir.hpp"

namespace barn::learning {
namespace {

using ::testing::HasSubstr;
constexpr double kInf = std::numeric_limits<double>::infinity();
constexpr double kPi = std::numbers::pi;

TEST(ApplrInput, ClipsAtTheClipScalesToHalfUnitsAndAppendsTheGoalAngleOverTwoPi) {
  // clip 2: (r - 1) / 2. 0.5 -> -0.25; 2 -> 0.5; 3.7, +inf and NaN read as 2 -> 0.5; 0 -> -0.5.
  const std::vector<double> ranges = {0.5, 2.0, 3.7, kInf, std::numeric_limits<double>::quiet_NaN(), 0.0};
  float x[7];
  encodeApplrInput(ranges, kPi / 2.0, 2.0, x);
  EXPECT_FLOAT_EQ(x[0], -0.25f);
  EXPECT_FLOAT_EQ(x[1], 0.5f);
  EXPECT_FLOAT_EQ(x[2], 0.5f);
  EXPECT_FLOAT_EQ(x[3], 0.5f);
  EXPECT_FLOAT_EQ(x[4], 0.5f);
  EXPECT_FLOAT_EQ(x[5], -0.5f);
  EXPECT_FLOAT_EQ(x[6], 0.25f);  // (pi / 2) / (2 pi)
  encodeApplrInput({1.0}, -kPi, 2.0, x);
  EXPECT_FLOAT_EQ(x[0], 0.0f);
  EXPECT_FLOAT_EQ(x[1], -0.5f);  // a goal behind: -pi / (2 pi)
}

TEST(ApplrAction, ScalesTanhIntoTheRangeInFloat32AndClipsToIt) {
  // max_vel_x in [0.2, 2]: scale (2 - 0.2) / 2 = 0.9, bias 1.1. u = 0.5 -> 1.1 + 0.45 = 1.55;
  // u = 1 -> 2; u = 0 -> 1.1.
  const ApplrAction max_vel_x{"max_vel_x", 0.2, 2.0};
  EXPECT_NEAR(scaleApplrAction(0.5f, max_vel_x), 1.55, 1e-6);
  EXPECT_NEAR(scaleApplrAction(1.0f, max_vel_x), 2.0, 1e-6);
  EXPECT_NEAR(scaleApplrAction(0.0f, max_vel_x), 1.1, 1e-6);
  // In float32, as the original: 0.2f = 0.200000003, 2 - 0.2f rounds to 1.79999995, so the
  // scale is 0.899999976 and the bias (2 + 0.2f) / 2 = 1.10000002: u = 0 gives the float 1.1f,
  // not the double 1.1.
  EXPECT_EQ(scaleApplrAction(0.0f, max_vel_x), static_cast<double>(1.1f));
  // u = -1 gives 1.10000002 - 0.899999976 = 0.200000048 (the float nearest 0.2000000476),
  // inside [0.2, 2]: kept (numpy gives the same 0.20000004768371582).
  EXPECT_EQ(scaleApplrAction(-1.0f, max_vel_x), 0.20000004768371582);
  // vx_samples in [4, 12]: scale 4, bias 8. u = 0.3 -> 9.2; a value past the range is clipped:
  // u = 1.5 -> 14 -> 12, u = -1.25 -> 3 -> 4.
  const ApplrAction vx_samples{"vx_samples", 4.0, 12.0};
  EXPECT_NEAR(scaleApplrAction(0.3f, vx_samples), 9.2, 1e-6);
  EXPECT_EQ(scaleApplrAction(1.5f, vx_samples), 12.0);
  EXPECT_EQ(scaleApplrAction(-1.25f, vx_samples), 4.0);
}

// A 3-2-2-1 actor (2 beams + the goal angle) with hand-picked weights, one action in [0, 10].
ApplrPolicy tinyPolicy() {
  ApplrPolicyInfo info;
  info.beams = 2;
  info.range_clip = 2.0;
  info.actions = {{"max_vel_x", 0.0, 10.0}};
  info.name = "tiny";
  info.source = "hand";
  MlpParameters<float> w = MlpParameters<float>::zeros(3, 2, 1);
  w.w1 << 1, 0, 0,
          0, -1, 2;
  w.b1 << 0.5f, 0.0f;
  w.w2 << 2, 0,
          0, 1;
  w.b2 << 0.0f, -1.0f;
  w.w3 << 0.4f, 3.0f;
  w.b3 << -0.1f;
  return ApplrPolicy(info, w);
}

TEST(ApplrPolicy, ForwardIsReluReluTanhThenTheScaling) {
  // Ranges (1.5, 3.0), goal angle pi / 2: x = ((1.5 - 1) / 2, (2 - 1) / 2, 1 / 4) = (0.25, 0.5, 0.25).
  // h1 = relu(0.25 + 0.5, -0.5 + 2 x 0.25) = (0.75, 0); h2 = relu(2 x 0.75, 0 - 1) = (1.5, 0);
  // y = 0.4 x 1.5 + 3 x 0 - 0.1 = 0.5; u = tanh(0.5) = 0.462117157;
  // [0, 10]: 5 + 5 u = 7.31058579.
  const ApplrPolicy policy = tinyPolicy();
  core::LaserScan scan;
  scan.ranges = {1.5, 3.0};
  const std::vector<double> parameters = policy.act(scan, kPi / 2.0);
  ASSERT_EQ(parameters.size(), 1u);
  EXPECT_NEAR(parameters[0], 5.0 + 5.0 * std::tanh(0.5), 1e-5);
  EXPECT_NEAR(policy.forward(Eigen::Vector3f(0.25f, 0.5f, 0.25f))[0], std::tanh(0.5), 1e-6);
  // A scan of another beam count is an InputError.
  scan.ranges = {1.0, 1.0, 1.0};
  EXPECT_THROW(policy.act(scan, 0.0), core::InputError);
}

TEST(ApplrPolicy, WeightsOfAnotherShapeOrAnUnusableActionAreRefused) {
  ApplrPolicyInfo info = tinyPolicy().info();
  EXPECT_THROW(ApplrPolicy(info, MlpParameters<float>::zeros(4, 2, 1)), core::InputError);  // 3 beams' inputs
  EXPECT_THROW(ApplrPolicy(info, MlpParameters<float>::zeros(3, 2, 2)), core::InputError);  // 2 outputs, 1 action
  info.actions = {{"max_vel_x", 1.0, 1.0}};
  EXPECT_THROW(ApplrPolicy(info, MlpParameters<float>::zeros(3, 2, 1)), core::InputError);  // lo = hi
  info.actions = {{"Max Vel", 0.0, 1.0}};
  EXPECT_THROW(ApplrPolicy(info, MlpParameters<float>::zeros(3, 2, 1)), core::InputError);
}

TEST(ApplrPolicyFile, RoundTripsByteForByte) {
  const ApplrPolicy policy = tinyPolicy();
  const std::string bytes = applrPolicyBytes(policy.info(), policy.weights());
  EXPECT_THAT(bytes, HasSubstr("format: barnbench-applr-policy\nversion: 1\narchitecture: 3-2-2-1\n"));
  EXPECT_THAT(bytes, HasSubstr("\nactions: max_vel_x 0 10\n"));
  // 3 x 2 + 2 + 2 x 2 + 2 + 1 x 2 + 1 = 17 floats.
  EXPECT_THAT(bytes, HasSubstr("\npayload_bytes: 68\n"));
  const ApplrPolicy back = ApplrPolicy::parse(bytes, "tiny.policy");
  EXPECT_EQ(back.info().beams, 2);
  EXPECT_EQ(back.info().actions.size(), 1u);
  EXPECT_EQ(back.info().source, "hand");
  EXPECT_EQ(back.weights().w1, policy.weights().w1);
  EXPECT_EQ(applrPolicyBytes(back.info(), back.weights()), bytes);
  const test::ScratchDir scratch("barn_applr_policy_roundtrip");
  writeApplrPolicyFile(scratch.path() / "tiny.policy", policy.info(), policy.weights());
  EXPECT_EQ(ApplrPolicy::load(scratch.path() / "tiny.policy").info().name, "tiny");
}

TEST(ApplrPolicyFile, TheFuzzSeedLoads) {
  const ApplrPolicy seed =
      ApplrPolicy::load(std::filesystem::path(BARN_SOURCE_DIR) / "tests" / "fuzz" / "seeds" / "policy" / "tiny_applr.policy");
  EXPECT_EQ(seed.info().beams, 2);
  EXPECT_EQ(seed.info().actions.size(), 2u);
}

// Every way a file can be wrong, each with the message that names it.
class ApplrPolicyErrors : public ::testing::Test {
 protected:
  void SetUp() override {
    const ApplrPolicy policy = tinyPolicy();
    good_ = applrPolicyBytes(policy.info(), policy.weights());
  }
  std::string errorOf(const std::string& content) const {
    try {
      ApplrPolicy::parse(content, "bad.policy");
    } catch (const core::InputError& e) {
      return e.what();
    }
    return "";
  }
  std::string replaced(const std::string& from, const std::string& to) const {
    std::string text = good_;
    const std::size_t at = text.find(from);
    EXPECT_NE(at, std::string::npos) << from;
    return text.replace(at, from.size(), to);
  }
  std::string good_;
};

TEST_F(ApplrPolicyErrors, EachNamesTheFileAndWhatIsWrong) {
  EXPECT_EQ(errorOf(good_), "");
  EXPECT_THAT(errorOf("format: barnbench-lflh-policy\n" + good_.substr(good_.find('\n') + 1)),
              HasSubstr("bad.policy: wrong magic"));
  EXPECT_THAT(errorOf(replaced("version: 1", "version: 2")), HasSubstr("unsupported version 2"));
  EXPECT_THAT(errorOf(replaced("activation: relu", "activation: tanh")), HasSubstr("activation is 'tanh'"));
  EXPECT_THAT(errorOf(replaced("architecture: 3-2-2-1", "architecture: 3-2-2-2")),
              HasSubstr("2 outputs, the header names 1 actions"));
  EXPECT_THAT(errorOf(replaced("architecture: 3-2-2-1", "architecture: 4-2-2-1")), HasSubstr("beams + 1 = 3"));
  EXPECT_THAT(errorOf(replaced("max_vel_x 0 10", "max_vel_x 10 0")), HasSubstr("lo < hi"));
  EXPECT_THAT(errorOf(replaced("max_vel_x 0 10", "max_vel_x 0")), HasSubstr("expected 'name lo hi"));
  EXPECT_THAT(errorOf(replaced("max_vel_x 0 10", "max_vel_x 0 10; max_vel_x 1 2")), HasSubstr("appears twice"));
  EXPECT_THAT(errorOf(replaced("range_clip: 2", "range_clip: 0")), HasSubstr("range_clip must be > 0"));
  EXPECT_THAT(errorOf(replaced("payload_bytes: 68", "payload_bytes: 72")), HasSubstr("does not match architecture"));
  EXPECT_THAT(errorOf(good_.substr(0, good_.size() - 4)), HasSubstr("truncated: expected 68 bytes"));
  EXPECT_THAT(errorOf(good_ + "x"), HasSubstr("1 bytes after the weights"));
  EXPECT_THAT(errorOf(replaced("name: tiny\n", "")), HasSubstr("missing key 'name'"));
  EXPECT_THAT(errorOf(replaced("name: tiny\n", "name: tiny\ncolour: red\n")), HasSubstr("unknown key 'colour'"));
  // A weight changed after the digest was taken; a NaN weight.
  std::string altered = good_;
  altered[altered.size() - 1] ^= 0x01;
  EXPECT_THAT(errorOf(altered), HasSubstr("digest"));
  std::string nan = good_;
  const float quiet_nan = std::numeric_limits<float>::quiet_NaN();
  std::memcpy(nan.data() + nan.size() - 4, &quiet_nan, 4);
  EXPECT_THAT(errorOf(nan), HasSubstr("block b3 holds a non-finite value"));
}

}  // namespace
}  // namespace barn::learning
