#include "barn/learning/mlp.hpp"

#include <cmath>

#include <gtest/gtest.h>

namespace barn::learning {
namespace {

using MatrixD = Eigen::MatrixXd;

// A small network in double precision with random weights and a batch of 5 examples.
struct Problem {
  Mlp<double> net;
  MatrixD x, t;
  explicit Problem(Activation activation = Activation::Relu, double slope = 0.01) : net(6, 5, 2, activation, slope) {
    core::Rng rng(7);
    net.initialise(rng);
    x.resize(6, 5);
    t.resize(2, 5);
    for (Eigen::Index i = 0; i < x.size(); ++i) x.data()[i] = 2.0 * rng.uniform01() - 1.0;
    for (Eigen::Index i = 0; i < t.size(); ++i) t.data()[i] = 2.0 * rng.uniform01() - 1.0;
  }
};

// The analytic gradient against central finite differences, block by block.
void expectGradientMatchesFiniteDifferences(Problem& p) {
  MlpParameters<double> grad = MlpParameters<double>::zeros(6, 5, 2);
  p.net.lossAndGradient(p.x, p.t, grad);

  // Central differences with h = 1e-6 have error O(h^2) ~ 1e-12 away from ReLU kinks; no
  // pre-activation of this problem lies within h of 0, so every entry must agree closely.
  constexpr double h = 1e-6;
  std::vector<double*> params, grads;
  std::vector<Eigen::Index> sizes;
  std::vector<std::string> names;
  p.net.parameters().forEachBlock([&](const char* name, double* data, Eigen::Index size) {
    params.push_back(data);
    sizes.push_back(size);
    names.push_back(name);
  });
  grad.forEachBlock([&](const char*, double* data, Eigen::Index) { grads.push_back(data); });
  ASSERT_EQ(params.size(), 6u);
  for (std::size_t b = 0; b < params.size(); ++b) {
    double largest = 0.0;
    for (Eigen::Index i = 0; i < sizes[b]; ++i) {
      const double saved = params[b][i];
      params[b][i] = saved + h;
      const double up = p.net.loss(p.x, p.t);
      params[b][i] = saved - h;
      const double down = p.net.loss(p.x, p.t);
      params[b][i] = saved;
      const double numeric = (up - down) / (2.0 * h);
      EXPECT_NEAR(grads[b][i], numeric, 1e-7 * std::max(1.0, std::abs(numeric))) << names[b] << "[" << i << "]";
      largest = std::max(largest, std::abs(numeric));
    }
    EXPECT_GT(largest, 1e-4) << names[b] << ": the check must see a non-zero gradient";
  }
}

TEST(Mlp, EveryGradientBlockMatchesCentralFiniteDifferences) {
  Problem p;
  expectGradientMatchesFiniteDifferences(p);
}

TEST(Mlp, LeakyReluGradientMatchesCentralFiniteDifferencesToo) {
  // A large slope makes the negative side's share of the gradient plain to see.
  Problem leaky(Activation::LeakyRelu, 0.01);
  expectGradientMatchesFiniteDifferences(leaky);
  Problem steep(Activation::LeakyRelu, 0.3);
  expectGradientMatchesFiniteDifferences(steep);
  // Some hidden units are negative, so relu and leaky_relu gradients differ there.
  MlpParameters<double> g_relu = MlpParameters<double>::zeros(6, 5, 2), g_leaky = g_relu;
  Problem relu;
  relu.net.lossAndGradient(relu.x, relu.t, g_relu);
  steep.net.lossAndGradient(steep.x, steep.t, g_leaky);
  EXPECT_GT((g_relu.w1 - g_leaky.w1).cwiseAbs().maxCoeff(), 1e-6);
}

TEST(Mlp, LeakyReluForwardKeepsPositivesAndScalesNegatives) {
  // One input, two hidden units with pre-activations +2 and -3 in both layers (identity-ish
  // weights), output = sum of the second layer.
  Mlp<double> net(1, 2, 1, Activation::LeakyRelu, 0.01);
  auto& p = net.parameters();
  p.w1 << 2.0, -3.0;                  // h1 = (f(2), f(-3)) = (2, -0.03)
  p.w2 << 1.0, 0.0,
          0.0, 100.0;                 // z2 = (2, -3), h2 = (2, -0.03)
  p.w3 << 1.0, 1.0;                   // y = 2 - 0.03
  const MatrixD x = MatrixD::Ones(1, 1);
  EXPECT_DOUBLE_EQ(net.forward(x)(0, 0), 2.0 - 0.03);
  Mlp<double> relu(p);                // relu by default: y = 2
  EXPECT_DOUBLE_EQ(relu.forward(x)(0, 0), 2.0);
}

TEST(Mlp, LossIsTheBatchMeanOfTheSummedSquaredErrors) {
  // Zero weights and biases b3 = (1, -1): y = (1, -1) for every column. Targets (0, 0) and
  // (1, 1): errors (1, -1) and (0, -2), sums of squares 2 and 4, mean 3.
  Mlp<double> net(3, 2, 2);
  net.parameters().b3 << 1.0, -1.0;
  MatrixD x = MatrixD::Ones(3, 2);
  MatrixD t(2, 2);
  t << 0.0, 1.0,
       0.0, 1.0;
  EXPECT_DOUBLE_EQ(net.loss(x, t), 3.0);
}

TEST(Mlp, InitialisationIsUniformWithinOneOverRootFanIn) {
  Mlp<float> net(722, 256, 2);
  core::Rng rng(1);
  net.initialise(rng);
  const auto& p = net.parameters();
  // 1 / sqrt(722) = 0.03722; 1 / sqrt(256) = 0.0625.
  EXPECT_LE(p.w1.cwiseAbs().maxCoeff(), 0.03722f);
  EXPECT_GT(p.w1.cwiseAbs().maxCoeff(), 0.0372f);
  EXPECT_LE(p.w3.cwiseAbs().maxCoeff(), 0.0625f);
  EXPECT_LE(p.b3.cwiseAbs().maxCoeff(), 0.0625f);
  EXPECT_EQ(p.count(), 251394u);  // 722*256 + 256 + 256*256 + 256 + 256*2 + 2, the original's size
}

TEST(Adam, FirstStepMovesEachParameterByTheLearningRateAgainstItsGradient) {
  // After one step m_hat = g and v_hat = g^2, so the update is lr g / (|g| + eps) ~ lr sign(g).
  MlpParameters<double> p = MlpParameters<double>::zeros(2, 2, 2);
  MlpParameters<double> g = MlpParameters<double>::zeros(2, 2, 2);
  g.w1 << 0.5, -2.0,
          1e-3, 0.0;
  Adam<double> adam(p, 0.01);
  adam.step(p, g);
  EXPECT_NEAR(p.w1(0, 0), -0.01, 1e-9);
  EXPECT_NEAR(p.w1(0, 1), 0.01, 1e-9);
  EXPECT_NEAR(p.w1(1, 0), -0.01, 1e-6);  // 0.01 * 1e-3 / (1e-3 + 1e-8)
  EXPECT_EQ(p.w1(1, 1), 0.0);             // zero gradient, zero moments: no move
  EXPECT_EQ(adam.steps(), 1);
}

}  // namespace
}  // namespace barn::learning
