#pragma once
/// The APPLR actor (Xu et al. 2021, the BARN 2023 APPLR-DWA baseline): a TD3 actor that maps one
/// scan and the direction of a local goal to the parameters of a DWA, and its file format.
///
/// The network is learning::MlpParameters with relu hidden layers and a tanh head:
///
///     h1 = relu(W1 x + b1),  h2 = relu(W2 h1 + b2),  u = tanh(W3 h2 + b3)
///     a_i = bias_i + scale_i u_i  (float32),  scale_i = (hi_i - lo_i) / 2,  bias_i = (hi_i + lo_i) / 2
///     parameter_i = a_i clipped to [lo_i, hi_i]
///
/// x holds `beams` ranges, each clipped at range_clip and scaled to (r - range_clip / 2) /
/// range_clip (so [-0.5, 0.5] for ranges in [0, range_clip]), then the angle of the local goal
/// in the robot frame divided by 2 pi. The published actor: 721-512-512-7, range_clip 2 m, the
/// seven DWA parameters and ranges of docs/systems/applr_dwa.md.
///
/// File (`barnbench-applr-policy`, documented in docs/systems/applr_dwa.md): the framing of the
/// LfLH policy file (learning::Policy): a text header of `key: value` lines ending with the line
/// `end_header`, then the weights as little-endian float32, blocks w1 b1 w2 b2 w3 b3, each
/// matrix column-major:
///
///     format: barnbench-applr-policy
///     version: 1
///     architecture: 721-512-512-7
///     ...
///     actions: max_vel_x 0.2 2; max_vel_theta 0.314 3.14; ...
///     weights_fnv1a64: 0x...
///     end_header
///
/// A sibling of the LfLH format rather than a version of it: the LfLH header describes a
/// network trained here with a (v, w) output and a unit-goal input; this one is only ever
/// imported, reads a goal angle and outputs named parameters in ranges that are part of the
/// network (the actor was trained to them). Both share the header reader: every key required
/// and known, fixed texts for the conventions, the payload size checked before allocating,
/// every weight finite, and here the weights' FNV-1a 64 digest.

#include <cstdint>
#include <filesystem>
#include <string>
#include <vector>

#include <Eigen/Core>

#include "barn/core/types.hpp"
#include "barn/learning/mlp.hpp"

namespace barn::learning {

/// One output of the actor: the parameter it sets and the range its tanh is scaled into.
struct ApplrAction {
  std::string name;  // e.g. max_vel_x ([a-z0-9_]+)
  double lo = 0.0;   // the parameter's value at tanh = -1
  double hi = 0.0;   // ... at tanh = +1 (> lo)
};

/// What the header says besides the weights.
struct ApplrPolicyInfo {
  int beams = 720;                   // [-] ranges in the input
  double range_clip = 2.0;           // [m] ranges clipped at this (APPLR: laser_clip 2)
  std::vector<ApplrAction> actions;  // one per output, in output order
  std::string name;                  // e.g. applr_dwa
  std::string source;                // where the weights came from (free text, one line)
};

/// The file's bytes: header and payload (what writeApplrPolicyFile writes). InputError for a
/// name or source that is not one line, or an action that the format cannot hold.
std::string applrPolicyBytes(const ApplrPolicyInfo& info, const MlpParameters<float>& weights);
/// Writes a policy file (atomically), format version 1.
void writeApplrPolicyFile(const std::filesystem::path& path, const ApplrPolicyInfo& info,
                          const MlpParameters<float>& weights);

/// The actor's input for one scan (`ranges.size()` beams) and local-goal angle [rad] into `x`
/// (ranges.size() + 1 floats): each range clipped at range_clip (+inf and NaN read as the clip,
/// as no return is free space up to it), then (r - range_clip / 2) / range_clip; then
/// goal_angle / (2 pi). Computed in double, then rounded to float (the original feeds a float64
/// array to torch.FloatTensor).
void encodeApplrInput(const std::vector<double>& ranges, double goal_angle, double range_clip, float* x);

/// One tanh output u in [-1, 1] as the parameter `action` sets: bias + scale u in float32 (scale
/// and bias computed in float32 from the range rounded to float32, as the original's float32
/// action space and torch tensors do), then clipped to [lo, hi] in double (np.clip against the
/// range's Python floats).
double scaleApplrAction(float u, const ApplrAction& action);

class ApplrPolicy {
 public:
  /// InputError unless the weights have beams + 1 inputs, one output per action, and the
  /// actions have names and lo < hi.
  ApplrPolicy(ApplrPolicyInfo info, MlpParameters<float> weights);

  /// Reads and checks a policy file; InputError naming the file and the mismatch (also for a
  /// folder, a device or a fifo).
  static ApplrPolicy load(const std::filesystem::path& path);
  /// Checks and decodes the bytes of a policy file; `source_name` prefixes every error.
  static ApplrPolicy parse(const std::string& bytes, const std::string& source_name);

  /// The parameters for one scan and local-goal angle [rad] (robot frame, counter-clockwise
  /// from ahead), in info().actions order, each in its range. InputError if the scan does not
  /// have info().beams ranges.
  std::vector<double> act(const core::LaserScan& scan, double goal_angle) const;
  /// The tanh outputs u for an encoded input (beams + 1 floats), before the scaling.
  Eigen::VectorXf forward(const Eigen::VectorXf& x) const;

  const ApplrPolicyInfo& info() const { return info_; }
  const MlpParameters<float>& weights() const { return weights_; }

 private:
  ApplrPolicyInfo info_;
  MlpParameters<float> weights_;
};

}  // namespace barn::learning
