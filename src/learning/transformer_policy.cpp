#include "barn/learning/transformer_policy.hpp"

#include <limits>
#include <string_view>
#include <vector>

#include "barn/core/errors.hpp"
#include "barn/core/text_io.hpp"
#include "barn/learning/policy.hpp"
#include "policy_header.hpp"

namespace barn::learning {

namespace {

using header::FixedText;
using header::FormatVersion;
using header::HexNumber;
using header::IntRange;

constexpr const char* kFormat = "barnbench-transformer-policy";
constexpr int kVersion = 1;  // written and read
// Fixed descriptions: part of the contract (see policy_header.hpp's FixedText).
constexpr const char* kInput =
    "ranges[beams] clipped to [0, range_clip] (+inf -> range_clip), beams / patches consecutive beams per patch; goal_x, goal_y";
constexpr const char* kGoal = "local goal in the robot frame, x forward, y left, as given; one token per component";
constexpr const char* kOutput = "v_hat, w_hat before the controller's scaling";
constexpr const char* kAttention = "no bias; scores q.k / sqrt(model_dim); decoder: cross-attention to the encoder only";
constexpr const char* kBlock = "post-norm: x = norm1(x + attention); x = norm2(x + w2 relu(w1 x + b1) + b2)";
constexpr const char* kLayout =
    "float32 little-endian; tensors in the documented order, named as the published state_dict; matrices column-major";

// The header's values as written, every key required, listed once here.
struct TransformerHeader {
  std::string format = kFormat;
  FormatVersion version{kVersion, kVersion};
  TransformerShape shape;
  double range_clip = 0.0;
  long long payload_bytes = 0;
  HexNumber weights_fnv1a64;
  std::string name;
  std::string source;

  template <class V> void visit(V& v) {
    const long long max = std::numeric_limits<long long>::max();
    v("format", format); v("version", version);
    v("beams", shape.beams, IntRange{1, 100000}); v("patches", shape.patches, IntRange{1, 100000});
    v("model_dim", shape.model_dim, IntRange{1, 4096}); v("heads", shape.heads, IntRange{1, 4096});
    v("ffn_dim", shape.ffn_dim, IntRange{1, 65536});
    v("encoder_layers", shape.encoder_layers, IntRange{0, 64}); v("decoder_layers", shape.decoder_layers, IntRange{0, 64});
    v("layer_norm_eps", shape.layer_norm_eps); v("range_clip", range_clip);
    v("input", FixedText{kInput}); v("goal", FixedText{kGoal}); v("output", FixedText{kOutput});
    v("attention", FixedText{kAttention}); v("block", FixedText{kBlock}); v("layout", FixedText{kLayout});
    v("payload_bytes", payload_bytes, IntRange{0, max}); v("weights_fnv1a64", weights_fnv1a64);
    v("name", name); v("source", source);
  }
};

const std::vector<std::string>& headerKeys() {
  static const std::vector<std::string> keys = header::keysOf<TransformerHeader>();
  return keys;
}

std::string payloadOf(const TransformerWeights& weights) {
  std::string payload;
  payload.reserve(4 * weights.count());
  weights.forEachTensor([&](const std::string&, const auto& tensor) {
    header::appendFloats(payload, tensor.data(), static_cast<std::size_t>(tensor.size()));
  });
  return payload;
}

void requireOneLine(const std::string& text, const char* field) {
  if (text.find_first_of("\r\n") != std::string::npos)
    throw core::InputError(std::string("transformer policy: ") + field + " must be one line");
}

}  // namespace

std::string transformerPolicyBytes(const TransformerPolicyInfo& info, const TransformerWeights& weights) {
  requireOneLine(info.name, "name");
  requireOneLine(info.source, "source");
  const std::string payload = payloadOf(weights);
  TransformerHeader fields;
  fields.shape = info.shape;
  fields.range_clip = info.range_clip;
  fields.payload_bytes = static_cast<long long>(payload.size());
  fields.weights_fnv1a64.value = core::fnv1a64(payload);
  fields.name = info.name;
  fields.source = info.source;
  header::HeaderWriter writer;
  fields.visit(writer);
  return writer.text() + payload;
}

void writeTransformerPolicyFile(const std::filesystem::path& path, const TransformerPolicyInfo& info,
                                const TransformerWeights& weights) {
  core::writeFileAtomic(path, transformerPolicyBytes(info, weights));
}

TransformerPolicy::TransformerPolicy(TransformerPolicyInfo info, TransformerWeights weights)
    : info_(std::move(info)), network_(info_.shape, std::move(weights)) {}

// Read as Policy::load reads (core::readTextFile: regular files only, at their own size).
TransformerPolicy TransformerPolicy::load(const std::filesystem::path& path) {
  return parse(core::readTextFile(path), path.string());
}

TransformerPolicy TransformerPolicy::parse(const std::string& file, const std::string& source_name) {
  const std::string where = source_name + ": ";
  const auto fail = [&](const std::string& message) { throw core::InputError(where + message); };

  TransformerHeader fields;
  header::HeaderLines lines = header::readHeader(file, kFormat, "a transformer policy file", headerKeys(), where, fields);

  TransformerPolicyInfo info;
  info.shape = fields.shape;
  const std::string problem = info.shape.problem();
  if (!problem.empty()) fail("wrong shape: " + problem);
  info.range_clip = fields.range_clip;
  if (!(info.range_clip > 0.0)) fail("header: range_clip must be > 0");
  info.name = fields.name;
  info.source = fields.source;

  // The payload size follows from the shape (bounded, so this cannot overflow); check it
  // against the header and the file before allocating, so a short file claiming a huge network
  // is refused without the allocation.
  const std::size_t expected = 4 * info.shape.parameterCount();
  if (static_cast<std::size_t>(fields.payload_bytes) != expected)
    fail("wrong shape: payload_bytes " + lines.values["payload_bytes"] + " does not match the shape (" +
         std::to_string(expected) + " bytes)");
  const std::size_t available = file.size() - lines.payload_offset;
  if (available > expected)
    fail(std::to_string(available - expected) + " bytes after the weights (expected exactly " + std::to_string(expected) + ")");
  if (available < expected) {
    // Name the tensor the file ends in (from the shape alone: nothing of the claimed size is
    // allocated for a file that does not hold it).
    std::size_t offset = 0;
    std::string cut;
    TransformerWeights::forEachTensorShape(info.shape, [&](const std::string& name, Eigen::Index rows, Eigen::Index cols) {
      offset += 4 * static_cast<std::size_t>(rows) * static_cast<std::size_t>(cols);
      if (cut.empty() && offset > available) cut = name;
    });
    fail("truncated: expected " + std::to_string(expected) + " bytes of weights, found " + std::to_string(available) +
         " (the file ends in tensor " + cut + ")");
  }
  TransformerWeights weights = TransformerWeights::zeros(info.shape);
  const std::string_view payload(file.data() + lines.payload_offset, expected);
  const char* in = payload.data();
  std::string bad;
  weights.forEachTensor([&](const std::string& name, auto& tensor) {
    if (!header::readFloats(in, tensor.data(), static_cast<std::size_t>(tensor.size())) && bad.empty()) bad = name;
    in += 4 * tensor.size();
  });
  if (!bad.empty()) fail("weights: tensor " + bad + " holds a non-finite value");
  const std::uint64_t digest = core::fnv1a64(payload);
  if (digest != fields.weights_fnv1a64.value)
    fail("weights: their FNV-1a 64 digest is " + core::formatHex(digest) + ", the header says " +
         core::formatHex(fields.weights_fnv1a64.value) + " (the weights were altered)");
  return TransformerPolicy(std::move(info), std::move(weights));
}

Eigen::Vector2d TransformerPolicy::act(const core::LaserScan& scan, const Eigen::Vector2d& goal_robot_frame) const {
  const int beams = info_.shape.beams;
  if (scan.ranges.size() != static_cast<std::size_t>(beams))
    throw core::InputError("transformer policy '" + info_.name + "' expects " + std::to_string(beams) +
                           " beams, the scan has " + std::to_string(scan.ranges.size()));
  Eigen::VectorXf ranges(beams);
  clipRanges(scan.ranges, info_.range_clip, ranges.data());
  const Eigen::Vector2f y = network_.forward(ranges.data(), goal_robot_frame.cast<float>());
  return y.cast<double>();
}

}  // namespace barn::learning
