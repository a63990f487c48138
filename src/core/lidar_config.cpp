#include "barn/core/lidar_config.hpp"

#include <cmath>
#include <numbers>

namespace barn::core {

Pose2 LidarConfig::sensorPose(const Pose2& robot) const {
  const Eigen::Vector2d origin = robot.transform({mount_x, mount_y});
  return {origin.x(), origin.y(), robot.yaw};
}

void validate(const LidarConfig& c, Errors& errors, const std::string& prefix) {
  core::validateFields(c, errors, prefix);
  errors.check(c.angle_max > c.angle_min, prefix + ".angle_max", "must be greater than angle_min");
  errors.check(c.angle_min >= -std::numbers::pi && c.angle_max <= std::numbers::pi, prefix + ".angle_min",
               "the field of view must lie within [-pi, pi]");
  errors.check(c.range_max > c.range_min, prefix + ".range_max", "must be greater than range_min");
}

}  // namespace barn::core
