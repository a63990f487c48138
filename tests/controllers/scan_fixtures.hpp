#pragma once
// Test fixture for controllers: a scan of one range (core types only, so the controller API's
// own test can use it without linking more than the API).

#include <cstddef>

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

}  // namespace barn::controllers
