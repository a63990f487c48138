#include "barn/core/lidar_config.hpp"

#include <cmath>
#include <numbers>

namespace barn::core {

Pose2 LidarConfig::sensorPose(const Pose2& robot) const {
  const Eigen::Vector2d origin = robot.transform({mount_x, mount_y});
  return {origin.x(), origin.y(), robot.yaw};
}

void validate(const LidarConfig& c, Errors& errors, const std::string& prefix) {
  errors.check(c.beams >= 2 && c.beams <= 100000, prefix + ".beams", "must be in [2, 100000]");
  errors.check(c.angle_max > c.angle_min, prefix + ".angle_max", "must be greater than angle_min");
  errors.check(c.angle_min >= -std::numbers::pi && c.angle_max <= std::numbers::pi, prefix + ".angle_min",
               "the field of view must lie within [-pi, pi]");
  errors.check(c.range_min >= 0.0, prefix + ".range_min", "must be >= 0");
  errors.check(c.range_max > c.range_min, prefix + ".range_max", "must be greater than range_min");
  // Upper bounds, our choice: far beyond any LiDAR, so a typo (1e308) is an error.
  errors.check(c.range_max <= 1000.0, prefix + ".range_max", "must be <= 1000 [m]");
  errors.check(c.noise_stddev >= 0.0 && c.noise_stddev <= 10.0, prefix + ".noise_stddev", "must be in [0, 10] [m]");
  errors.check(c.rate > 0.0, prefix + ".rate", "must be > 0");
  errors.check(c.rate <= 10000.0, prefix + ".rate", "must be <= 10000 [Hz]");
  errors.check(std::abs(c.mount_x) <= 10.0 && std::abs(c.mount_y) <= 10.0, prefix + ".mount_x",
               "mount_x and mount_y must be within 10 m of the robot centre");
}

}  // namespace barn::core
