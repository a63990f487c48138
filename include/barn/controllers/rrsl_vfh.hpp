#pragma once
/// `rrsl_vfh`: Michigan Tech RRSL's BARN 2025 winner, VFH* with fuzzy speed and turn rate at
/// 10 Hz from the LiDAR alone: no map, no global planner (vfh_fuzzy.hpp has the method).
///
/// Pose and goal: the team's node adds INIT (-2, 3) to the odometry and aims at INIT + (0, 10).
/// INIT cancels in everything it computes (the bearing and the distance to the goal), which
/// are therefore those from the odometry to the goal (0, 10) in the odom frame: exactly what
/// barnbench's Observation gives (odom pose, odom-frame goal). Under the official harness's
/// start x = -2.25 the node, whose INIT default is -2, still aims at odom (0, 10), the true
/// goal; docs/systems/rrsl_vfh.md says more.
///
/// Source: MazenMTULab/the-barn-challenge@6072114 navigation_pkg/scripts/Nav-VFH.py.

#include "barn/controllers/controller.hpp"
#include "barn/controllers/vfh_fuzzy.hpp"
#include "barn/core/config.hpp"
#include "barn/core/errors.hpp"

namespace barn::controllers {

struct RrslVfhConfig {
  double rate = 10.0;
  double goal_stop_radius = 0.5;
  VfhConfig vfh;
  template <class V> void visit(V& v) {
    v("rate", rate, {.unit = "Hz", .range = core::kPositive, .doc = "team: rospy.Rate(10)"});
    v("goal_stop_radius", goal_stop_radius,
      {.unit = "m", .range = core::kNonNegative, .doc = "team: stop (and quit) within 0.5 m of the goal"});
    v("vfh", vfh, {.doc = "the team's VFH* and fuzzy systems (vfh_fuzzy.hpp)"});
  }
};
void validate(const RrslVfhConfig& config, core::Errors& errors, const std::string& prefix);

class RrslVfhController : public Controller {
 public:
  explicit RrslVfhController(const RrslVfhConfig& config) : config_(config), vfh_(config.vfh) {}
  void reset(const EpisodeInfo& info) override;
  core::Twist act(const Observation& observation) override;
  double period() const override { return 1.0 / config_.rate; }
  std::string_view stateLabel() const override { return core::enumName(action_); }
  void checkLidar(const core::LidarConfig& lidar) const override { checkVfhBeams(config_.vfh, lidar.beams); }

 private:
  RrslVfhConfig config_;
  VfhFuzzy vfh_;
  VfhAction action_ = VfhAction::Steer;  // this tick's; GoalStop and Halted last the episode
};

}  // namespace barn::controllers
