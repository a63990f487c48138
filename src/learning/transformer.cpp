#include "barn/learning/transformer.hpp"

#include <cmath>

#include "barn/core/errors.hpp"

namespace barn::learning {

namespace {

using Matrix = Eigen::MatrixXf;
using Vector = Eigen::VectorXf;

// LayerNorm of every column (token) in place: (x - mean) / sqrt(var + eps) * gain + bias, the
// variance biased (divided by d), as PyTorch's nn.LayerNorm.
void layerNorm(Matrix& x, const Vector& gain, const Vector& bias, float eps) {
  const float d = static_cast<float>(x.rows());
  for (Eigen::Index c = 0; c < x.cols(); ++c) {
    auto column = x.col(c);
    const float mean = column.sum() / d;
    column.array() -= mean;
    const float variance = column.squaredNorm() / d;
    column *= 1.0f / std::sqrt(variance + eps);
    column.array() = column.array() * gain.array() + bias.array();
  }
}

// queries = norm1(queries + Attention(queries, source)): multi-head attention without biases,
// the scores scaled by 1 / sqrt(d) (the whole width; see the header).
void attend(const TransformerBlock& b, int heads, float eps, Matrix& queries, const Matrix& source) {
  const Eigen::Index d = queries.rows();
  const Eigen::Index head_dim = d / heads;
  Matrix q, k, v;
  q.noalias() = b.wq * queries;
  // PyTorch divides the keys by sqrt(d) before the product; so does this, for its rounding.
  k.noalias() = b.wk * source;
  k /= std::sqrt(static_cast<float>(d));
  v.noalias() = b.wv * source;
  Matrix mixed(d, queries.cols());
  Matrix scores;  // (keys x queries)
  for (int h = 0; h < heads; ++h) {
    const Eigen::Index row = h * head_dim;
    scores.noalias() = k.middleRows(row, head_dim).transpose() * q.middleRows(row, head_dim);
    // Softmax over the keys (each column), shifted by its maximum as PyTorch's is.
    for (Eigen::Index c = 0; c < scores.cols(); ++c) {
      auto column = scores.col(c);
      column.array() = (column.array() - column.maxCoeff()).exp();
      column /= column.sum();
    }
    mixed.middleRows(row, head_dim).noalias() = v.middleRows(row, head_dim) * scores;
  }
  queries.noalias() += b.wo * mixed;
  layerNorm(queries, b.norm1_gain, b.norm1_bias, eps);
}

// x = norm2(x + W2 relu(W1 x + b1) + b2).
void feedForward(const TransformerBlock& b, float eps, Matrix& x) {
  Matrix hidden;
  hidden.noalias() = b.ffn_w1 * x;
  hidden.colwise() += b.ffn_b1;
  hidden = hidden.cwiseMax(0.0f);
  Matrix out;
  out.noalias() = b.ffn_w2 * hidden;
  out.colwise() += b.ffn_b2;
  x += out;
  layerNorm(x, b.norm2_gain, b.norm2_bias, eps);
}

}  // namespace

std::string TransformerShape::problem() const {
  const auto in = [](long long value, long long lo, long long hi) { return value >= lo && value <= hi; };
  if (!in(beams, 1, 100000)) return "beams " + std::to_string(beams) + " not in [1, 100000]";
  if (!in(patches, 1, beams) || beams % patches != 0)
    return "patches " + std::to_string(patches) + " does not divide beams " + std::to_string(beams);
  if (!in(model_dim, 1, 4096)) return "model_dim " + std::to_string(model_dim) + " not in [1, 4096]";
  if (!in(heads, 1, model_dim) || model_dim % heads != 0)
    return "heads " + std::to_string(heads) + " does not divide model_dim " + std::to_string(model_dim);
  if (!in(ffn_dim, 1, 65536)) return "ffn_dim " + std::to_string(ffn_dim) + " not in [1, 65536]";
  if (!in(encoder_layers, 0, 64)) return "encoder_layers " + std::to_string(encoder_layers) + " not in [0, 64]";
  if (!in(decoder_layers, 0, 64)) return "decoder_layers " + std::to_string(decoder_layers) + " not in [0, 64]";
  if (!(layer_norm_eps > 0.0) || !std::isfinite(layer_norm_eps)) return "layer_norm_eps must be > 0";
  return "";
}

std::size_t TransformerShape::parameterCount() const {
  std::size_t n = 0;
  TransformerWeights::forEachTensorShape(*this, [&](const std::string&, Eigen::Index rows, Eigen::Index cols) {
    n += static_cast<std::size_t>(rows) * static_cast<std::size_t>(cols);
  });
  return n;
}

TransformerWeights TransformerWeights::zeros(const TransformerShape& shape) {
  TransformerWeights w;
  w.encoder.resize(static_cast<std::size_t>(shape.encoder_layers));
  w.decoder.resize(static_cast<std::size_t>(shape.decoder_layers));
  visit(w, shape, [](const std::string&, auto& tensor, Eigen::Index rows, Eigen::Index cols) { tensor.setZero(rows, cols); });
  return w;
}

std::size_t TransformerWeights::count() const {
  std::size_t n = 0;
  forEachTensor([&](const std::string&, const auto& tensor) { n += static_cast<std::size_t>(tensor.size()); });
  return n;
}

Transformer::Transformer(TransformerShape shape, TransformerWeights weights)
    : shape_(std::move(shape)), weights_(std::move(weights)) {
  const std::string problem = shape_.problem();
  if (!problem.empty()) throw core::InputError("transformer: " + problem);
  // Every tensor against the shape's, in order; the layer counts first (the lists differ in length otherwise).
  if (weights_.encoder.size() != static_cast<std::size_t>(shape_.encoder_layers) ||
      weights_.decoder.size() != static_cast<std::size_t>(shape_.decoder_layers))
    throw core::InputError("transformer: " + std::to_string(weights_.encoder.size()) + " encoder and " +
                           std::to_string(weights_.decoder.size()) + " decoder blocks, the shape has " +
                           std::to_string(shape_.encoder_layers) + " and " + std::to_string(shape_.decoder_layers));
  std::vector<std::pair<Eigen::Index, Eigen::Index>> expected;
  TransformerWeights::forEachTensorShape(shape_, [&](const std::string&, Eigen::Index rows, Eigen::Index cols) {
    expected.emplace_back(rows, cols);
  });
  std::size_t i = 0;
  weights_.forEachTensor([&](const std::string& name, const auto& tensor) {
    const auto [rows, cols] = expected[i++];
    if (tensor.rows() != rows || tensor.cols() != cols)
      throw core::InputError("transformer: tensor " + name + " is " + std::to_string(tensor.rows()) + " x " +
                             std::to_string(tensor.cols()) + ", the shape needs " + std::to_string(rows) + " x " +
                             std::to_string(cols));
  });
}

Eigen::Vector2f Transformer::forward(const float* ranges, const Eigen::Vector2f& goal) const {
  const TransformerWeights& w = weights_;
  const float eps = static_cast<float>(shape_.layer_norm_eps);
  // Encoder: the scan's patches as columns, embedded.
  const Eigen::Map<const Matrix> patches(ranges, shape_.patchSize(), shape_.patches);
  Matrix x;
  x.noalias() = w.patch_w * patches;
  x.colwise() += w.patch_b;
  x += w.position.transpose();
  for (const TransformerBlock& block : w.encoder) {
    attend(block, shape_.heads, eps, x, x);
    feedForward(block, eps, x);
  }
  // Decoder: one token per goal component, each attending to the encoder's tokens only.
  Matrix tokens(shape_.model_dim, 2);
  tokens.col(0) = w.goal_w * goal.x() + w.goal_b;
  tokens.col(1) = w.goal_w * goal.y() + w.goal_b;
  for (const TransformerBlock& block : w.decoder) {
    attend(block, shape_.heads, eps, tokens, x);
    feedForward(block, eps, tokens);
  }
  // Head on the two tokens stacked (token 0's d values, then token 1's: column-major order).
  const Eigen::Map<const Vector> stacked(tokens.data(), tokens.size());
  Eigen::Vector2f y = w.head_w * stacked;
  y += w.head_b;
  return y;
}

}  // namespace barn::learning
