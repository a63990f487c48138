#pragma once
/// The 2D LiDAR's description (Hokuyo UST-10LX on the Jackal, as in BARN): beam layout, range,
/// noise, rate and where it sits on the robot.
///
/// It lives in core, not sim, because controllers need the sensor geometry too (EpisodeInfo),
/// and a controller must build without the simulator. The caster that uses it is
/// sim::LidarCaster.

#include <string>

#include "barn/core/config.hpp"
#include "barn/core/errors.hpp"
#include "barn/core/types.hpp"

namespace barn::core {

/// Defaults: the UST-10LX Gazebo model of jackal_description, mounted as run.py mounts it.
struct LidarConfig {
  int beams = 720;
  double angle_min = -2.35619;
  double angle_max = 2.35619;
  double range_min = 0.1;
  double range_max = 30.0;
  double noise_stddev = 0.001;
  double rate = 50.0;
  double mount_x = 0.055;
  double mount_y = 0.0;

  // Upper bounds (our choice) lie far beyond any LiDAR, so a typo (1e308) is an error.
  template <class V> void visit(V& v) {
    v("beams", beams, {.range = core::closed(2, 100000)});
    v("angle_min", angle_min, {.unit = "rad", .doc = "beam 0, at the robot's right rear"});
    v("angle_max", angle_max, {.unit = "rad", .doc = "last beam"});
    v("range_min", range_min, {.unit = "m", .range = core::kNonNegative});
    v("range_max", range_max, {.unit = "m", .range = core::atMost(1000.0), .doc = "farther returns report +inf"});
    v("noise_stddev", noise_stddev, {.unit = "m", .range = core::closed(0.0, 10.0), .doc = "Gaussian range noise"});
    v("rate", rate, {.unit = "Hz", .range = core::openClosed(0.0, 10000.0)});
    v("mount_x", mount_x, {.unit = "m", .range = core::closed(-10.0, 10.0), .doc = "sensor origin ahead of the robot centre"});
    v("mount_y", mount_y, {.unit = "m", .range = core::closed(-10.0, 10.0)});
  }

  double angleIncrement() const { return (angle_max - angle_min) / (beams - 1); }
  /// The sensor's pose in the world for a robot at `robot`.
  Pose2 sensorPose(const Pose2& robot) const;
};

/// Records every out-of-range field of `config` (prefix: the config's key path).
void validate(const LidarConfig& config, Errors& errors, const std::string& prefix = "lidar");

}  // namespace barn::core
