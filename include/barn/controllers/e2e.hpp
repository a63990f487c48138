#pragma once
/// `e2e`: BARN's End-to-End baseline (the ros_jackal TD3 `e2e` branch of the-barn-challenge):
/// a TD3 actor maps four stacked frames of (scan, the end of move_base's global plan, the
/// previous action) straight to (v, w), every 0.2 s. barnbench trains its own actor with
/// tools/train_e2e.py on barnbench.VecEnv (docs/rl.md); the published weights are not used.
///
/// Every tick (5 Hz, the env's time_step 0.2 s):
///   1. move_base's stack (GlobalPlanFeed: NavFn on BARN's costmaps, as the env's move_base
///      ran beside it) folds in the scan and replans; its plan's last pose, in the robot frame
///      by the odometry, is the goal input (the goal itself until a plan is found);
///   2. the frame: 720 ranges clipped at range_clip and scaled to [-1, 1] by (r - c/2) / (c/2),
///      the plan end / goal_scale - 1 (x and y), the previous command scaled to [-1, 1] by the
///      action range ((a - bias) / scale; (0, 0) before the first command);
///   3. the last `frames` frames, oldest first (at the start the first frame repeated), into
///      the actor (an MLP policy file, learning::MlpPolicy): tanh outputs mapped to
///      v in [min_v, max_v], w in [min_w, max_w]; that is the command, unclipped otherwise.
///
/// Sources (MIT): Daffan/the-barn-challenge@e1faeb9 (branch e2e) end_to_end/data/config.yaml,
/// envs/jackal_gazebo_envs.py, envs/motion_control_envs.py, envs/move_base.py, envs/wrappers.py,
/// td3/rl.py, td3/net.py; docs/rl.md restates them.

#include <deque>
#include <memory>
#include <string>
#include <vector>

#include "barn/controllers/controller.hpp"
#include "barn/controllers/global_plan_feed.hpp"
#include "barn/core/config.hpp"
#include "barn/core/errors.hpp"
#include "barn/learning/mlp_policy.hpp"
#include "barn/nav/nav_stack.hpp"

namespace barn::controllers {

/// The observation encoding (the env's, motion_control_envs.py and jackal_gazebo_envs.py).
struct E2eEncoding {
  int frames = 4;
  double range_clip = 5.0;
  double goal_scale = 5.0;
  double min_v = -1.0;
  double max_v = 2.0;
  double min_w = -3.14;
  double max_w = 3.14;
  template <class V> void visit(V& v) {
    v("frames", frames, {.range = core::closed(1, 64), .doc = "the env's stack_frame 4"});
    v("range_clip", range_clip, {.unit = "m", .doc = "the env's laser_clip 5"});
    v("goal_scale", goal_scale, {.unit = "m", .doc = "goal input = plan end / 5 - 1 (the env's \"roughly (-1, 1)\")"});
    v("min_v", min_v, {.unit = "m/s", .doc = "the env's min_v"});
    v("max_v", max_v, {.unit = "m/s", .doc = "the env's max_v"});
    v("min_w", min_w, {.unit = "rad/s", .doc = "the env's min_w"});
    v("max_w", max_w, {.unit = "rad/s", .doc = "the env's max_w"});
  }
};
void validate(const E2eEncoding& encoding, core::Errors& errors, const std::string& prefix);

/// The `input` text of a policy trained on `encoding` (the policy file records it; e2e refuses
/// a policy whose text differs), e.g. "e2e frames=4 range_clip=5 goal_scale=5 v=-1,2 w=-3.14,3.14".
std::string e2eInputText(const E2eEncoding& encoding);

/// Values per frame for `beams` ranges: the ranges, the goal (2), the previous action (2).
inline int e2eFrameSize(int beams) { return beams + 4; }

/// One frame (e2eFrameSize(beams) floats into `out`): `ranges` (beams of them; +inf and NaN
/// read as range_clip) clipped and scaled, the plan end in the robot frame (x forward, y
/// left) scaled, and the previous command scaled. Computed in double, stored as float.
template <class Range>
void encodeE2eFrame(const Range* ranges, int beams, const Eigen::Vector2d& plan_end_robot, const core::Twist& previous,
                    const E2eEncoding& encoding, float* out);

struct E2eConfig {
  std::string policy = "configs/policies/e2e.policy";
  double rate = 5.0;
  E2eEncoding encoding;
  nav::NavStackConfig nav = nav::NavStackConfig::moveBaseWithNavFn();
  template <class V> void visit(V& v) {
    v("policy", policy, {.doc = "relative to the config file's folder"});
    v("rate", rate, {.unit = "Hz", .doc = "the env's time_step 0.2 s"});
    v("encoding", encoding, {.doc = "the env's observation and action space (above)"});
    v("nav", nav, {.doc = "the env's move_base: BARN's DWA-baseline stack with NavFn"});
  }
};
void validate(const E2eConfig& config, core::Errors& errors, const std::string& prefix);

/// InputError naming `source` unless `policy` is an actor for `encoding` with `beams` ranges:
/// its input text, its input size frames x (beams + 4), two tanh outputs onto the action range.
void checkE2ePolicy(const learning::MlpPolicy& policy, const E2eEncoding& encoding, int beams, const std::string& source);

class E2eController : public Controller {
 public:
  E2eController(const E2eConfig& config, std::shared_ptr<const learning::MlpPolicy> policy);
  void reset(const EpisodeInfo& info) override;
  core::Twist act(const Observation& observation) override;
  double period() const override { return 1.0 / config_.rate; }
  void checkLidar(const core::LidarConfig& lidar) const override;
  std::uint64_t trainedPlant() const override { return policy_->info().plant_hash; }

 private:
  E2eConfig config_;
  std::shared_ptr<const learning::MlpPolicy> policy_;
  GlobalPlanFeed feed_;
  std::deque<std::vector<float>> frames_;  // oldest first
  std::vector<float> input_;
  core::Twist previous_;
};

}  // namespace barn::controllers
