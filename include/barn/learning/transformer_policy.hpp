#pragma once
/// A transformer policy file (the LiCS-KI network, learning::Transformer) and its use on a scan.
///
/// File (`barnbench-transformer-policy`, documented in docs/systems/lics.md): the same framing
/// as the LfLH policy file (learning::Policy): a text header of `key: value` lines ending with
/// the line `end_header`, then the weights as little-endian float32, each tensor column-major
/// in TransformerWeights::forEachTensor's order:
///
///     format: barnbench-transformer-policy
///     version: 1
///     beams: 720
///     patches: 36
///     ...
///     weights_fnv1a64: 0x...
///     end_header
///     <payload_bytes bytes of float32>
///
/// It is a sibling of the LfLH format rather than a version of it: the LfLH header's keys
/// describe an MLP (its architecture string, its activation, its block list) and its training
/// here (config and plant hashes, losses), and its output is (v, w) in m/s and rad/s; this
/// network has other hyper-parameters, is only ever imported, and outputs (v_hat, w_hat) for
/// the controller to scale. Both share the header reader (every key required and known, fixed
/// texts for the conventions, payload size checked before allocating, weights finite).
///
/// Loading checks the magic, the version, every key, the hyper-parameters, the payload size
/// against them, the file length, that every weight is finite and the weights' FNV-1a 64
/// digest, and throws an InputError naming the file and what mismatched (the tensor, where one
/// is at fault).

#include <cstdint>
#include <filesystem>
#include <string>

#include <Eigen/Core>

#include "barn/core/types.hpp"
#include "barn/learning/transformer.hpp"

namespace barn::learning {

/// What the header says besides the weights.
struct TransformerPolicyInfo {
  TransformerShape shape;      // hyper-parameters
  double range_clip = 5.0;     // [m] ranges clipped to [0, range_clip], +inf and NaN -> range_clip (LiCS: laser_clip 5.0)
  std::string name;            // e.g. lics_transformer_99
  std::string source;          // where the weights came from (free text, one line)
};

/// The file's bytes: header and payload (what writeTransformerPolicyFile writes).
std::string transformerPolicyBytes(const TransformerPolicyInfo& info, const TransformerWeights& weights);
/// Writes a policy file (atomically), format version 1.
void writeTransformerPolicyFile(const std::filesystem::path& path, const TransformerPolicyInfo& info,
                                const TransformerWeights& weights);

class TransformerPolicy {
 public:
  /// InputError if the weights do not have info.shape (naming the tensor).
  TransformerPolicy(TransformerPolicyInfo info, TransformerWeights weights);

  /// Reads and checks a policy file; InputError naming the file and the mismatch (also for a
  /// folder, a device or a fifo).
  static TransformerPolicy load(const std::filesystem::path& path);
  /// Checks and decodes the bytes of a policy file; `source_name` prefixes every error.
  static TransformerPolicy parse(const std::string& bytes, const std::string& source_name);

  /// (v_hat, w_hat), before the controller's scaling, for one scan and the local goal in the
  /// robot frame (x forward, y left) as given: LiCS feeds the unit vector to the goal, or
  /// (0, 0) before its first plan. Ranges are clipped to [0, range_clip] (+inf and NaN read as
  /// range_clip). InputError if the scan does not have shape.beams ranges.
  Eigen::Vector2d act(const core::LaserScan& scan, const Eigen::Vector2d& goal_robot_frame) const;

  const TransformerPolicyInfo& info() const { return info_; }
  const Transformer& network() const { return network_; }

 private:
  TransformerPolicyInfo info_;
  Transformer network_;
};

}  // namespace barn::learning
