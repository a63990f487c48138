#pragma once
/// `applr_dwa`: APPLR-DWA (Xu et al. 2021, the BARN 2023 baseline): barnbench's `dwa` (BARN's
/// move_base DWA, dwa.hpp) whose parameters a learned TD3 actor (learning::ApplrPolicy) sets
/// every `period` (1 s) of simulated time, as the published APPLR runs it
/// (Daffan/the-barn-challenge@8f90246, branch applr: applr/scripts/test_param_policy.py,
/// applr/envs/real_robot.py, applr/envs/move_base.py).
///
/// At the first control tick of an episode and every `period` after it, after the DWA's own
/// cycle:
///   1. the observation: the scan's ranges clipped at the actor's range_clip (2 m) and scaled
///      to [-0.5, 0.5], and the angle of APPLR's local goal in the robot frame / (2 pi);
///      the local goal is the first point farther than `los` (1 m) from the robot of the
///      latest global plan smoothed by a Savitzky-Golay filter (window 19, cubic, on x and y
///      apart; a plan of fewer points is used raw), else the plan's last point; angle 0
///      without a plan;
///   2. the actor's seven outputs, each tanh scaled into its published range and clipped to it;
///   3. set on the DWA (DwaController::setParameter): max_vel_x, max_vel_theta, vx_samples and
///      vtheta_samples (truncated to whole numbers, as dynamic_reconfigure's int() does),
///      path_distance_bias and goal_distance_bias (pdist_scale and gdist_scale), and
///      inflation_radius on both costmaps (at each map's next update).
/// They are in force from the next control tick on (the original's reconfigure reaches
/// move_base after its observation). Between updates the DWA runs as `dwa` does; reset()
/// restores its configured parameters. parameterChanges() reports what a tick set, as
/// `key=value;...` with the DWA's keys.

#include <filesystem>
#include <memory>
#include <string>
#include <string_view>
#include <vector>

#include "barn/controllers/controller.hpp"
#include "barn/controllers/dwa.hpp"
#include "barn/core/config.hpp"
#include "barn/core/errors.hpp"
#include "barn/learning/applr_policy.hpp"
#include "barn/nav/path_tools.hpp"

namespace barn::controllers {

struct ApplrDwaConfig {
  std::string policy = "configs/policies/applr_dwa.policy";
  double period = 1.0;
  double los = 1.0;
  int smoothing_window = 19;
  int smoothing_order = 3;
  DwaConfig dwa;

  template <class V> void visit(V& v) {
    v("policy", policy, {.doc = "relative to the config file's folder"});
    v("period", period,
      {.unit = "s", .range = core::kPositive, .doc = "APPLR time_step: new parameters every 1 s of simulated time"});
    v("los", los,
      {.unit = "m", .range = core::kNonNegative, .doc = "APPLR Robot_config.los: the local goal is the first plan point farther than this"});
    v("smoothing_window", smoothing_window,
      {.unit = "points", .doc = "APPLR get_global_path: savgol_filter(x, 19, 3) on x and y; 0: no smoothing"});
    v("smoothing_order", smoothing_order, {.doc = "... its polynomial order"});
    v("dwa", dwa,
      {.doc = "the DWA it tunes, BARN's (dwa.yaml); its values are the parameters before the first update"});
  }
};
void validate(const ApplrDwaConfig& config, core::Errors& errors, const std::string& prefix);

/// scipy.signal.savgol_filter(values, window, order) in its default mode 'interp': each value
/// away from the ends is the least-squares polynomial of degree `order` through the `window`
/// values centred on it, evaluated there; the first and last window / 2 values come from the
/// polynomial through the first (last) `window` values. Fewer values than `window` (scipy
/// raises, and APPLR keeps the path as it is), or window < 3, return `values` unchanged.
/// Requires an odd window > order.
std::vector<double> savitzkyGolay(const std::vector<double>& values, int window, int order);

/// The angle [rad] of APPLR's local goal in the frame of the robot at `pose`: the first point
/// of `path` (smoothed as above) farther than `los` from the robot, else its last point;
/// atan2(0, 0) = 0 for an empty path.
double applrGoalAngle(const nav::Path& path, const core::Pose2& pose, double los, int window, int order);

/// The policy file for config `policy` (resolvePolicyPath, lflh.hpp), loaded; an InputError
/// naming the import command if it does not exist (the published actor is not shipped).
std::shared_ptr<const learning::ApplrPolicy> loadApplrPolicy(const std::string& policy, const std::string& config_source);

class ApplrDwaController : public Controller {
 public:
  /// InputError if the policy has an action this controller cannot set (it knows max_vel_x,
  /// max_vel_theta, vx_samples, vtheta_samples, path_distance_bias, goal_distance_bias and
  /// inflation_radius) or one whose range the DWA would refuse.
  ApplrDwaController(const ApplrDwaConfig& config, std::shared_ptr<const learning::ApplrPolicy> policy);
  void reset(const EpisodeInfo& info) override;
  core::Twist act(const Observation& observation) override;
  double period() const override { return dwa_.period(); }
  std::string_view stateLabel() const override { return dwa_.stateLabel(); }
  void checkLidar(const core::LidarConfig& lidar) const override;
  std::string_view parameterChanges() const override { return changes_; }

  const DwaController& dwa() const { return dwa_; }
  /// The actor's last output, as set (sample counts truncated), in the policy's action order;
  /// empty before the first update of an episode.
  const std::vector<double>& lastParameters() const { return last_; }

 private:
  /// One update: observation, actor, parameters onto the DWA.
  void tune(const Observation& observation);

  struct Target {
    std::vector<std::string> keys;  // DwaController::setParameter keys it sets
    bool whole = false;             // truncated to a whole number first
  };

  ApplrDwaConfig config_;
  std::shared_ptr<const learning::ApplrPolicy> policy_;
  std::vector<Target> targets_;  // one per action of the policy
  DwaController dwa_;
  double next_update_ = 0.0;  // [s] simulated time of the next update
  std::vector<double> last_;
  std::string changes_;
};

}  // namespace barn::controllers
