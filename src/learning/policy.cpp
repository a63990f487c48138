#include "barn/learning/policy.hpp"

#include <algorithm>
#include <cmath>
#include <limits>
#include <map>
#include <vector>

#include "barn/core/errors.hpp"
#include "barn/core/text_io.hpp"
#include "policy_header.hpp"

namespace barn::learning {

namespace {

constexpr const char* kFormat = "barnbench-lflh-policy";
constexpr int kVersion = 3;  // written; versions 1 to 3 are read
// Fixed descriptions: part of the contract, so a file written for another input or output
// convention fails to load instead of driving the robot backwards.
constexpr const char* kRelu = "relu";              // version 1: the only activation
constexpr const char* kLeakyRelu = "leaky_relu";   // version 2: "leaky_relu <slope>"
constexpr const char* kUnknown = "unknown";        // a plant not known (versions 1 and 2)
constexpr const char* kInput = "ranges[beams] clipped to [0, range_clip] (+inf -> range_clip), goal_x, goal_y";
constexpr const char* kGoal = "unit vector to the local goal in the robot frame, x forward, y left";
constexpr const char* kOutput = "v [m/s], w [rad/s]";
constexpr const char* kLayout = "float32 little-endian; w1 b1 w2 b2 w3 b3; matrices column-major";

std::string activationText(const PolicyInfo& info) {
  if (info.activation == Activation::Relu) return kRelu;
  return std::string(kLeakyRelu) + " " + core::formatDouble(info.slope);
}

using header::FixedText;
using header::FormatVersion;
using header::HexNumber;
using header::IntRange;
using header::Loss;
using header::PlantHash;

// The header's values as written, every key required, listed once here; Policy::parse checks
// the ones that depend on each other.
struct PolicyHeader {
  std::string format = kFormat;
  FormatVersion version{kVersion, kVersion};
  std::string architecture;  // inputs-hidden-hidden-outputs
  std::string activation;    // relu | leaky_relu <slope>
  int beams = 0;
  double range_clip = 0.0;
  long long payload_bytes = 0;
  std::string name;
  HexNumber config_hash;
  PlantHash plant_hash;
  std::string trained;
  std::uint64_t seed = 0;
  int epochs = 0;
  Loss train_loss, validation_loss, mean_predictor_loss;

  template <class V> void visit(V& v) {
    const long long max = std::numeric_limits<long long>::max();
    v("format", format); v("version", version); v("architecture", architecture); v("activation", activation);
    v("input", FixedText{kInput}); v("beams", beams, IntRange{1, 100000}); v("range_clip", range_clip);
    v("goal", FixedText{kGoal}); v("output", FixedText{kOutput}); v("layout", FixedText{kLayout});
    v("payload_bytes", payload_bytes, IntRange{0, max}); v("name", name); v("config_hash", config_hash);
    v("plant_hash", plant_hash);
    v("trained", trained); v("seed", seed, IntRange{0, max}); v("epochs", epochs, IntRange{0, 100000000});
    v("train_loss", train_loss); v("validation_loss", validation_loss); v("mean_predictor_loss", mean_predictor_loss);
  }
};

const std::vector<std::string>& headerKeys() {
  static const std::vector<std::string> keys = header::keysOf<PolicyHeader>();
  return keys;
}

}  // namespace

void writePolicyFile(const std::filesystem::path& path, const PolicyInfo& info, const MlpParameters<float>& weights) {
  const std::size_t payload = 4 * weights.count();
  PolicyHeader fields;
  fields.architecture = std::to_string(weights.inputs()) + "-" + std::to_string(weights.hidden()) + "-" +
                        std::to_string(weights.hidden()) + "-" + std::to_string(weights.outputs());
  fields.activation = activationText(info);
  fields.beams = info.beams;
  fields.range_clip = info.range_clip;
  fields.payload_bytes = static_cast<long long>(payload);
  fields.name = info.name;
  fields.config_hash.value = info.config_hash;
  fields.plant_hash.value = info.plant_hash;
  fields.trained = info.trained;
  fields.seed = info.seed;
  fields.epochs = info.epochs;
  fields.train_loss.value = info.train_loss;
  fields.validation_loss.value = info.validation_loss;
  fields.mean_predictor_loss.value = info.mean_predictor_loss;
  header::HeaderWriter writer;
  fields.visit(writer);
  std::string text = writer.text();
  text.reserve(text.size() + payload);
  const_cast<MlpParameters<float>&>(weights).forEachBlock([&](const char*, float* data, Eigen::Index size) {
    header::appendFloats(text, data, static_cast<std::size_t>(size));
  });
  core::writeFileAtomic(path, text);
}

Policy::Policy(PolicyInfo info, MlpParameters<float> weights) : info_(std::move(info)), weights_(std::move(weights)) {
  if (weights_.inputs() != info_.beams + 2 || weights_.outputs() != 2 || weights_.hidden() != info_.hidden)
    throw core::InputError("policy '" + info_.name + "': weights of shape " + std::to_string(weights_.inputs()) + "-" +
                           std::to_string(weights_.hidden()) + "-" + std::to_string(weights_.outputs()) +
                           " do not match beams + 2 inputs, hidden " + std::to_string(info_.hidden) + ", 2 outputs");
  beam_column_sum_ = weights_.w1.leftCols(info_.beams).rowwise().sum();
}

Policy Policy::load(const std::filesystem::path& path) {
  // readTextFile refuses folders, devices and fifos (a policy: /dev/zero would never end), and
  // a regular file is read at its own size, so a header cannot make this allocate more.
  return parse(core::readTextFile(path), path.string());
}

Policy Policy::parse(const std::string& file, const std::string& source_name) {
  const std::string where = source_name + ": ";
  const auto fail = [&](const std::string& message) { throw core::InputError(where + message); };

  // Header: "key: value" lines up to end_header.
  header::HeaderLines lines = header::splitHeader(file, kFormat, "an LfLH policy file", where);
  std::map<std::string, std::string>& header = lines.values;
  // Versions 1 and 2 predate plant_hash: their plant is unknown.
  const auto version = header.find("version");
  if (version != header.end() && (version->second == "1" || version->second == "2") && !header.count("plant_hash"))
    header["plant_hash"] = kUnknown;
  header::checkKeys(lines, headerKeys(), where);
  PolicyHeader fields;
  header::HeaderReader reader(header, where);
  fields.visit(reader);

  PolicyInfo info;
  if (fields.version.value == 1) {
    if (fields.activation != kRelu) fail("header: activation is '" + fields.activation + "', expected '" + kRelu + "'");
  } else {
    const std::string& text = fields.activation;
    const std::string leaky = std::string(kLeakyRelu) + " ";
    if (text == kRelu) {
      info.activation = Activation::Relu;
    } else if (text.rfind(leaky, 0) == 0 && core::parseDouble(text.substr(leaky.size()), info.slope) &&
               info.slope > 0.0 && info.slope < 1.0) {
      info.activation = Activation::LeakyRelu;
    } else {
      fail("header: activation '" + text + "': expected 'relu' or 'leaky_relu S' with the slope S in (0, 1)");
    }
  }
  info.beams = fields.beams;
  info.range_clip = fields.range_clip;
  if (!(info.range_clip > 0.0)) fail("header: range_clip must be > 0");
  info.name = fields.name;
  info.config_hash = fields.config_hash.value;
  info.plant_hash = fields.plant_hash.value;
  info.trained = fields.trained;
  info.seed = fields.seed;
  info.epochs = fields.epochs;
  info.train_loss = fields.train_loss.value;
  info.validation_loss = fields.validation_loss.value;
  info.mean_predictor_loss = fields.mean_predictor_loss.value;

  // Architecture "inputs-hidden-hidden-outputs" against the input layout.
  const std::array<int, 4> sizes = header::parseArchitecture(fields.architecture, "722-256-256-2", where);
  if (sizes[0] != info.beams + 2)
    fail("wrong shape: architecture " + fields.architecture + " has " + std::to_string(sizes[0]) +
         " inputs, the input layout needs beams + 2 = " + std::to_string(info.beams + 2));
  if (sizes[1] != sizes[2] || sizes[1] > 4096)
    fail("wrong shape: architecture " + fields.architecture + ": both hidden layers must have the same size (<= 4096)");
  if (sizes[3] != 2) fail("wrong shape: architecture " + fields.architecture + " has " + std::to_string(sizes[3]) + " outputs, expected 2 (v, w)");
  info.hidden = sizes[1];

  // The payload size follows from the architecture; check it against the header and the file
  // before allocating, so a short file claiming a huge network (100002-4096-4096-2 is 1.7 GB)
  // is refused without the allocation. The sizes are bounded above, so this cannot overflow.
  const auto inputs = static_cast<std::size_t>(sizes[0]);
  const auto hidden = static_cast<std::size_t>(sizes[1]);
  const auto outputs = static_cast<std::size_t>(sizes[3]);
  const std::size_t expected = 4 * (hidden * inputs + hidden + hidden * hidden + hidden + outputs * hidden + outputs);
  if (static_cast<std::size_t>(fields.payload_bytes) != expected)
    fail("wrong shape: payload_bytes " + header["payload_bytes"] + " does not match architecture " +
         fields.architecture + " (" + std::to_string(expected) + " bytes)");
  const std::size_t available = file.size() - lines.payload_offset;
  if (available < expected)
    fail("truncated: expected " + std::to_string(expected) + " bytes of weights, found " + std::to_string(available));
  if (available > expected)
    fail(std::to_string(available - expected) + " bytes after the weights (expected exactly " + std::to_string(expected) + ")");
  MlpParameters<float> weights = MlpParameters<float>::zeros(sizes[0], sizes[1], sizes[3]);
  const char* in = file.data() + lines.payload_offset;
  std::string bad_block;
  weights.forEachBlock([&](const char* name, float* data, Eigen::Index size) {
    if (!header::readFloats(in, data, static_cast<std::size_t>(size)) && bad_block.empty()) bad_block = name;
    in += 4 * size;
  });
  if (!bad_block.empty()) fail("weights: block " + bad_block + " holds a non-finite value");
  return Policy(std::move(info), std::move(weights));
}

core::Twist Policy::act(const core::LaserScan& scan, const Eigen::Vector2d& goal_direction_robot_frame,
                        double range_clip) const {
  const int beams = info_.beams;
  if (scan.ranges.size() != static_cast<std::size_t>(beams))
    throw core::InputError("policy '" + info_.name + "' expects " + std::to_string(beams) + " beams, the scan has " +
                           std::to_string(scan.ranges.size()));
  Eigen::VectorXf x(beams + 2);
  const double clip = range_clip > 0.0 ? range_clip : info_.range_clip;
  encodeInput(scan.ranges, goal_direction_robot_frame, clip, x.data());
  const bool relu = info_.activation == Activation::Relu;
  const float slope = static_cast<float>(info_.slope);
  const auto activate = [&](Eigen::VectorXf& h) {
    if (relu) h = h.cwiseMax(0.0f);
    else h = (h.array() > 0.0f).select(h, slope * h);
  };
  // Most beams of a scan read the clip (nothing that near): the first layer, most of the
  // network's memory traffic, reads only the columns of the beams that do not.
  const float c = static_cast<float>(clip);
  Eigen::VectorXf h1 = weights_.b1 + c * beam_column_sum_;
  for (int i = 0; i < beams; ++i)
    if (x[i] != c) h1 += weights_.w1.col(i) * (x[i] - c);
  h1 += weights_.w1.col(beams) * x[beams] + weights_.w1.col(beams + 1) * x[beams + 1];
  activate(h1);
  Eigen::VectorXf h2 = weights_.w2 * h1;
  h2 += weights_.b2;
  activate(h2);
  Eigen::Vector2f y = weights_.w3 * h2;
  y += weights_.b3;
  return {static_cast<double>(y[0]), static_cast<double>(y[1])};
}

void clipRanges(const std::vector<double>& ranges, double range_clip, float* out) {
  for (std::size_t i = 0; i < ranges.size(); ++i) {
    const double r = ranges[i];
    // +inf (no return) and NaN read as "free up to the clip"; noise cannot make a range negative.
    out[i] = static_cast<float>(std::isnan(r) ? range_clip : std::clamp(r, 0.0, range_clip));
  }
}

void encodeInput(const std::vector<double>& ranges, const Eigen::Vector2d& goal, double range_clip, float* column) {
  clipRanges(ranges, range_clip, column);
  const double norm = goal.norm();
  const Eigen::Vector2d unit = norm > 0.0 ? Eigen::Vector2d(goal / norm) : Eigen::Vector2d::UnitX();
  column[ranges.size()] = static_cast<float>(unit.x());
  column[ranges.size() + 1] = static_cast<float>(unit.y());
}

void checkPolicyLidar(const Policy& policy, const core::LidarConfig& lidar) {
  if (policy.info().beams != lidar.beams)
    throw core::InputError("policy '" + policy.info().name + "' reads " + std::to_string(policy.info().beams) +
                           " beams but the LiDAR gives " + std::to_string(lidar.beams) +
                           " (lidar.beams in the sim config); train or choose a policy for this LiDAR");
}

}  // namespace barn::learning
