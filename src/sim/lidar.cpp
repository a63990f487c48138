#include "barn/sim/lidar.hpp"

#include <algorithm>
#include <cmath>
#include <limits>
#include <numbers>

namespace barn::sim {

core::Pose2 LidarConfig::sensorPose(const core::Pose2& robot) const {
  const Eigen::Vector2d origin = robot.transform({mount_x, mount_y});
  return {origin.x(), origin.y(), robot.yaw};
}

void validate(const LidarConfig& c, core::Errors& errors, const std::string& prefix) {
  errors.check(c.beams >= 2 && c.beams <= 100000, prefix + ".beams", "must be in [2, 100000]");
  errors.check(c.angle_max > c.angle_min, prefix + ".angle_max", "must be greater than angle_min");
  errors.check(c.angle_min >= -std::numbers::pi && c.angle_max <= std::numbers::pi, prefix + ".angle_min",
               "the field of view must lie within [-pi, pi]");
  errors.check(c.range_min >= 0.0, prefix + ".range_min", "must be >= 0");
  errors.check(c.range_max > c.range_min, prefix + ".range_max", "must be greater than range_min");
  errors.check(c.noise_stddev >= 0.0, prefix + ".noise_stddev", "must be >= 0");
  errors.check(c.rate > 0.0, prefix + ".rate", "must be > 0");
}

LidarCaster::LidarCaster(const LidarConfig& config, const ObstacleField& field) : config_(config), field_(&field) {
  beam_cos_.resize(static_cast<std::size_t>(config.beams));
  beam_sin_.resize(static_cast<std::size_t>(config.beams));
  const double increment = config.angleIncrement();
  for (int i = 0; i < config.beams; ++i) {
    const double angle = config.angle_min + i * increment;
    beam_cos_[static_cast<std::size_t>(i)] = std::cos(angle);
    beam_sin_[static_cast<std::size_t>(i)] = std::sin(angle);
  }
}

void LidarCaster::cast(const core::Pose2& sensor_pose, std::vector<double>& ranges) const {
  constexpr double kInf = std::numeric_limits<double>::infinity();
  constexpr double kTwoPi = 2.0 * std::numbers::pi;
  // Beams whose angle lies within this margin outside a circle's angular interval are tested
  // too; the exact ray-circle test then decides. It absorbs rounding in the index arithmetic.
  constexpr double kAngleMargin = 1e-9;

  const int beams = config_.beams;
  ranges.assign(static_cast<std::size_t>(beams), kInf);
  const double r = field_->radius;
  const double r2 = r * r;
  const double reach2 = (config_.range_max + r) * (config_.range_max + r);
  const double increment = config_.angleIncrement();
  const double c = std::cos(sensor_pose.yaw);
  const double s = std::sin(sensor_pose.yaw);

  for (const Eigen::Vector2d& centre : field_->centres) {
    // The circle in the sensor frame.
    const double wx = centre.x() - sensor_pose.x;
    const double wy = centre.y() - sensor_pose.y;
    const double dx = c * wx + s * wy;
    const double dy = -s * wx + c * wy;
    const double dist2 = dx * dx + dy * dy;
    if (dist2 > reach2 || dist2 <= r2) continue;  // out of range, or the sensor is inside it
    const double dist = std::sqrt(dist2);
    const double bearing = std::atan2(dy, dx);
    const double half = std::asin(r / dist) + kAngleMargin;
    // The interval may wrap past +-pi (behind the sensor); test it shifted by one turn each way.
    for (double shift : {0.0, -kTwoPi, kTwoPi}) {
      const double lo = bearing - half + shift;
      const double hi = bearing + half + shift;
      if (hi < config_.angle_min || lo > config_.angle_max) continue;
      const int first = std::max(0, static_cast<int>(std::ceil((lo - config_.angle_min) / increment)));
      const int last = std::min(beams - 1, static_cast<int>(std::floor((hi - config_.angle_min) / increment)));
      for (int i = first; i <= last; ++i) {
        // Ray p(t) = t u, |u| = 1: |t u - d|^2 = r^2 -> t = u.d - sqrt((u.d)^2 - (|d|^2 - r^2)).
        const double along = beam_cos_[static_cast<std::size_t>(i)] * dx + beam_sin_[static_cast<std::size_t>(i)] * dy;
        const double disc = along * along - (dist2 - r2);
        if (disc < 0.0 || along <= 0.0) continue;
        const double t = along - std::sqrt(disc);
        double& range = ranges[static_cast<std::size_t>(i)];
        if (t < range) range = t;
      }
    }
  }
  for (double& range : ranges) {
    if (range > config_.range_max) range = kInf;
    else if (range < config_.range_min) range = config_.range_min;
  }
}

core::LaserScan LidarCaster::scan(const core::Pose2& robot_pose, double stamp, core::Rng* noise) const {
  core::LaserScan scan;
  scan.stamp = stamp;
  scan.angle_min = config_.angle_min;
  scan.angle_increment = config_.angleIncrement();
  scan.range_min = config_.range_min;
  scan.range_max = config_.range_max;
  cast(config_.sensorPose(robot_pose), scan.ranges);
  if (noise && config_.noise_stddev > 0.0) {
    for (double& range : scan.ranges) {
      if (!std::isfinite(range)) continue;  // Gazebo's noise does not turn a miss into a hit
      range = std::clamp(range + config_.noise_stddev * noise->normal(), config_.range_min, config_.range_max);
    }
  }
  return scan;
}

}  // namespace barn::sim
