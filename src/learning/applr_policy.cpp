#include "barn/learning/applr_policy.hpp"

#include <algorithm>
#include <cmath>
#include <limits>
#include <numbers>
#include <sstream>
#include <string_view>

#include "barn/core/errors.hpp"
#include "barn/core/text_io.hpp"
#include "policy_header.hpp"

namespace barn::learning {

namespace {

using header::FixedText;
using header::FormatVersion;
using header::HexNumber;
using header::IntRange;

constexpr const char* kFormat = "barnbench-applr-policy";
constexpr int kVersion = 1;  // written and read
// Fixed descriptions: part of the contract (see policy_header.hpp's FixedText).
constexpr const char* kActivation = "relu";
constexpr const char* kInput =
    "ranges[beams] clipped at range_clip (+inf and NaN -> range_clip), each (r - range_clip / 2) / range_clip; "
    "then the local goal's angle in the robot frame / (2 pi)";
constexpr const char* kOutput =
    "tanh; float32 bias + scale * tanh with scale = (hi - lo) / 2, bias = (hi + lo) / 2; then clipped to [lo, hi]";
constexpr const char* kLayout =
    "float32 little-endian; w1 b1 w2 b2 w3 b3 (state_dict head.mlp.0, head.mlp.2, fc); matrices column-major";
constexpr int kMaxHidden = 4096;

// The header's values as written, every key required, listed once here.
struct ApplrHeader {
  std::string format = kFormat;
  FormatVersion version{kVersion, kVersion};
  std::string architecture;  // inputs-hidden-hidden-outputs
  int beams = 0;
  double range_clip = 0.0;
  std::string actions;  // "name lo hi; name lo hi; ..."
  long long payload_bytes = 0;
  HexNumber weights_fnv1a64;
  std::string name;
  std::string source;

  template <class V> void visit(V& v) {
    const long long max = std::numeric_limits<long long>::max();
    v("format", format); v("version", version); v("architecture", architecture);
    v("activation", FixedText{kActivation}); v("beams", beams, IntRange{1, 100000}); v("range_clip", range_clip);
    v("input", FixedText{kInput}); v("output", FixedText{kOutput}); v("actions", actions); v("layout", FixedText{kLayout});
    v("payload_bytes", payload_bytes, IntRange{0, max}); v("weights_fnv1a64", weights_fnv1a64);
    v("name", name); v("source", source);
  }
};

const std::vector<std::string>& headerKeys() {
  static const std::vector<std::string> keys = header::keysOf<ApplrHeader>();
  return keys;
}

bool validName(const std::string& name) {
  return !name.empty() && std::all_of(name.begin(), name.end(), [](char c) {
    return (c >= 'a' && c <= 'z') || (c >= '0' && c <= '9') || c == '_';
  });
}

// Why `action` cannot be in a file ("" if it can).
std::string actionProblem(const ApplrAction& action) {
  if (!validName(action.name)) return "action name '" + action.name + "' must be [a-z0-9_]+";
  if (!(std::isfinite(action.lo) && std::isfinite(action.hi) && action.lo < action.hi))
    return "action " + action.name + ": its range [" + core::formatDouble(action.lo) + ", " + core::formatDouble(action.hi) +
           "] must be finite with lo < hi";
  return "";
}

std::string actionsText(const std::vector<ApplrAction>& actions) {
  std::string text;
  for (const ApplrAction& a : actions)
    text += (text.empty() ? "" : "; ") + a.name + " " + core::formatDouble(a.lo) + " " + core::formatDouble(a.hi);
  return text;
}

// "name lo hi; ..." back into actions; the problem in `error` ("" if none).
std::vector<ApplrAction> parseActions(const std::string& text, std::string& error) {
  std::vector<ApplrAction> actions;
  std::size_t start = 0;
  while (start <= text.size()) {
    const std::size_t end = std::min(text.find("; ", start), text.size());
    std::istringstream fields(text.substr(start, end - start));
    ApplrAction action;
    std::string lo, hi, extra;
    if (!(fields >> action.name >> lo >> hi) || (fields >> extra) || !core::parseDouble(lo, action.lo) ||
        !core::parseDouble(hi, action.hi)) {
      error = "header: actions '" + text.substr(0, 200) + "': expected 'name lo hi; name lo hi; ...'";
      return {};
    }
    if (const std::string problem = actionProblem(action); !problem.empty()) {
      error = "header: " + problem;
      return {};
    }
    for (const ApplrAction& other : actions)
      if (other.name == action.name) {
        error = "header: action " + action.name + " appears twice";
        return {};
      }
    actions.push_back(action);
    start = end + 2;
  }
  return actions;
}

std::string payloadOf(const MlpParameters<float>& weights) {
  std::string payload;
  payload.reserve(4 * weights.count());
  const_cast<MlpParameters<float>&>(weights).forEachBlock([&](const char*, float* data, Eigen::Index size) {
    header::appendFloats(payload, data, static_cast<std::size_t>(size));
  });
  return payload;
}

void requireOneLine(const std::string& text, const char* field) {
  if (text.find_first_of("\r\n") != std::string::npos)
    throw core::InputError(std::string("APPLR policy: ") + field + " must be one line");
}

}  // namespace

std::string applrPolicyBytes(const ApplrPolicyInfo& info, const MlpParameters<float>& weights) {
  requireOneLine(info.name, "name");
  requireOneLine(info.source, "source");
  for (const ApplrAction& action : info.actions)
    if (const std::string problem = actionProblem(action); !problem.empty()) throw core::InputError("APPLR policy: " + problem);
  const std::string payload = payloadOf(weights);
  ApplrHeader fields;
  fields.architecture = std::to_string(weights.inputs()) + "-" + std::to_string(weights.hidden()) + "-" +
                        std::to_string(weights.hidden()) + "-" + std::to_string(weights.outputs());
  fields.beams = info.beams;
  fields.range_clip = info.range_clip;
  fields.actions = actionsText(info.actions);
  fields.payload_bytes = static_cast<long long>(payload.size());
  fields.weights_fnv1a64.value = core::fnv1a64(payload);
  fields.name = info.name;
  fields.source = info.source;
  header::HeaderWriter writer;
  fields.visit(writer);
  return writer.text() + payload;
}

void writeApplrPolicyFile(const std::filesystem::path& path, const ApplrPolicyInfo& info, const MlpParameters<float>& weights) {
  core::writeFileAtomic(path, applrPolicyBytes(info, weights));
}

void encodeApplrInput(const std::vector<double>& ranges, double goal_angle, double range_clip, float* x) {
  for (std::size_t i = 0; i < ranges.size(); ++i) {
    const double r = std::isnan(ranges[i]) ? range_clip : std::min(ranges[i], range_clip);
    x[i] = static_cast<float>((r - range_clip / 2.0) / range_clip);
  }
  x[ranges.size()] = static_cast<float>(goal_angle / (2.0 * std::numbers::pi));
}

double scaleApplrAction(float u, const ApplrAction& action) {
  const float lo = static_cast<float>(action.lo), hi = static_cast<float>(action.hi);
  const float scale = (hi - lo) / 2.0f, bias = (hi + lo) / 2.0f;
  const float scaled = u * scale;  // two roundings, as numpy's in-place *= then +=
  const float a = scaled + bias;
  return std::clamp(static_cast<double>(a), action.lo, action.hi);
}

ApplrPolicy::ApplrPolicy(ApplrPolicyInfo info, MlpParameters<float> weights) : info_(std::move(info)), weights_(std::move(weights)) {
  const auto fail = [&](const std::string& message) { throw core::InputError("APPLR policy '" + info_.name + "': " + message); };
  if (info_.actions.empty()) fail("no actions");
  for (const ApplrAction& action : info_.actions)
    if (const std::string problem = actionProblem(action); !problem.empty()) fail(problem);
  if (weights_.inputs() != info_.beams + 1 || weights_.outputs() != static_cast<int>(info_.actions.size()) ||
      weights_.w2.rows() != weights_.hidden() || weights_.w2.cols() != weights_.hidden() || weights_.w3.cols() != weights_.hidden() ||
      weights_.b1.size() != weights_.hidden() || weights_.b2.size() != weights_.hidden() || weights_.b3.size() != weights_.outputs())
    fail("weights of shape " + std::to_string(weights_.inputs()) + "-" + std::to_string(weights_.hidden()) + "-" +
         std::to_string(weights_.outputs()) + " do not match beams + 1 = " + std::to_string(info_.beams + 1) + " inputs and " +
         std::to_string(info_.actions.size()) + " actions");
  if (!(info_.range_clip > 0.0) || !std::isfinite(info_.range_clip)) fail("range_clip must be > 0");
}

// Read as Policy::load reads (core::readTextFile: regular files only, at their own size).
ApplrPolicy ApplrPolicy::load(const std::filesystem::path& path) { return parse(core::readTextFile(path), path.string()); }

ApplrPolicy ApplrPolicy::parse(const std::string& file, const std::string& source_name) {
  const std::string where = source_name + ": ";
  const auto fail = [&](const std::string& message) { throw core::InputError(where + message); };

  ApplrHeader fields;
  header::HeaderLines lines = header::readHeader(file, kFormat, "an APPLR policy file", headerKeys(), where, fields);

  ApplrPolicyInfo info;
  info.beams = fields.beams;
  info.range_clip = fields.range_clip;
  if (!(info.range_clip > 0.0)) fail("header: range_clip must be > 0");
  std::string error;
  info.actions = parseActions(fields.actions, error);
  if (!error.empty()) fail(error);
  info.name = fields.name;
  info.source = fields.source;

  // Architecture "inputs-hidden-hidden-outputs" against the input layout and the actions.
  const std::array<int, 4> sizes = header::parseArchitecture(fields.architecture, "721-512-512-7", where);
  if (sizes[0] != info.beams + 1)
    fail("wrong shape: architecture " + fields.architecture + " has " + std::to_string(sizes[0]) +
         " inputs, the input layout needs beams + 1 = " + std::to_string(info.beams + 1));
  if (sizes[1] != sizes[2] || sizes[1] > kMaxHidden)
    fail("wrong shape: architecture " + fields.architecture + ": both hidden layers must have the same size (<= " +
         std::to_string(kMaxHidden) + ")");
  if (sizes[3] != static_cast<int>(info.actions.size()))
    fail("wrong shape: architecture " + fields.architecture + " has " + std::to_string(sizes[3]) + " outputs, the header names " +
         std::to_string(info.actions.size()) + " actions");

  // The payload size follows from the architecture (bounded, so this cannot overflow); check it
  // against the header and the file before allocating.
  const auto inputs = static_cast<std::size_t>(sizes[0]);
  const auto hidden = static_cast<std::size_t>(sizes[1]);
  const auto outputs = static_cast<std::size_t>(sizes[3]);
  const std::size_t expected = 4 * (hidden * inputs + hidden + hidden * hidden + hidden + outputs * hidden + outputs);
  if (static_cast<std::size_t>(fields.payload_bytes) != expected)
    fail("wrong shape: payload_bytes " + lines.values["payload_bytes"] + " does not match architecture " +
         fields.architecture + " (" + std::to_string(expected) + " bytes)");
  const std::size_t available = file.size() - lines.payload_offset;
  if (available < expected)
    fail("truncated: expected " + std::to_string(expected) + " bytes of weights, found " + std::to_string(available));
  if (available > expected)
    fail(std::to_string(available - expected) + " bytes after the weights (expected exactly " + std::to_string(expected) + ")");
  MlpParameters<float> weights = MlpParameters<float>::zeros(sizes[0], sizes[1], sizes[3]);
  const std::string_view payload(file.data() + lines.payload_offset, expected);
  const char* in = payload.data();
  std::string bad_block;
  weights.forEachBlock([&](const char* name, float* data, Eigen::Index size) {
    if (!header::readFloats(in, data, static_cast<std::size_t>(size)) && bad_block.empty()) bad_block = name;
    in += 4 * size;
  });
  if (!bad_block.empty()) fail("weights: block " + bad_block + " holds a non-finite value");
  const std::uint64_t digest = core::fnv1a64(payload);
  if (digest != fields.weights_fnv1a64.value)
    fail("weights: their FNV-1a 64 digest is " + core::formatHex(digest) + ", the header says " +
         core::formatHex(fields.weights_fnv1a64.value) + " (the weights were altered)");
  return ApplrPolicy(std::move(info), std::move(weights));
}

Eigen::VectorXf ApplrPolicy::forward(const Eigen::VectorXf& x) const {
  Eigen::VectorXf h1 = weights_.w1 * x;
  h1 += weights_.b1;
  h1 = h1.cwiseMax(0.0f);
  Eigen::VectorXf h2 = weights_.w2 * h1;
  h2 += weights_.b2;
  h2 = h2.cwiseMax(0.0f);
  Eigen::VectorXf y = weights_.w3 * h2;
  y += weights_.b3;
  for (Eigen::Index i = 0; i < y.size(); ++i) y[i] = std::tanh(y[i]);
  return y;
}

std::vector<double> ApplrPolicy::act(const core::LaserScan& scan, double goal_angle) const {
  if (scan.ranges.size() != static_cast<std::size_t>(info_.beams))
    throw core::InputError("APPLR policy '" + info_.name + "' expects " + std::to_string(info_.beams) + " beams, the scan has " +
                           std::to_string(scan.ranges.size()));
  Eigen::VectorXf x(info_.beams + 1);
  encodeApplrInput(scan.ranges, goal_angle, info_.range_clip, x.data());
  const Eigen::VectorXf u = forward(x);
  std::vector<double> parameters(info_.actions.size());
  for (std::size_t i = 0; i < parameters.size(); ++i)
    parameters[i] = scaleApplrAction(u[static_cast<Eigen::Index>(i)], info_.actions[i]);
  return parameters;
}

}  // namespace barn::learning
