#include "barn/learning/mlp_policy.hpp"

#include <gmock/gmock.h>
#include <gtest/gtest.h>

#include <cmath>
#include <limits>

#include "barn/core/errors.hpp"

namespace barn::learning {
namespace {

using ::testing::HasSubstr;

// A 3-2-1 network: h = relu(W1 x + b1), y = tanh(W2 h + b2) mapped from [-1, 1] to [0, 4].
MlpPolicy smallPolicy(bool half = false) {
  MlpPolicyInfo info;
  info.layers = {3, 2, 1};
  info.output = MlpOutput::Tanh;
  info.output_low = {0.0};
  info.output_high = {4.0};
  info.input = "three numbers";
  info.output_text = "one number";
  info.half = half;
  info.name = "small";
  info.steps = 1234;
  MlpLayer l1, l2;
  l1.weight.resize(2, 3);
  l1.weight << 1.0f, 0.5f, 0.0f,  //
      -1.0f, 0.0f, 2.0f;
  l1.bias.resize(2);
  l1.bias << 0.25f, 0.0f;
  l2.weight.resize(1, 2);
  l2.weight << 0.5f, -0.25f;
  l2.bias.resize(1);
  l2.bias << 0.125f;
  return MlpPolicy(info, {l1, l2});
}

TEST(MlpPolicy, ForwardIsReluLayersThenTanhMappedOntoTheOutputRange) {
  // x = (1, 2, 0.5): W1 x + b1 = (1 + 1 + 0.25, -1 + 1) = (2.25, 0), relu the same;
  // W2 h + b2 = 1.125 + 0.125 = 1.25; tanh(1.25) = 0.8482836; mapped to [0, 4]:
  // 0 + (0.8482836 + 1) * 4 / 2 = 3.6965673.
  const float x[3] = {1.0f, 2.0f, 0.5f};
  const Eigen::VectorXd y = smallPolicy().forward(x);
  ASSERT_EQ(y.size(), 1);
  EXPECT_NEAR(y[0], 2.0 + 2.0 * std::tanh(1.25), 1e-6);
  EXPECT_NEAR(y[0], 3.6965673, 1e-6);
  // A negative pre-activation is cut: x = (-1, 0, 0) gives W1 x + b1 = (-0.75, 1) -> (0, 1);
  // W2 h + b2 = -0.25 + 0.125 = -0.125.
  const float z[3] = {-1.0f, 0.0f, 0.0f};
  EXPECT_NEAR(smallPolicy().forward(z)[0], 2.0 + 2.0 * std::tanh(-0.125), 1e-6);
}

TEST(MlpPolicy, AFileReadsBackTheSameNetworkAndHeader) {
  const MlpPolicy p = smallPolicy();
  const MlpPolicy q = MlpPolicy::parse(mlpPolicyBytes(p.info(), p.layers()), "round.policy");
  EXPECT_EQ(q.info().layers, p.info().layers);
  EXPECT_EQ(q.info().input, "three numbers");
  EXPECT_EQ(q.info().output_low, std::vector<double>{0.0});
  EXPECT_EQ(q.info().steps, 1234);
  EXPECT_FALSE(q.info().half);
  for (std::size_t k = 0; k < 2; ++k) {
    EXPECT_EQ(q.layers()[k].weight, p.layers()[k].weight);
    EXPECT_EQ(q.layers()[k].bias, p.layers()[k].bias);
  }
  // Every weight of the small network is a short binary fraction, exact in float16 too.
  const MlpPolicy h = MlpPolicy::parse(mlpPolicyBytes(smallPolicy(true).info(), p.layers()), "half.policy");
  EXPECT_TRUE(h.info().half);
  EXPECT_EQ(h.layers()[0].weight, p.layers()[0].weight);
  // The payload: 2 x 3 + 2 + 2 + 1 = 11 weights, 44 bytes as float32, 22 as float16.
  const std::string bytes32 = mlpPolicyBytes(p.info(), p.layers());
  const std::string bytes16 = mlpPolicyBytes(smallPolicy(true).info(), p.layers());
  EXPECT_THAT(bytes32, HasSubstr("payload_bytes: 44\n"));
  EXPECT_THAT(bytes16, HasSubstr("payload_bytes: 22\n"));
  EXPECT_THAT(bytes32, HasSubstr("architecture: 3-2-1\n"));
}

TEST(MlpPolicy, HalfPrecisionConversionsMatchIeee754) {
  EXPECT_EQ(floatToHalf(1.0f), 0x3C00);
  EXPECT_EQ(floatToHalf(-2.0f), 0xC000);
  EXPECT_EQ(floatToHalf(65504.0f), 0x7BFF);        // the largest half
  EXPECT_EQ(floatToHalf(65520.0f), 0x7C00);        // halfway to 65536: ties to even, infinity
  EXPECT_EQ(floatToHalf(1.0f / 3.0f), 0x3555);     // 0.333251953125
  EXPECT_EQ(floatToHalf(0.1f), 0x2E66);            // 0.0999755859375
  EXPECT_EQ(floatToHalf(std::ldexp(1.0f, -24)), 0x0001);  // the smallest subnormal
  EXPECT_EQ(floatToHalf(std::ldexp(1.0f, -26)), 0x0000);  // a quarter of it rounds to 0
  EXPECT_EQ(floatToHalf(std::ldexp(3.0f, -25)), 0x0002);  // 1.5 units: ties to even, 2
  EXPECT_EQ(floatToHalf(1.0f + std::ldexp(1.0f, -11)), 0x3C00);  // halfway above 1: ties to even, 1
  EXPECT_EQ(halfToFloat(0x3555), 0.333251953125f);
  EXPECT_EQ(halfToFloat(0x0001), std::ldexp(1.0f, -24));
  EXPECT_EQ(halfToFloat(0x8000), -0.0f);
  EXPECT_TRUE(std::isinf(halfToFloat(0x7C00)));
  for (std::uint16_t h = 0; h < 0x7C00; ++h) ASSERT_EQ(floatToHalf(halfToFloat(h)), h);  // every finite half
}

TEST(MlpPolicy, BadFilesAreInputErrorsNamingTheProblem) {
  const MlpPolicy p = smallPolicy();
  const std::string good = mlpPolicyBytes(p.info(), p.layers());
  const auto error = [](const std::string& bytes) {
    try {
      MlpPolicy::parse(bytes, "bad.policy");
    } catch (const core::InputError& e) {
      return std::string(e.what());
    }
    return std::string("no error");
  };
  EXPECT_THAT(error("format: barnbench-lflh-policy\n"), HasSubstr("bad.policy"));
  EXPECT_THAT(error(good.substr(0, good.size() - 3)), HasSubstr("truncated"));
  EXPECT_THAT(error(good + "x"), HasSubstr("1 bytes after the weights"));
  std::string wrong = good;
  wrong.replace(wrong.find("3-2-1"), 5, "3-2-2");
  EXPECT_THAT(error(wrong), HasSubstr("payload_bytes"));
  std::string activation = good;
  activation.replace(activation.find("output_activation: tanh"), 23, "output_activation: sigm");
  EXPECT_THAT(error(activation), HasSubstr("output_activation"));
  // A NaN weight (float32 0x7FC00000, little-endian) in the first layer.
  std::string nan = good;
  const std::size_t payload = nan.size() - 44;
  nan.replace(payload, 4, std::string("\x00\x00\xC0\x7F", 4));
  EXPECT_THAT(error(nan), HasSubstr("non-finite"));
  MlpPolicyInfo mismatched = p.info();
  mismatched.layers = {3, 5, 1};
  EXPECT_THROW(MlpPolicy(mismatched, p.layers()), core::InputError);
}

}  // namespace
}  // namespace barn::learning
