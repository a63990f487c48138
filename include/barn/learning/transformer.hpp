#pragma once
/// The LiCS-KI policy network (BARN Challenge 2024 winner): a small transformer that maps a
/// LiDAR scan and a local goal to a normalised command. Inference only, in float, on Eigen
/// (docs/systems/lics.md has the network with every dimension and its source).
///
/// With d = model_dim, n = patches, P = beams / patches, h = heads, and every token a column:
///
///     X   = We R + be + E^T                     R (P x n): patch j = beams jP .. jP+P-1 (clipped)
///     encoder block, encoder_layers times:
///         X = norm1(X + Attention(X, X))
///         X = norm2(X + W2 relu(W1 X + b1) + b2)
///     T   = [wg g_x + bg, wg g_y + bg]          (d x 2): the goal's two components, one shared Linear(1 -> d)
///     decoder block, decoder_layers times:
///         T = norm1(T + Attention(T, X))        cross-attention only: the two tokens never meet
///         T = norm2(T + W2 relu(W1 T + b1) + b2)
///     (v_hat, w_hat) = Wh [T_0; T_1] + bh       no squashing
///
/// Attention(Q, S) = Wo [head_1 ... head_h], head_i = V_i softmax_keys(K_i^T Q_i / sqrt(d)) with
/// Q = Wq Q, K = Wk S, V = Wv S and the i-th d/h rows of each: the projections have no bias,
/// and the scores are scaled by the full width sqrt(d), not sqrt(d / h) (the published model's
/// quirk). norm: LayerNorm over a token's d values (biased variance, eps layer_norm_eps), with
/// a gain and a bias. Blocks are post-norm.
///
/// Thread-safe: forward() is const and keeps nothing between calls.

#include <cstddef>
#include <string>
#include <vector>

#include <Eigen/Core>

namespace barn::learning {

/// The hyper-parameters (defaults: the published LiCS-KI network, lics/scripts/run.py).
struct TransformerShape {
  int beams = 720;              // [-] ranges in the input
  int patches = 36;             // [-] encoder tokens: beams / patches consecutive beams each
  int model_dim = 32;           // [-] token width d
  int heads = 4;                // [-] attention heads, d / heads rows each
  int ffn_dim = 256;            // [-] hidden units of each block's feed-forward network
  int encoder_layers = 3;       // [-]
  int decoder_layers = 3;       // [-]
  double layer_norm_eps = 1e-5; // [-] LayerNorm's epsilon (PyTorch's default)

  int patchSize() const { return beams / patches; }   // [-] beams per patch
  /// Number of floats in the weights (of a valid shape; cannot overflow within the bounds).
  std::size_t parameterCount() const;
  /// Empty if the shape is one this network can have, else what is wrong with it. Bounds:
  /// beams <= 100000 and divisible by patches; d <= 4096 and divisible by heads; ffn_dim
  /// <= 65536; at most 64 encoder and 64 decoder layers; eps > 0.
  std::string problem() const;
};

/// One encoder or decoder block.
struct TransformerBlock {
  Eigen::MatrixXf wq, wk, wv, wo;              // (d x d) attention projections, no bias
  Eigen::VectorXf norm1_gain, norm1_bias;      // (d) LayerNorm after attention
  Eigen::MatrixXf ffn_w1;                      // (ffn_dim x d)
  Eigen::VectorXf ffn_b1;                      // (ffn_dim)
  Eigen::MatrixXf ffn_w2;                      // (d x ffn_dim)
  Eigen::VectorXf ffn_b2;                      // (d)
  Eigen::VectorXf norm2_gain, norm2_bias;      // (d) LayerNorm after the feed-forward network
};

struct TransformerWeights {
  Eigen::MatrixXf patch_w;                     // (d x P) patch embedding
  Eigen::VectorXf patch_b;                     // (d)
  Eigen::MatrixXf position;                    // (patches x d) learned position embedding, a row per patch
  std::vector<TransformerBlock> encoder;       // encoder_layers blocks
  Eigen::VectorXf goal_w, goal_b;              // (d) the goal tokens' Linear(1 -> d)
  std::vector<TransformerBlock> decoder;       // decoder_layers blocks
  Eigen::MatrixXf head_w;                      // (2 x 2d) on the two decoder tokens, stacked
  Eigen::VectorXf head_b;                      // (2)

  /// Zero weights of `shape` (assumed valid: TransformerShape::problem() empty).
  static TransformerWeights zeros(const TransformerShape& shape);
  /// Number of floats.
  std::size_t count() const;

  /// Calls f(name, tensor) for every tensor in file order, with the name the published
  /// PyTorch state_dict gives it (e.g. "encoder.layers.0.self_attn.q_proj.weight") and the
  /// tensor an Eigen matrix or vector of its PyTorch shape (decoder.linear.weight, d x 1 there,
  /// is a vector), column-major. The order: the patch embedding's weight and bias, the position
  /// embedding; per encoder block q k v out, norm1 gain and bias, the feed-forward w1 b1 w2 b2,
  /// norm2 gain and bias; the goal embedding's weight and bias; per decoder block the same; the
  /// head's weight and bias.
  template <class F> void forEachTensor(F&& f) {
    visit(*this, TransformerShape{}, [&](const std::string& name, auto& tensor, Eigen::Index, Eigen::Index) { f(name, tensor); });
  }
  template <class F> void forEachTensor(F&& f) const {
    visit(*this, TransformerShape{}, [&](const std::string& name, auto& tensor, Eigen::Index, Eigen::Index) { f(name, tensor); });
  }
  /// Calls f(name, rows, cols) for every tensor `shape` gives, in file order, allocating none.
  template <class F> static void forEachTensorShape(const TransformerShape& shape, F&& f) {
    TransformerWeights skeleton;  // the block lists sized, every tensor empty
    skeleton.encoder.resize(static_cast<std::size_t>(shape.encoder_layers));
    skeleton.decoder.resize(static_cast<std::size_t>(shape.decoder_layers));
    visit(skeleton, shape, [&](const std::string& name, auto&, Eigen::Index rows, Eigen::Index cols) { f(name, rows, cols); });
  }

 private:
  // The one list of tensors: f(name, tensor, rows, cols) with rows x cols what `shape` gives the
  // tensor (blocks as many as `self` holds).
  template <class Self, class F> static void visit(Self& self, const TransformerShape& shape, F&& f);
};

class Transformer {
 public:
  /// Throws InputError naming the first tensor whose shape `shape` does not give (or the
  /// shape's problem).
  Transformer(TransformerShape shape, TransformerWeights weights);

  /// (v_hat, w_hat) for shape().beams ranges already clipped and the goal as given.
  Eigen::Vector2f forward(const float* ranges, const Eigen::Vector2f& goal) const;

  const TransformerShape& shape() const { return shape_; }
  const TransformerWeights& weights() const { return weights_; }

 private:
  TransformerShape shape_;
  TransformerWeights weights_;
};

// ---------------------------------------------------------------------------------------------

template <class Self, class F>
void TransformerWeights::visit(Self& self, const TransformerShape& shape, F&& f) {
  const Eigen::Index d = shape.model_dim, ffn = shape.ffn_dim;
  const auto block = [&](auto& b, const std::string& prefix, const std::string& attention, const std::string& norm1) {
    f(prefix + attention + ".q_proj.weight", b.wq, d, d);
    f(prefix + attention + ".k_proj.weight", b.wk, d, d);
    f(prefix + attention + ".v_proj.weight", b.wv, d, d);
    f(prefix + attention + ".out_proj.weight", b.wo, d, d);
    f(prefix + norm1 + ".weight", b.norm1_gain, d, 1);
    f(prefix + norm1 + ".bias", b.norm1_bias, d, 1);
    f(prefix + "PositionWiseFeedForward.w_1.weight", b.ffn_w1, ffn, d);
    f(prefix + "PositionWiseFeedForward.w_1.bias", b.ffn_b1, ffn, 1);
    f(prefix + "PositionWiseFeedForward.w_2.weight", b.ffn_w2, d, ffn);
    f(prefix + "PositionWiseFeedForward.w_2.bias", b.ffn_b2, d, 1);
    f(prefix + "final_layer_norm.weight", b.norm2_gain, d, 1);
    f(prefix + "final_layer_norm.bias", b.norm2_bias, d, 1);
  };
  f(std::string("encoder.embedding.linear.weight"), self.patch_w, d, shape.patchSize());
  f(std::string("encoder.embedding.linear.bias"), self.patch_b, d, 1);
  f(std::string("encoder.embedding.pos_embed"), self.position, shape.patches, d);
  for (std::size_t l = 0; l < self.encoder.size(); ++l)
    block(self.encoder[l], "encoder.layers." + std::to_string(l) + ".", "self_attn", "self_attn_layer_norm");
  f(std::string("decoder.linear.weight"), self.goal_w, d, 1);
  f(std::string("decoder.linear.bias"), self.goal_b, d, 1);
  for (std::size_t l = 0; l < self.decoder.size(); ++l)
    block(self.decoder[l], "decoder.layers." + std::to_string(l) + ".", "encoder_attn", "encoder_attn_layer_norm");
  f(std::string("prediction_head.weight"), self.head_w, 2, 2 * d);
  f(std::string("prediction_head.bias"), self.head_b, 2, 1);
}

}  // namespace barn::learning
