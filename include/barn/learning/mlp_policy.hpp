#pragma once
/// A multi-layer perceptron policy file of any depth (`barnbench-mlp-policy`), e.g. the
/// End-to-End TD3 actor trained by tools/train_e2e.py, and its inference.
///
/// File (documented in configs/policies/README.md): the framing of the other policy files (a
/// text header of `key: value` lines ending with the line `end_header`, then the weights):
///
///     format: barnbench-mlp-policy
///     version: 1
///     architecture: 2896-512-512-512-512-2
///     activation: relu
///     output_activation: tanh
///     output_low: -1,-3.14
///     output_high: 2,3.14
///     input: e2e frames=4 range_clip=5 goal_scale=5 v=-1,2 w=-3.14,3.14
///     ...
///     end_header
///     <payload_bytes bytes of float32 or float16, little-endian>
///
/// The network: h_0 = x; h_k = f(W_k h_(k-1) + b_k) for the hidden layers; y = g(W_L h + b_L),
/// with f the hidden activation (relu) and g the output activation (tanh or linear); with tanh
/// the output is mapped affinely from [-1, 1] to [output_low, output_high] (a = low + (y + 1)
/// (high - low) / 2), as a TD3 actor's action is. The `input` text names the encoding the
/// policy was trained on; its user checks it (a policy for another encoding is refused).
///
/// The LfLH policy file (learning::Policy) is a fixed 2-hidden-layer network with its own input
/// layout and training record; this format is the general one for policies trained outside
/// barnbench's C++ (in PyTorch) and exported.

#include <cstdint>
#include <filesystem>
#include <string>
#include <vector>

#include <Eigen/Core>

namespace barn::learning {

enum class MlpOutput { Linear, Tanh };

struct MlpPolicyInfo {
  std::vector<int> layers;             // [-] sizes: inputs, hidden..., outputs
  MlpOutput output = MlpOutput::Tanh;  // output activation
  std::vector<double> output_low;      // with tanh: the action each output's -1 maps to
  std::vector<double> output_high;     // ... and +1
  std::string input;                   // the input encoding (one line), checked by its user
  std::string output_text;             // what the outputs are (one line), e.g. "v [m/s], w [rad/s]"
  bool half = false;                   // payload stored as float16 (read into float32)
  std::string name;                    // e.g. e2e
  std::uint64_t config_hash = 0;       // FNV-1a 64 of the training config text (0: unknown)
  std::uint64_t plant_hash = 0;        // sim::plantHash of the plant it trained on (0: unknown)
  std::string trained;                 // UTC date and time, ISO 8601
  std::uint64_t seed = 0;              // training seed
  long long steps = 0;                 // [-] environment steps trained on
};

/// One layer's weights: out x in (column-major in memory) and out biases.
struct MlpLayer {
  Eigen::MatrixXf weight;
  Eigen::VectorXf bias;
};

/// The file's bytes (header and payload); float16 payloads are rounded to nearest even.
std::string mlpPolicyBytes(const MlpPolicyInfo& info, const std::vector<MlpLayer>& layers);
void writeMlpPolicyFile(const std::filesystem::path& path, const MlpPolicyInfo& info, const std::vector<MlpLayer>& layers);

class MlpPolicy {
 public:
  /// InputError if the layers do not chain the info's sizes.
  MlpPolicy(MlpPolicyInfo info, std::vector<MlpLayer> layers);

  /// Reads and checks a policy file; InputError naming the file and the mismatch.
  static MlpPolicy load(const std::filesystem::path& path);
  /// Checks and decodes the bytes of a policy file; `source_name` prefixes every error.
  static MlpPolicy parse(const std::string& bytes, const std::string& source_name);

  /// The outputs for one input (inputs() floats), mapped to [output_low, output_high] with tanh.
  Eigen::VectorXd forward(const float* input) const;

  int inputs() const { return info_.layers.front(); }
  int outputs() const { return info_.layers.back(); }
  const MlpPolicyInfo& info() const { return info_; }
  const std::vector<MlpLayer>& layers() const { return layers_; }

 private:
  MlpPolicyInfo info_;
  std::vector<MlpLayer> layers_;
};

/// IEEE 754 binary16 <-> binary32 (round to nearest even; exact widening).
float halfToFloat(std::uint16_t h);
std::uint16_t floatToHalf(float f);

}  // namespace barn::learning
