#pragma once
/// The 2D LiDAR's description (Hokuyo UST-10LX on the Jackal, as in BARN): beam layout, range,
/// noise, rate and where it sits on the robot.
///
/// It lives in core, not sim, because controllers need the sensor geometry too (EpisodeInfo),
/// and a controller must build without the simulator. The caster that uses it is
/// sim::LidarCaster.

#include <string>

#include "barn/core/errors.hpp"
#include "barn/core/types.hpp"

namespace barn::core {

/// Defaults: the UST-10LX Gazebo model of jackal_description, mounted as run.py mounts it.
struct LidarConfig {
  int beams = 720;                 // [-]
  double angle_min = -2.35619;     // [rad] beam 0, at the robot's right rear
  double angle_max = 2.35619;      // [rad] last beam
  double range_min = 0.1;          // [m]
  double range_max = 30.0;         // [m] farther returns report +inf
  double noise_stddev = 0.001;     // [m] Gaussian range noise
  double rate = 50.0;              // [Hz]
  double mount_x = 0.055;          // [m] sensor origin ahead of the robot centre
  double mount_y = 0.0;            // [m]

  template <class V> void visit(V& v) {
    v("beams", beams); v("angle_min", angle_min); v("angle_max", angle_max);
    v("range_min", range_min); v("range_max", range_max); v("noise_stddev", noise_stddev);
    v("rate", rate); v("mount_x", mount_x); v("mount_y", mount_y);
  }

  double angleIncrement() const { return (angle_max - angle_min) / (beams - 1); }
  /// The sensor's pose in the world for a robot at `robot`.
  Pose2 sensorPose(const Pose2& robot) const;
};

/// Records every out-of-range field of `config` (prefix: the config's key path).
void validate(const LidarConfig& config, Errors& errors, const std::string& prefix = "lidar");

}  // namespace barn::core
