#include "barn/controllers/rrsl_vfh.hpp"

namespace barn::controllers {

void validate(const RrslVfhConfig& c, core::Errors& errors, const std::string& prefix) {
  core::validateFields(c, errors, prefix);
  validate(c.vfh, errors, prefix + ".vfh");
}

void RrslVfhController::reset(const EpisodeInfo& /*info*/) {
  vfh_.reset();
  action_ = VfhAction::Steer;
}

core::Twist RrslVfhController::act(const Observation& obs) {
  // The team's node leaves its loop for good at the goal (after one zero command) and dies on
  // a fuzzy error; either way the robot gets no more commands and stands (the Jackal's
  // cmd_vel timeout).
  if (action_ == VfhAction::GoalStop || action_ == VfhAction::Halted) return {};
  if ((obs.goal - obs.odom_pose.position()).norm() < config_.goal_stop_radius) {
    action_ = VfhAction::GoalStop;
    return {};
  }
  const VfhStep step = vfh_.step(*obs.scan, obs.odom_pose, obs.goal);
  action_ = step.action;
  return step.command;
}

}  // namespace barn::controllers
