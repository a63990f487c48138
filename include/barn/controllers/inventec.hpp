#pragma once
/// `inventec`: the seed paper's controller (BARN 2023, 2nd place): the LfLH policy inside a
/// finite state machine with forward safety checks and a backtracking recovery.
///
///   Initial --path--> Heading --aligned--> LfLH --dangerous command--> Backtrack
///   LfLH --not aligned--> Heading        Heading --unsafe rotation--> Backtrack
///   Backtrack --reversed to the breadcrumb--> Heading
///   Backtrack --obstacle behind (costmap ROI)--> Forward --nudged--> Heading
///   Forward --unsafe--> Backtrack
///
/// Defaults follow the paper where it gives a number, otherwise the team's published code as
/// described in shared/research/controllers.md section 1; configs/controllers/inventec_*.yaml
/// say which is which.

#include <memory>
#include <string>

#include "barn/controllers/controller.hpp"
#include "barn/controllers/lflh.hpp"
#include "barn/controllers/safety_checks.hpp"
#include "barn/core/errors.hpp"
#include "barn/learning/policy.hpp"
#include "barn/nav/nav_stack.hpp"

namespace barn::controllers {

enum class InventecState { Initial, Heading, Lflh, Backtrack, Forward };
std::string_view toString(InventecState state);

struct InventecSafetyConfig {
  std::string type = "fi";      // fi (footprint inflation, the simulation entry), mpc, none
  double fi_offset = 0.04;      // [m] paper: FI 0.04 m
  int mpc_steps = 20;           // paper: 20 steps (~0.2 s)
  double mpc_dt = 0.01;         // [s] code (simulation branch)
  double mpc_offset = 0.0;      // [m] footprint growth in the rollout
  template <class V> void visit(V& v) {
    v("type", type); v("fi_offset", fi_offset); v("mpc_steps", mpc_steps); v("mpc_dt", mpc_dt); v("mpc_offset", mpc_offset);
  }
};

struct InventecConfig {
  std::string policy = "configs/policies/lflh_1ms.policy";  // paper: the 1 m/s LfLH model
  double rate = 25.0;                  // [Hz] policy rate (the code's FSM loop runs at 30 Hz)
  double max_speed = 0.7;              // [m/s] paper: clip 0.7 m/s
  double max_turn_rate = 2.0;          // [rad/s] code: max_w
  double local_goal_distance = 0.5;    // [m] paper: 0.5 m (code: 1.5 m)
  double path_direction_distance = 0.5;  // [m] code: dir_dist
  double heading_tolerance_deg = 30.0;   // paper: +-30 degrees to leave Heading (code: 10)
  double heading_limit_deg = 60.0;       // code: LfLH hands over to Heading beyond 60 degrees
  double heading_gain = 1.5;             // [1/s] code: w = 1.5 x heading error
  double min_turn_rate = 0.2;            // [rad/s] code: rotate_align_min_w
  double footprint_length = 0.508;       // [m] paper: 0.43 x 0.508 (x by y in our frame: 0.508 along x)
  double footprint_width = 0.43;         // [m]
  InventecSafetyConfig safety;
  bool backtrack_roi = true;             // check the costmap strip behind before reversing
  double roi_depth = 0.1;                // [m] code (simulation): rear_length_m
  double backtrack_distance = 0.3;       // [m] paper: the point 0.3 m behind along the driven path
  double backtrack_speed = 0.3;          // [m/s] code: rev_vel
  double align_tolerance_deg = 3.0;      // code: align_deg
  double forward_speed = 0.2;            // [m/s] paper: 0.2 m/s (code: 0.1)
  double forward_turn_rate = 0.1;        // [rad/s] code: stuck_w
  double forward_duration = 0.25;        // [s] code: backtrack.timeout
  nav::NavStackConfig nav = LflhConfig::lflhNav();

  template <class V> void visit(V& v) {
    v("policy", policy); v("rate", rate); v("max_speed", max_speed); v("max_turn_rate", max_turn_rate);
    v("local_goal_distance", local_goal_distance); v("path_direction_distance", path_direction_distance);
    v("heading_tolerance_deg", heading_tolerance_deg); v("heading_limit_deg", heading_limit_deg);
    v("heading_gain", heading_gain); v("min_turn_rate", min_turn_rate); v("footprint_length", footprint_length);
    v("footprint_width", footprint_width); v("safety", safety); v("backtrack_roi", backtrack_roi);
    v("roi_depth", roi_depth); v("backtrack_distance", backtrack_distance); v("backtrack_speed", backtrack_speed);
    v("align_tolerance_deg", align_tolerance_deg); v("forward_speed", forward_speed);
    v("forward_turn_rate", forward_turn_rate); v("forward_duration", forward_duration); v("nav", nav);
  }
};
void validate(const InventecConfig& config, core::Errors& errors, const std::string& prefix);

/// What the transition function looks at; every flag is computed by the controller from the
/// observation and the checks of the current state only.
struct InventecInputs {
  bool has_path = false;
  double heading_error = 0.0;    // [rad] to the path direction
  bool command_unsafe = false;   // LfLH: the safety check rejects the policy's command
  bool rotation_unsafe = false;  // Heading: turning in place would touch an obstacle
  bool backtrack_done = false;   // Backtrack: reached the breadcrumb (or there is none)
  bool rear_blocked = false;     // Backtrack: lethal cells in the region behind
  bool forward_done = false;     // Forward: the nudge has lasted forward_duration
  bool forward_unsafe = false;   // Forward: the nudge would touch an obstacle
};

/// The state machine's transitions (see the header comment), as one pure function.
InventecState nextInventecState(InventecState state, const InventecInputs& in, const InventecConfig& config);

class InventecController : public Controller {
 public:
  InventecController(const InventecConfig& config, std::shared_ptr<const learning::Policy> policy);
  void reset(const EpisodeInfo& info) override;
  core::Twist act(const Observation& observation) override;
  double period() const override { return 1.0 / config_.rate; }
  std::string_view stateLabel() const override { return toString(state_); }
  InventecState state() const { return state_; }

 private:
  bool commandUnsafe(const std::vector<Eigen::Vector2d>& points, const core::Twist& command) const;
  void enter(InventecState state, const core::Pose2& pose, double time);
  core::Twist turnToward(double error) const;

  InventecConfig config_;
  std::shared_ptr<const learning::Policy> policy_;
  nav::NavStack nav_;
  EpisodeInfo info_;
  InventecState state_ = InventecState::Initial;
  Box footprint_;                            // the robot rectangle
  std::vector<Eigen::Vector2d> breadcrumbs_;  // odom positions driven in LfLH
  Eigen::Vector2d backtrack_target_ = Eigen::Vector2d::Zero();
  bool has_backtrack_target_ = false;
  bool aligned_ = false;                     // Backtrack: rear faces the target
  double forward_started_ = 0.0;             // [s]
};

}  // namespace barn::controllers
