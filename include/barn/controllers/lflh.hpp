#pragma once
/// `lflh`: the LfLH baseline. A learned policy (learning::Policy, trained by `barn lflh train`)
/// maps the clipped scan and the unit vector to a local goal 1.5 m along the global path
/// (nav::NavStack, NavFn-like) to (v, w) at 25 Hz.
///
/// deployed: true (configs/controllers/lflh.yaml, lflh_2ms.yaml) — what BARN's LfLH baseline
/// ran, the published deployment script (LfD_2D/run_policy.py), every tick:
///
///   heading error e = the angle of the local goal in the robot frame (the policy's goal input)
///   hard turn: entered when |e| > 60 deg, left when |e| < 10 deg; while in it (0, 2 e)
///   otherwise the policy's command (v, w), kept if the 0.2 s final-pose rollout check clears
///   (safety_checks.hpp beamRolloutHit, 20 x 0.01 s, 40 points on the 0.42 x 0.33 rectangle,
///   each beam against the point's |x| + |y|, tolerance 0.0: the script's own arithmetic);
///   else the turn in place (0, 2 e) if it clears the same check; else the back-up (-0.2, 0).
///
/// deployed: false (lflh_raw.yaml, lflh_2ms_raw.yaml) — the bare policy: no hard turn, no
/// safety check. Either way the command is clipped to max_speed and max_turn_rate.
/// The Inventec controller builds its own state machine on the same policy.

#include <memory>
#include <string>
#include <string_view>
#include <vector>

#include "barn/controllers/controller.hpp"
#include "barn/controllers/safety_checks.hpp"
#include "barn/core/config.hpp"
#include "barn/core/errors.hpp"
#include "barn/learning/policy.hpp"
#include "barn/nav/nav_stack.hpp"

namespace barn::controllers {

/// The drive the controllers on the LfLH policy share (LflhConfig, InventecConfig): the policy
/// file, the control rate, the local goal the policy steers to and the clip of what is sent.
/// Its keys are its owner's own: the owner's visit() calls visit() with the same visitor, so
/// they stay at the top level of the owner's block. The defaults are LfLH's (LflhConfig says
/// where each comes from); an owner whose values differ sets them where it declares its member,
/// and passes the docs `barn config` shows for its defaults' sources.
struct PolicyDriveConfig {
  std::string policy = "configs/policies/lflh_1ms.policy";
  double rate = 25.0;                // [Hz]
  double local_goal_distance = 1.5;  // [m]
  double max_speed = 1.0;            // [m/s]
  double max_turn_rate = 4.0;        // [rad/s]

  /// The owner's doc line of each field; an empty one shows the field's meaning instead.
  struct Docs {
    std::string_view policy, rate, local_goal_distance, max_speed, max_turn_rate;
  };
  template <class V> void visit(V& v, const Docs& docs = {}) {
    v("policy", policy, {.doc = docOr(docs.policy, "the LfLH policy file, relative to the config file's folder")});
    v("rate", rate, {.unit = "Hz", .range = core::kPositive, .doc = docOr(docs.rate, "control rate")});
    v("local_goal_distance", local_goal_distance,
      {.unit = "m", .range = core::kPositive,
       .doc = docOr(docs.local_goal_distance, "the policy's local goal: the point of the global path this far ahead")});
    v("max_speed", max_speed,
      {.unit = "m/s", .range = core::kPositive, .doc = docOr(docs.max_speed, "|v| clip of the command sent")});
    v("max_turn_rate", max_turn_rate,
      {.unit = "rad/s", .range = core::kPositive, .doc = docOr(docs.max_turn_rate, "|w| clip of the command sent")});
  }

 private:
  static std::string_view docOr(std::string_view given, std::string_view meaning) { return given.empty() ? meaning : given; }
};
/// The drive's rule beyond its fields' ranges (which the owner's validateFields checks, the
/// keys being the owner's): a policy file is named. Errors name `prefix.policy`.
void validate(const PolicyDriveConfig& drive, core::Errors& errors, const std::string& prefix);

struct LflhConfig {
  // Published deployment (LfD_2D/run_policy.py): the 1 m/s model, a new command every 0.04 s,
  // the local goal 1.5 m along the global path; the clips are the policy's own speed and the
  // Jackal's turn-rate limit.
  PolicyDriveConfig drive;
  double range_clip = 0.0;
  bool deployed = true;
  double hard_turn_enter_deg = 60.0;
  double hard_turn_exit_deg = 10.0;
  double turn_gain = 2.0;
  double backup_speed = 0.2;
  // The safety check tests the stack's unpadded footprint, nav.footprint() (published
  // deployment: the same 0.42 x 0.33 rectangle): tolerance 0.0, 20 Euler steps of 0.01 s, the
  // final pose only.
  BeamRolloutConfig safety;
  nav::NavStackConfig nav = lflhNav();

  template <class V> void visit(V& v) {
    drive.visit(v, {.policy = "relative to the config file's folder",
                    .rate = "(the original publishes every 0.04 s)",
                    .local_goal_distance = "along the global path",
                    .max_speed = "|v| clip (the policy's own speed)",
                    .max_turn_rate = "|w| clip (the Jackal's limit)"});
    v("range_clip", range_clip,
      {.unit = "m", .range = core::kNonNegative, .doc = "scan clip for the policy; 0: the policy file's (published deployment: 2.0 for both models)"});
    v("deployed", deployed, {.doc = "published deployment: hard turn + safety check + fallbacks; false = bare policy"});
    v("hard_turn_enter_deg", hard_turn_enter_deg,
      {.unit = "deg", .range = core::atMost(180.0), .doc = "published deployment: hard turn when |heading error| > pi/3"});
    v("hard_turn_exit_deg", hard_turn_exit_deg,
      {.unit = "deg", .doc = "published deployment: ... until |heading error| < pi/18"});
    v("turn_gain", turn_gain,
      {.unit = "1/s", .range = core::kPositive, .doc = "published deployment: w = 2 * heading error (hard turn and fallback turn)"});
    v("backup_speed", backup_speed,
      {.unit = "m/s", .range = core::kNonNegative, .doc = "published deployment: v = -0.2, w = 0 when the turn is unsafe too"});
    safety.visit(v, {.tolerance = {"safety_tolerance", "published deployment: tolerance 0.0 (Inventec's code: 0.02)"},
                     .steps = {"safety_steps", "published deployment: 20 Euler steps ..."},
                     .dt = {"safety_dt", "published deployment: ... of 0.01 s, final pose only"}});
    v("nav", nav);
  }

  /// The LfLH/Inventec move_base costmaps (the Inventec team's published move_base
  /// configuration): footprint padding 0.075, a wide exponential inflation that keeps the NavFn
  /// path in the middle of gaps (global: radius 5 m, k = 3, whose cost reaches 0 at 2.1 m; local:
  /// k = 1, cut here at 1 m, the local map being read only by Inventec, which sets its 5 m).
  static nav::NavStackConfig lflhNav();
};
void validate(const LflhConfig& config, core::Errors& errors, const std::string& prefix);

/// The policy file named by `policy`, resolved against the folder of the config file
/// `config_source` (if that is a file), else the current folder.
std::string resolvePolicyPath(const std::string& policy, const std::string& config_source);

/// The direction of the local goal in the robot frame for the policy: the unit vector from the
/// robot to the point `distance` along the path (x forward, y left).
Eigen::Vector2d localGoalDirection(const nav::Path& path, const core::Pose2& pose, double distance);


/// What the deployed LfLH sends in a tick (its state label in the trajectory record).
enum class LflhAction { Policy, HardTurn, SafetyTurn, BackUp };
std::string_view toString(LflhAction action);

/// The hard turn's hysteresis: whether the robot hard-turns this tick, given whether it did
/// the last tick and the heading error [rad] now.
bool nextHardTurn(bool turning, double heading_error, const LflhConfig& config);

/// The deployed command of a tick outside the hard turn: the policy's command if its rollout
/// clears the points (robot frame, see safety_checks.hpp), else the turn in place
/// (0, turn_gain * heading_error) if that clears, else the back-up (-backup_speed, 0).
/// `action` (if set) receives which of the three it is.
core::Twist deployedCommand(const core::Twist& policy_command, double heading_error, const core::LaserScan& scan,
                            const LflhConfig& config, LflhAction* action = nullptr);

class LflhController : public Controller {
 public:
  LflhController(const LflhConfig& config, std::shared_ptr<const learning::Policy> policy);
  void reset(const EpisodeInfo& info) override;
  core::Twist act(const Observation& observation) override;
  double period() const override { return 1.0 / config_.drive.rate; }
  void checkLidar(const core::LidarConfig& lidar) const override { learning::checkPolicyLidar(*policy_, lidar); }
  std::uint64_t trainedPlant() const override { return policy_->info().plant_hash; }
  /// The deployed controller's action of the last tick; "" for the bare policy.
  std::string_view stateLabel() const override { return config_.deployed ? toString(action_) : std::string_view{}; }
  LflhAction action() const { return action_; }

 private:
  LflhConfig config_;
  std::shared_ptr<const learning::Policy> policy_;
  nav::NavStack nav_;
  EpisodeInfo info_;
  bool hard_turn_ = false;
  LflhAction action_ = LflhAction::Policy;
};

}  // namespace barn::controllers
