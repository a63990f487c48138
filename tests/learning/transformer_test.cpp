#include "barn/learning/transformer.hpp"

#include <cmath>
#include <string>
#include <vector>

#include <gmock/gmock.h>
#include <gtest/gtest.h>

#include "barn/core/errors.hpp"

namespace barn::learning {
namespace {

using ::testing::HasSubstr;

TEST(TransformerShape, ThePublishedNetworkHas127394WeightsInTheFile) {
  // 32 x 20 + 32 + 36 x 32 = 1824 (embedding); per block 4 x 32 x 32 + 2 x 2 x 32 + 256 x 32 +
  // 256 + 32 x 256 + 32 = 20896, six blocks 125376; goal 2 x 32 = 64; head 2 x 64 + 2 = 130:
  // 127394. The published state_dict holds 127586: 3 x 2 x 32 = 192 more, the decoder blocks'
  // self_attn_layer_norm, which its forward pass never reads.
  const TransformerShape published;
  EXPECT_EQ(published.problem(), "");
  EXPECT_EQ(published.patchSize(), 20);
  EXPECT_EQ(published.parameterCount(), 127394u);
  EXPECT_EQ(TransformerWeights::zeros(published).count(), 127394u);
}

TEST(TransformerShape, ShapesTheNetworkCannotHaveAreNamed) {
  TransformerShape shape;
  shape.heads = 5;
  EXPECT_EQ(shape.problem(), "heads 5 does not divide model_dim 32");
  shape = {};
  shape.patches = 7;
  EXPECT_EQ(shape.problem(), "patches 7 does not divide beams 720");
  shape = {};
  shape.layer_norm_eps = 0.0;
  EXPECT_EQ(shape.problem(), "layer_norm_eps must be > 0");
}

TEST(TransformerWeights, TensorsAreNamedAsThePublishedStateDictInFileOrder) {
  TransformerShape shape;
  shape.encoder_layers = 1;
  shape.decoder_layers = 1;
  std::vector<std::string> names;
  std::vector<std::string> shapes;
  TransformerWeights::zeros(shape).forEachTensor([&](const std::string& name, const auto& tensor) {
    names.push_back(name);
    shapes.push_back(std::to_string(tensor.rows()) + "x" + std::to_string(tensor.cols()));
  });
  ASSERT_EQ(names.size(), 3u + 12u + 2u + 12u + 2u);
  EXPECT_EQ(names[0], "encoder.embedding.linear.weight");
  EXPECT_EQ(shapes[0], "32x20");
  EXPECT_EQ(names[2], "encoder.embedding.pos_embed");
  EXPECT_EQ(shapes[2], "36x32");  // PyTorch's (patches, d)
  EXPECT_EQ(names[3], "encoder.layers.0.self_attn.q_proj.weight");
  EXPECT_EQ(names[7], "encoder.layers.0.self_attn_layer_norm.weight");
  EXPECT_EQ(names[9], "encoder.layers.0.PositionWiseFeedForward.w_1.weight");
  EXPECT_EQ(shapes[9], "256x32");
  EXPECT_EQ(names[15], "decoder.linear.weight");
  EXPECT_EQ(names[17], "decoder.layers.0.encoder_attn.q_proj.weight");
  EXPECT_EQ(names[21], "decoder.layers.0.encoder_attn_layer_norm.weight");
  EXPECT_EQ(names[28], "decoder.layers.0.final_layer_norm.bias");
  EXPECT_EQ(names[29], "prediction_head.weight");
  EXPECT_EQ(shapes[29], "2x64");
}

TEST(Transformer, AWrongTensorShapeIsNamed) {
  const TransformerShape shape;
  TransformerWeights weights = TransformerWeights::zeros(shape);
  weights.decoder[1].ffn_w2 = Eigen::MatrixXf::Zero(32, 255);
  try {
    Transformer net(shape, weights);
    FAIL() << "accepted";
  } catch (const core::InputError& e) {
    EXPECT_THAT(e.what(), HasSubstr("tensor decoder.layers.1.PositionWiseFeedForward.w_2.weight is 32 x 255, the shape needs 32 x 256"));
  }
  weights = TransformerWeights::zeros(shape);
  weights.encoder.pop_back();
  EXPECT_THROW(Transformer(shape, weights), core::InputError);
}

// A network small enough to follow by hand: 2 beams in 2 patches of 1, width 2, 2 heads of 1
// row each, no encoder block, one decoder block. LayerNorm's eps is 1e8 and its gain 1e4, so
// that norm(x) = (x - mean) * 1e4 / sqrt(var + 1e8) = x - mean (var ~ 1 vanishes next to 1e8 in
// float): the block's arithmetic shows through to the head.
struct HandNetwork {
  TransformerShape shape;
  TransformerWeights weights;
  HandNetwork() {
    shape.beams = 2;
    shape.patches = 2;
    shape.model_dim = 2;
    shape.heads = 2;
    shape.ffn_dim = 1;
    shape.encoder_layers = 0;
    shape.decoder_layers = 1;
    shape.layer_norm_eps = 1e8;
    weights = TransformerWeights::zeros(shape);
    weights.patch_w << 1.0f, 0.0f;  // token j = (r_j, 0)
    weights.goal_w << 1.0f, 0.0f;   // goal token i = (g_i, 0)
    TransformerBlock& b = weights.decoder[0];
    b.wq = b.wk = b.wv = b.wo = Eigen::Matrix2f::Identity();
    b.norm1_gain << 1e4f, 1e4f;
    b.norm2_gain << 1e4f, 1e4f;
    // The feed-forward network adds 0 (all zero), its inner residual keeps the token.
    weights.head_w << 2.0f, 0.0f, 0.0f, 0.0f,  // v_hat = 2 x token 0's first value
        0.0f, 0.0f, 2.0f, 0.0f;                // w_hat = 2 x token 1's first value
  }
};

TEST(Transformer, HandNetworkScalesScoresByTheFullWidthAndKeepsTheGoalTokensApart) {
  const HandNetwork hand;
  const Transformer net(hand.shape, hand.weights);
  // Ranges r = (0, sqrt(2) ln 3 = 1.5536724), goal (1, 0). Head 1 (row 0): token 0's query is g_x = 1, the
  // keys r_j / sqrt(d = 2) = (0, ln 3): softmax (1/4, 3/4), so it mixes 3/4 r_1 = 1.1652543.
  // Head 2 (row 1) reads zeros. Token 0 + attention = (1 + 1.1652543, 0); norm1 subtracts the
  // mean: (1.0826271, -1.0826271); the feed-forward block and norm2 keep it. v_hat = 2 x
  // 1.0826271 = 2.1652543. Token 1's query is g_y = 0: every score 0, weights (1/2, 1/2),
  // mixing r_1 / 2 = 0.7768362; norm1 centres (0 + 0.7768362, 0) to (0.3884181, -0.3884181):
  // w_hat = 2 x 0.3884181 = 0.7768362.
  // With the per-head scaling 1/sqrt(1) instead, head 1's weights would be (1, 3^sqrt(2)) /
  // (1 + 3^sqrt(2)) = (0.1746, 0.8254): v_hat = 1 + 1.2825 = 2.2825.
  const float r1 = std::sqrt(2.0f) * std::log(3.0f);
  const float ranges[2] = {0.0f, r1};
  const Eigen::Vector2f y = net.forward(ranges, {1.0f, 0.0f});
  EXPECT_NEAR(y[0], 2.1652543, 1e-5);
  EXPECT_NEAR(y[1], 0.7768362, 1e-5);
  // Goal (1, 2): token 1's query 2 gives keys' scores (0, 2 ln 3): weights (1, 9) / 10, mixing
  // 0.9 r_1 = 1.3983052: w_hat = 2 + 1.3983052 (centred and doubled as above); token 0 does
  // not see g_y (no self-attention), so v_hat stays.
  const Eigen::Vector2f y2 = net.forward(ranges, {1.0f, 2.0f});
  EXPECT_NEAR(y2[0], 2.1652543, 1e-5);
  EXPECT_NEAR(y2[1], 3.3983052, 1e-5);
}

TEST(Transformer, PatchesAreRunsOfConsecutiveBeams) {
  // 4 beams in 2 patches of 2: the embedding reads beam 2 j + k as patch j's k-th value. With
  // the embedding (1, 0; 0, 0) per patch, only beams 0 and 2 enter (as r_0, r_1 of the hand
  // network): moving beams 1 and 3 changes nothing, moving beam 2 changes the output.
  HandNetwork hand;
  hand.shape.beams = 4;
  hand.weights.patch_w = Eigen::Matrix2f::Zero();
  hand.weights.patch_w(0, 0) = 1.0f;
  const Transformer net(hand.shape, hand.weights);
  const float r1 = std::sqrt(2.0f) * std::log(3.0f);
  const float ranges[4] = {0.0f, 4.0f, r1, 4.0f};
  const float moved_odd[4] = {0.0f, 1.0f, r1, 2.0f};
  const float moved_two[4] = {0.0f, 4.0f, 2.0f * r1, 4.0f};
  const Eigen::Vector2f y = net.forward(ranges, {1.0f, 0.0f});
  EXPECT_NEAR(y[0], 2.1652543, 1e-5);  // the hand network's case
  EXPECT_EQ(net.forward(moved_odd, {1.0f, 0.0f}), y);
  EXPECT_GT(std::abs(net.forward(moved_two, {1.0f, 0.0f})[0] - y[0]), 0.1);
}

}  // namespace
}  // namespace barn::learning
