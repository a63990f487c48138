#include "barn/nav/path_tools.hpp"

#include <cmath>
#include <limits>

namespace barn::nav {

std::size_t closestIndex(const Path& path, const Eigen::Vector2d& position) {
  std::size_t best = 0;
  double best_d2 = std::numeric_limits<double>::infinity();
  for (std::size_t i = 0; i < path.size(); ++i) {
    const double d2 = (path[i] - position).squaredNorm();
    if (d2 < best_d2) {
      best_d2 = d2;
      best = i;
    }
  }
  return best;
}

Eigen::Vector2d pointAlongPath(const Path& path, const Eigen::Vector2d& position, double lookahead) {
  std::size_t i = closestIndex(path, position);
  double remaining = lookahead;
  while (i + 1 < path.size()) {
    const double segment = (path[i + 1] - path[i]).norm();
    if (segment >= remaining) return path[i] + (path[i + 1] - path[i]) * (remaining / segment);
    remaining -= segment;
    ++i;
  }
  return path.back();
}

double headingError(const Path& path, const core::Pose2& pose, double lookahead) {
  const Eigen::Vector2d target = pointAlongPath(path, pose.position(), lookahead);
  const Eigen::Vector2d d = target - pose.position();
  if (d.squaredNorm() < 1e-12) return 0.0;
  return core::wrapAngle(std::atan2(d.y(), d.x()) - pose.yaw);
}

Path pathInRobotFrame(const Path& path, const core::Pose2& pose) {
  Path local;
  local.reserve(path.size());
  const core::PoseFrame robot(pose);
  for (const auto& p : path) local.push_back(robot.toLocal(p));
  return local;
}

}  // namespace barn::nav
