#include "barn/controllers/pure_pursuit.hpp"

#include <algorithm>
#include <cmath>
#include <limits>

namespace barn::controllers {

void validate(const PurePursuitConfig& c, core::Errors& errors, const std::string& prefix) {
  core::validateFields(c, errors, prefix);  // every rule is a field's range
}

void PurePursuitController::reset(const EpisodeInfo& info) {
  path_ = reference_path_;
  path_.push_back(info.goal);
  progress_ = 0;
  max_angular_ = info.robot.max_angular_speed;
}

core::Twist PurePursuitController::act(const Observation& obs) {
  const Eigen::Vector2d position = obs.odom_pose.position();
  // Advance along the path to the closest point within a short window (never backwards).
  const std::size_t window_end = std::min(path_.size(), progress_ + 10);
  double best = std::numeric_limits<double>::infinity();
  for (std::size_t i = progress_; i < window_end; ++i) {
    const double d = (path_[i] - position).norm();
    if (d < best) {
      best = d;
      progress_ = i;
    }
  }
  // The pursued point: the first point past the closest one that is at least `lookahead`
  // away, else the goal. (Starting at the closest point itself would pick it once the robot
  // has driven `lookahead` beyond it, i.e. a point behind the robot.)
  Eigen::Vector2d target = path_.back();
  for (std::size_t i = progress_ + 1; i < path_.size(); ++i) {
    if ((path_[i] - position).norm() >= config_.lookahead) {
      target = path_[i];
      break;
    }
  }
  const Eigen::Vector2d local = obs.odom_pose.inverseTransform(target);
  const double distance = local.norm();
  core::Twist cmd;
  if (distance < 1e-9) return cmd;
  const double alpha = std::atan2(local.y(), local.x());
  if (std::abs(alpha) > 1.2) {
    // Facing away: turn in place first.
    cmd.angular = std::copysign(std::min(max_angular_, 1.5), alpha);
    return cmd;
  }
  cmd.linear = config_.speed;
  // Pure pursuit: curvature 2 sin(alpha) / distance.
  cmd.angular = std::clamp(cmd.linear * 2.0 * std::sin(alpha) / distance, -max_angular_, max_angular_);
  return cmd;
}

}  // namespace barn::controllers
