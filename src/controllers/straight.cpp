#include "barn/controllers/straight.hpp"

#include <algorithm>
#include <cmath>

namespace barn::controllers {

void validate(const StraightConfig& c, core::Errors& errors, const std::string& prefix) {
  core::validateFields(c, errors, prefix);  // every rule is a field's range
}

void StraightController::reset(const EpisodeInfo& info) { max_angular_ = info.robot.max_angular_speed; }

core::Twist StraightController::act(const Observation& obs) {
  const Eigen::Vector2d to_goal = obs.goal - obs.odom_pose.position();
  const double error = core::wrapAngle(std::atan2(to_goal.y(), to_goal.x()) - obs.odom_pose.yaw);
  core::Twist cmd;
  cmd.angular = std::clamp(config_.heading_gain * error, -max_angular_, max_angular_);
  // Drive only when roughly facing the goal; slow down with the heading error.
  cmd.linear = config_.speed * std::max(0.0, std::cos(error));
  return cmd;
}

}  // namespace barn::controllers
