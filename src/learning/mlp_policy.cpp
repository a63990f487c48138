#include "barn/learning/mlp_policy.hpp"

#include <bit>
#include <cmath>
#include <cstring>
#include <limits>

#include "barn/core/errors.hpp"
#include "barn/core/text_io.hpp"
#include "policy_header.hpp"

namespace barn::learning {

namespace {

using header::FixedText;
using header::FormatVersion;
using header::HexNumber;
using header::IntRange;
using header::PlantHash;

constexpr const char* kFormat = "barnbench-mlp-policy";
constexpr int kVersion = 1;
constexpr const char* kActivation = "relu";
constexpr const char* kLayout =
    "little-endian; per layer in order: weight (out x in, column-major), then bias";
constexpr int kMaxLayers = 64;
constexpr long long kMaxUnits = 1 << 20;

struct MlpHeader {
  std::string format = kFormat;
  FormatVersion version{kVersion, kVersion};
  std::string architecture;
  std::string output_activation;
  std::string output_low;
  std::string output_high;
  std::string input;
  std::string output;
  std::string dtype;
  long long payload_bytes = 0;
  std::string name;
  HexNumber config_hash;
  PlantHash plant_hash;
  std::string trained;
  long long seed = 0;
  long long steps = 0;

  template <class V> void visit(V& v) {
    const long long max = std::numeric_limits<long long>::max();
    v("format", format); v("version", version); v("architecture", architecture);
    v("activation", FixedText{kActivation}); v("output_activation", output_activation);
    v("output_low", output_low); v("output_high", output_high); v("input", input); v("output", output);
    v("dtype", dtype); v("layout", FixedText{kLayout}); v("payload_bytes", payload_bytes, IntRange{0, max});
    v("name", name); v("config_hash", config_hash); v("plant_hash", plant_hash); v("trained", trained);
    v("seed", seed, IntRange{0, max}); v("steps", steps, IntRange{0, max});
  }
};

const std::vector<std::string>& headerKeys() {
  static const std::vector<std::string> keys = header::keysOf<MlpHeader>();
  return keys;
}

std::string joinNumbers(const std::vector<double>& values) {
  std::string out;
  for (double v : values) out += (out.empty() ? "" : ",") + core::formatDouble(v);
  return out;
}

// "a,b,c" -> numbers; nullopt-like empty result with `ok` false on a bad item.
std::vector<double> splitNumbers(const std::string& text, char separator, bool& ok) {
  std::vector<double> out;
  ok = true;
  std::size_t start = 0;
  while (start <= text.size()) {
    const std::size_t end = std::min(text.find(separator, start), text.size());
    const std::string item = text.substr(start, end - start);
    char* stop = nullptr;
    const double value = std::strtod(item.c_str(), &stop);
    if (item.empty() || stop != item.c_str() + item.size() || !std::isfinite(value)) {
      ok = false;
      return {};
    }
    out.push_back(value);
    start = end + 1;
  }
  return out;
}

void requireOneLine(const std::string& text, const char* field) {
  if (text.find_first_of("\r\n") != std::string::npos)
    throw core::InputError(std::string("mlp policy: ") + field + " must be one line");
}

std::size_t parameterCount(const std::vector<int>& layers) {
  std::size_t count = 0;
  for (std::size_t k = 1; k < layers.size(); ++k)
    count += static_cast<std::size_t>(layers[k]) * (static_cast<std::size_t>(layers[k - 1]) + 1);
  return count;
}

}  // namespace

float halfToFloat(std::uint16_t h) {
  const std::uint32_t sign = static_cast<std::uint32_t>(h & 0x8000u) << 16;
  const std::uint32_t exponent = (h >> 10) & 0x1Fu;
  std::uint32_t mantissa = h & 0x3FFu;
  std::uint32_t bits;
  if (exponent == 0) {
    if (mantissa == 0) {
      bits = sign;  // +-0
    } else {  // subnormal: normalise
      int shift = 0;
      while (!(mantissa & 0x400u)) {
        mantissa <<= 1;
        ++shift;
      }
      mantissa &= 0x3FFu;
      bits = sign | (static_cast<std::uint32_t>(127 - 15 - shift + 1) << 23) | (mantissa << 13);
    }
  } else if (exponent == 0x1F) {
    bits = sign | 0x7F800000u | (mantissa << 13);  // inf or NaN
  } else {
    bits = sign | ((exponent + 127 - 15) << 23) | (mantissa << 13);
  }
  return std::bit_cast<float>(bits);
}

std::uint16_t floatToHalf(float f) {
  const std::uint32_t bits = std::bit_cast<std::uint32_t>(f);
  const std::uint16_t sign = static_cast<std::uint16_t>((bits >> 16) & 0x8000u);
  const std::uint32_t abs = bits & 0x7FFFFFFFu;
  if (abs >= 0x7F800000u) return static_cast<std::uint16_t>(sign | 0x7C00u | (abs > 0x7F800000u ? 0x200u : 0u));
  if (abs >= 0x477FF000u) return static_cast<std::uint16_t>(sign | 0x7C00u);  // rounds past 65504: inf
  if (abs < 0x38800000u) {
    // Below the smallest normal half: a subnormal (or 0) in units of 2^-24. Scaling by 2^24 is
    // exact in float, and nearbyint rounds to nearest even; 1024 is the smallest normal's code.
    const float scaled = std::bit_cast<float>(abs) * 16777216.0f;
    return static_cast<std::uint16_t>(sign | static_cast<std::uint32_t>(std::nearbyint(scaled)));
  }
  std::uint32_t value = ((abs >> 23) - 127 + 15) << 10 | ((abs >> 13) & 0x3FFu);
  const std::uint32_t rest = abs & 0x1FFFu;
  if (rest > 0x1000u || (rest == 0x1000u && (value & 1u))) ++value;  // may carry into the exponent: correct
  return static_cast<std::uint16_t>(sign | value);
}

std::string mlpPolicyBytes(const MlpPolicyInfo& info, const std::vector<MlpLayer>& layers) {
  const MlpPolicy check(info, layers);  // the shapes chain
  requireOneLine(info.input, "input");
  requireOneLine(info.output_text, "output");
  requireOneLine(info.name, "name");
  requireOneLine(info.trained, "trained");
  std::string payload;
  for (const MlpLayer& layer : layers) {
    const auto append = [&](const float* data, Eigen::Index count) {
      if (info.half) {
        for (Eigen::Index k = 0; k < count; ++k) {
          const std::uint16_t h = floatToHalf(data[k]);
          payload.push_back(static_cast<char>(h & 0xFF));
          payload.push_back(static_cast<char>(h >> 8));
        }
      } else {
        header::appendFloats(payload, data, static_cast<std::size_t>(count));
      }
    };
    append(layer.weight.data(), layer.weight.size());
    append(layer.bias.data(), layer.bias.size());
  }
  MlpHeader fields;
  std::string architecture;
  for (int size : info.layers) architecture += (architecture.empty() ? "" : "-") + std::to_string(size);
  fields.architecture = architecture;
  fields.output_activation = info.output == MlpOutput::Tanh ? "tanh" : "linear";
  fields.output_low = joinNumbers(info.output_low);
  fields.output_high = joinNumbers(info.output_high);
  fields.input = info.input;
  fields.output = info.output_text;
  fields.dtype = info.half ? "float16" : "float32";
  fields.payload_bytes = static_cast<long long>(payload.size());
  fields.name = info.name;
  fields.config_hash.value = info.config_hash;
  fields.plant_hash.value = info.plant_hash;
  fields.trained = info.trained;
  fields.seed = static_cast<long long>(info.seed);
  fields.steps = info.steps;
  header::HeaderWriter writer;
  fields.visit(writer);
  return writer.text() + payload;
}

void writeMlpPolicyFile(const std::filesystem::path& path, const MlpPolicyInfo& info, const std::vector<MlpLayer>& layers) {
  core::writeFileAtomic(path, mlpPolicyBytes(info, layers));
}

MlpPolicy::MlpPolicy(MlpPolicyInfo info, std::vector<MlpLayer> layers) : info_(std::move(info)), layers_(std::move(layers)) {
  const std::vector<int>& sizes = info_.layers;
  if (sizes.size() < 2) throw core::InputError("mlp policy: needs at least an input and an output size");
  if (layers_.size() != sizes.size() - 1)
    throw core::InputError("mlp policy: " + std::to_string(layers_.size()) + " layers for an architecture of " +
                           std::to_string(sizes.size() - 1));
  for (std::size_t k = 0; k < layers_.size(); ++k) {
    const MlpLayer& layer = layers_[k];
    if (layer.weight.rows() != sizes[k + 1] || layer.weight.cols() != sizes[k] || layer.bias.size() != sizes[k + 1])
      throw core::InputError("mlp policy: layer " + std::to_string(k + 1) + " is not " + std::to_string(sizes[k + 1]) +
                             " x " + std::to_string(sizes[k]) + " with " + std::to_string(sizes[k + 1]) + " biases");
  }
  if (info_.output == MlpOutput::Tanh) {
    const std::size_t outputs = static_cast<std::size_t>(sizes.back());
    if (info_.output_low.size() != outputs || info_.output_high.size() != outputs)
      throw core::InputError("mlp policy: output_low and output_high need one value per output (" +
                             std::to_string(outputs) + ")");
    for (std::size_t k = 0; k < outputs; ++k)
      if (!(info_.output_low[k] < info_.output_high[k]))
        throw core::InputError("mlp policy: output_low must be below output_high for every output");
  }
}

MlpPolicy MlpPolicy::load(const std::filesystem::path& path) { return parse(core::readTextFile(path), path.string()); }

MlpPolicy MlpPolicy::parse(const std::string& file, const std::string& source_name) {
  const std::string where = source_name + ": ";
  const auto fail = [&](const std::string& message) { throw core::InputError(where + message); };
  MlpHeader fields;
  header::HeaderLines lines = header::readHeader(file, kFormat, "an MLP policy file", headerKeys(), where, fields);

  MlpPolicyInfo info;
  bool ok = false;
  for (double size : splitNumbers(fields.architecture, '-', ok)) {
    if (size < 1 || size > static_cast<double>(kMaxUnits) || size != std::floor(size)) {
      ok = false;
      break;
    }
    info.layers.push_back(static_cast<int>(size));
  }
  if (!ok || info.layers.size() < 2 || info.layers.size() > kMaxLayers + 1)
    fail("header: architecture '" + fields.architecture + "' is not sizes joined by '-' (2 to 65 of them, each 1 to 2^20)");
  if (fields.output_activation == "tanh") info.output = MlpOutput::Tanh;
  else if (fields.output_activation == "linear") info.output = MlpOutput::Linear;
  else fail("header: output_activation '" + fields.output_activation + "' is not tanh or linear");
  if (info.output == MlpOutput::Tanh) {
    info.output_low = splitNumbers(fields.output_low, ',', ok);
    if (!ok) fail("header: output_low '" + fields.output_low + "' is not numbers joined by ','");
    info.output_high = splitNumbers(fields.output_high, ',', ok);
    if (!ok) fail("header: output_high '" + fields.output_high + "' is not numbers joined by ','");
  }
  if (fields.dtype == "float16") info.half = true;
  else if (fields.dtype != "float32") fail("header: dtype '" + fields.dtype + "' is not float32 or float16");
  info.input = fields.input;
  info.output_text = fields.output;
  info.name = fields.name;
  info.config_hash = fields.config_hash.value;
  info.plant_hash = fields.plant_hash.value;
  info.trained = fields.trained;
  info.seed = static_cast<std::uint64_t>(fields.seed);
  info.steps = fields.steps;

  const std::size_t width = info.half ? 2 : 4;
  const std::size_t expected = width * parameterCount(info.layers);
  if (static_cast<std::size_t>(fields.payload_bytes) != expected)
    fail("wrong shape: payload_bytes " + lines.values["payload_bytes"] + " does not match the architecture (" +
         std::to_string(expected) + " bytes of " + fields.dtype + ")");
  const std::size_t available = file.size() - lines.payload_offset;
  if (available < expected)
    fail("truncated: expected " + std::to_string(expected) + " bytes of weights, found " + std::to_string(available));
  if (available > expected)
    fail(std::to_string(available - expected) + " bytes after the weights (expected exactly " + std::to_string(expected) + ")");

  const unsigned char* in = reinterpret_cast<const unsigned char*>(file.data() + lines.payload_offset);
  std::vector<MlpLayer> layers;
  const auto read = [&](float* data, Eigen::Index count, std::size_t layer) {
    for (Eigen::Index k = 0; k < count; ++k) {
      float value;
      if (info.half) {
        value = halfToFloat(static_cast<std::uint16_t>(in[0] | (in[1] << 8)));
      } else {
        std::uint32_t bits = static_cast<std::uint32_t>(in[0]) | static_cast<std::uint32_t>(in[1]) << 8 |
                             static_cast<std::uint32_t>(in[2]) << 16 | static_cast<std::uint32_t>(in[3]) << 24;
        value = std::bit_cast<float>(bits);
      }
      in += width;
      if (!std::isfinite(value)) fail("weights: layer " + std::to_string(layer) + " holds a non-finite value");
      data[k] = value;
    }
  };
  for (std::size_t k = 1; k < info.layers.size(); ++k) {
    MlpLayer layer;
    layer.weight.resize(info.layers[k], info.layers[k - 1]);
    layer.bias.resize(info.layers[k]);
    read(layer.weight.data(), layer.weight.size(), k);
    read(layer.bias.data(), layer.bias.size(), k);
    layers.push_back(std::move(layer));
  }
  try {
    return MlpPolicy(std::move(info), std::move(layers));
  } catch (const core::InputError& e) {
    throw core::InputError(where + "header: " + e.what());
  }
}

Eigen::VectorXd MlpPolicy::forward(const float* input) const {
  Eigen::VectorXf h = Eigen::Map<const Eigen::VectorXf>(input, inputs());
  for (std::size_t k = 0; k < layers_.size(); ++k) {
    Eigen::VectorXf z = layers_[k].bias;
    z.noalias() += layers_[k].weight * h;
    if (k + 1 < layers_.size()) h = z.cwiseMax(0.0f);
    else h = std::move(z);
  }
  Eigen::VectorXd out = h.cast<double>();
  if (info_.output == MlpOutput::Tanh)
    for (Eigen::Index k = 0; k < out.size(); ++k) {
      const double low = info_.output_low[static_cast<std::size_t>(k)];
      const double high = info_.output_high[static_cast<std::size_t>(k)];
      out[k] = std::tanh(out[k]) * (high - low) / 2.0 + (high + low) / 2.0;
    }
  return out;
}

}  // namespace barn::learning
