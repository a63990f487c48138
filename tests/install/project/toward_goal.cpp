#include "toward_goal.hpp"

#include <algorithm>
#include <cmath>

void TowardGoal::reset(const barn::controllers::EpisodeInfo& info) { info_ = info; }

barn::core::Twist TowardGoal::act(const barn::controllers::Observation& observation) {
  const Eigen::Vector2d to_goal = observation.goal - observation.odom_pose.position();
  const double error = barn::core::wrapAngle(std::atan2(to_goal.y(), to_goal.x()) - observation.odom_pose.yaw);
  barn::core::Twist command;
  command.angular = std::clamp(2.0 * error, -info_.robot.max_angular_speed, info_.robot.max_angular_speed);
  command.linear = 0.5 * std::max(0.0, std::cos(error));  // [m/s]
  return command;
}
