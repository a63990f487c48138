#pragma once
/// The trained LfLH policy: its file format and inference.
///
/// File (`configs/policies/*.policy`, documented in configs/policies/README.md): a text header
/// of `key: value` lines ending with the line `end_header`, then the weights as little-endian
/// float32, blocks w1 b1 w2 b2 w3 b3, each matrix column-major (Eigen's order):
///
///     format: barnbench-lflh-policy
///     version: 3
///     architecture: 722-256-256-2
///     activation: leaky_relu 0.01
///     ...
///     end_header
///     <payload_bytes bytes of float32>
///
/// Version 3 (written now) records the plant the policy was trained on (`plant_hash`, see
/// sim::plantHash; `unknown` for a policy not trained here). Version 2 added the hidden
/// layers' activation: `relu`, or `leaky_relu S` with the negative slope S in (0, 1) (the
/// published LfLH network: `leaky_relu 0.01`). Version 1 files had the fixed text
/// `activation: relu` and load as relu; version 1 and 2 files load with an unknown plant. Any
/// version may give `unknown` for train_loss, validation_loss and mean_predictor_loss (a policy
/// not trained here, e.g. converted by tools/import_lflh_weights.py); they load as NaN.
///
/// Loading checks the magic, the version, every required key, the architecture against the
/// input layout, the payload size and that every weight is finite, and throws an InputError
/// naming the file and what mismatched.

#include <cstdint>
#include <filesystem>
#include <string>
#include <vector>

#include <Eigen/Core>

#include "barn/core/lidar_config.hpp"
#include "barn/core/types.hpp"
#include "barn/learning/mlp.hpp"

namespace barn::learning {

/// What the header says besides the weights.
struct PolicyInfo {
  int beams = 720;                 // [-] ranges in the input
  double range_clip = 2.0;         // [m] ranges clipped to [0, range_clip], +inf -> range_clip
  int hidden = 256;                // [-] units per hidden layer
  Activation activation = Activation::Relu;  // of both hidden layers
  double slope = 0.01;             // [-] leaky_relu's negative slope (unused for relu)
  std::string name;                // config name, e.g. lflh_1ms
  std::uint64_t config_hash = 0;   // core::fnv1a64 of the effective training config
  std::uint64_t plant_hash = 0;    // sim::plantHash of the plant its demonstrations drove (0: unknown)
  std::string trained;             // UTC date and time of training, ISO 8601
  std::uint64_t seed = 0;          // training seed
  int epochs = 0;                  // [-]
  double train_loss = 0.0;         // final epoch, mean over samples of squared v and w error (NaN: unknown)
  double validation_loss = 0.0;    // (NaN: unknown)
  double mean_predictor_loss = 0.0;  // validation loss of always predicting the mean command (NaN: unknown)
};

/// Writes a policy file (atomically), format version 3.
void writePolicyFile(const std::filesystem::path& path, const PolicyInfo& info, const MlpParameters<float>& weights);

class Policy {
 public:
  Policy(PolicyInfo info, MlpParameters<float> weights);

  /// Reads and checks a policy file; InputError naming the file and the mismatch (also for a
  /// folder, a device or a fifo).
  static Policy load(const std::filesystem::path& path);
  /// Checks and decodes the bytes of a policy file; `source_name` prefixes every error.
  static Policy parse(const std::string& bytes, const std::string& source_name);

  /// The command for one scan and the goal direction in the robot frame (x forward, y left;
  /// normalised here, any length > 0). Ranges are clipped exactly as in training; +inf and NaN
  /// read as range_clip. `range_clip` > 0 clips at that distance instead of the file's (the
  /// published deployment clipped at 2.0 m a model trained at 2.5 m). Throws InputError if the
  /// scan does not have info().beams ranges.
  core::Twist act(const core::LaserScan& scan, const Eigen::Vector2d& goal_direction_robot_frame,
                  double range_clip = 0.0) const;

  const PolicyInfo& info() const { return info_; }
  const MlpParameters<float>& weights() const { return weights_; }

 private:
  PolicyInfo info_;
  MlpParameters<float> weights_;
  // The sum of the first layer's beam columns: with every beam at the clip c the layer is
  // b1 + c beam_column_sum_ + the goal's columns, and act() adds only the beams that read less.
  Eigen::VectorXf beam_column_sum_;
};

/// Writes `ranges` clipped to [0, range_clip] in double and then rounded to float into `out`
/// (ranges.size() floats): +inf and NaN read as range_clip (no return: free up to the clip).
void clipRanges(const std::vector<double>& ranges, double range_clip, float* out);

/// Writes the policy's input for one scan and goal direction (normalised here; x forward, y
/// left) into `column` (ranges.size() + 2 floats): the ranges as clipRanges writes them, then
/// the unit goal. Training and acting both use it.
void encodeInput(const std::vector<double>& ranges, const Eigen::Vector2d& goal, double range_clip, float* column);

/// InputError unless `policy` reads scans of `lidar`'s beam count (it would fail every call).
void checkPolicyLidar(const Policy& policy, const core::LidarConfig& lidar);

}  // namespace barn::learning
