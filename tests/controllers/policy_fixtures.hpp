#pragma once
// Test fixtures for controllers that run an LfLH policy: a policy with a fixed output and
// scans of one range.

#include <cstddef>
#include <memory>

#include "barn/core/lidar_config.hpp"
#include "barn/core/types.hpp"
#include "barn/learning/policy.hpp"

namespace barn::controllers {

/// A policy that always says (v, w): zero weights, the output bias (v, w).
inline std::shared_ptr<const learning::Policy> constantPolicy(double v, double w) {
  learning::PolicyInfo info;
  info.hidden = 4;
  info.name = "constant";
  learning::MlpParameters<float> weights = learning::MlpParameters<float>::zeros(722, 4, 2);
  weights.b3 << static_cast<float>(v), static_cast<float>(w);
  return std::make_shared<const learning::Policy>(info, weights);
}

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
