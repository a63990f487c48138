#pragma once
/// `lflh`: the seed paper's LfLH baseline. A learned policy (learning::Policy, trained by
/// `barn lflh train`) maps the clipped scan and the unit vector to a local goal 1.5 m along the
/// global path (nav::NavStack, NavFn-like) to (v, w) at 25 Hz. No state machine, no safety
/// check: the Inventec controller builds those on top.

#include <memory>
#include <string>

#include "barn/controllers/controller.hpp"
#include "barn/core/errors.hpp"
#include "barn/learning/policy.hpp"
#include "barn/nav/nav_stack.hpp"

namespace barn::controllers {

struct LflhConfig {
  std::string policy = "configs/policies/lflh_1ms.policy";  // relative to the config file's folder
  double rate = 25.0;            // [Hz] (the original publishes every 0.04 s)
  double local_goal_distance = 1.5;  // [m] along the global path
  double max_speed = 1.0;        // [m/s] |v| clip (the policy's own speed)
  double max_turn_rate = 4.0;    // [rad/s] |w| clip (the Jackal's limit)
  nav::NavStackConfig nav = lflhNav();

  template <class V> void visit(V& v) {
    v("policy", policy); v("rate", rate); v("local_goal_distance", local_goal_distance); v("max_speed", max_speed);
    v("max_turn_rate", max_turn_rate); v("nav", nav);
  }

  /// The LfLH/Inventec move_base costmaps (the Inventec team's published move_base
  /// configuration): footprint padding 0.075, a wide exponential inflation that keeps the NavFn
  /// path in the middle of gaps (k = 3 global, 1 local; BARN's 5 m radius cut at 1 m, where the
  /// global cost has fallen to 26 of 252).
  static nav::NavStackConfig lflhNav();
};
void validate(const LflhConfig& config, core::Errors& errors, const std::string& prefix);

/// The policy file named by `policy`, resolved against the folder of the config file
/// `config_source` (if that is a file), else the current folder.
std::string resolvePolicyPath(const std::string& policy, const std::string& config_source);

/// The direction of the local goal in the robot frame for the policy: the unit vector from the
/// robot to the point `distance` along the path (x forward, y left).
Eigen::Vector2d localGoalDirection(const nav::Path& path, const core::Pose2& pose, double distance);


class LflhController : public Controller {
 public:
  LflhController(const LflhConfig& config, std::shared_ptr<const learning::Policy> policy);
  void reset(const EpisodeInfo& info) override;
  core::Twist act(const Observation& observation) override;
  double period() const override { return 1.0 / config_.rate; }

 private:
  LflhConfig config_;
  std::shared_ptr<const learning::Policy> policy_;
  nav::NavStack nav_;
  EpisodeInfo info_;
};

}  // namespace barn::controllers
