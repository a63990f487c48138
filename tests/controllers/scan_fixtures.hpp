#pragma once
// Test fixture for controllers: a scan of one range (core types only, so the controller API's
// own test can use it without linking more than the API).

#include <algorithm>
#include <cmath>
#include <cstddef>
#include <limits>

#include <Eigen/Core>

#include "barn/core/lidar_config.hpp"
#include "barn/core/types.hpp"

namespace barn::controllers {

/// A scan of `lidar` with every beam at `range` (+inf: nothing seen).
inline core::LaserScan uniformScan(const core::LidarConfig& lidar, double range) {
  core::LaserScan scan;
  scan.angle_min = lidar.angle_min;
  scan.angle_increment = lidar.angleIncrement();
  scan.range_min = lidar.range_min;
  scan.range_max = lidar.range_max;
  scan.ranges.assign(static_cast<std::size_t>(lidar.beams), range);
  return scan;
}

/// The default LiDAR moved to the robot centre: the published code's checks read ranges as if
/// taken there (they ignored the mounting offset), so with it their numbers stay exact.
inline core::LidarConfig centredLidar() {
  core::LidarConfig lidar;
  lidar.mount_x = 0.0;
  return lidar;
}

/// A scan of `lidar` (at its mount offset) seeing a straight wall across the robot's path,
/// `x` [m] ahead of the robot centre: each beam's exact range to the line, +inf if it points away.
inline core::LaserScan wallScan(const core::LidarConfig& lidar, double x) {
  core::LaserScan scan = uniformScan(lidar, std::numeric_limits<double>::infinity());
  for (std::size_t i = 0; i < scan.ranges.size(); ++i) {
    const double c = std::cos(scan.angle(i));
    if (c > 1e-9) scan.ranges[i] = (x - lidar.mount_x) / c;
  }
  return scan;
}

/// `scan` with a round post of `radius` at `centre` (robot frame) added: each beam's range is the
/// nearer of what it saw and its exact entry into the circle.
inline core::LaserScan withPost(core::LaserScan scan, const core::LidarConfig& lidar, const Eigen::Vector2d& centre,
                                double radius) {
  const Eigen::Vector2d to_centre = centre - Eigen::Vector2d(lidar.mount_x, lidar.mount_y);
  for (std::size_t i = 0; i < scan.ranges.size(); ++i) {
    const Eigen::Vector2d d(std::cos(scan.angle(i)), std::sin(scan.angle(i)));
    const double along = to_centre.dot(d);
    const double miss2 = to_centre.squaredNorm() - along * along;
    if (along <= 0.0 || miss2 > radius * radius) continue;
    scan.ranges[i] = std::min(scan.ranges[i], along - std::sqrt(radius * radius - miss2));
  }
  return scan;
}

}  // namespace barn::controllers
