#pragma once
/// The simulated 2D LiDAR (Hokuyo UST-10LX on the Jackal, as in BARN) and its exact caster.
///
/// The caster rasterises each cylinder into the beams it can cover: for a cylinder at distance
/// d and bearing b it visits only the beams within asin(r / d) of b and intersects each beam's
/// ray with the circle exactly. A scan costs one pass over the obstacles plus a few beams per
/// obstacle, instead of a ray march per beam. Box2D's RayCast (Simulator::referenceScan) is
/// the reference it is tested against.

#include <vector>

#include "barn/core/errors.hpp"
#include "barn/core/rng.hpp"
#include "barn/core/types.hpp"
#include "barn/sim/obstacle_field.hpp"

namespace barn::sim {

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
  core::Pose2 sensorPose(const core::Pose2& robot) const;
};

void validate(const LidarConfig& config, core::Errors& errors, const std::string& prefix = "lidar");

/// One caster per episode (thread): it keeps scratch buffers between scans.
class LidarCaster {
 public:
  LidarCaster(const LidarConfig& config, const ObstacleField& field);

  /// Exact noise-free ranges from a sensor at `sensor_pose` (world frame) into `ranges`
  /// (resized to the beam count). No return within range_max -> +inf; a return closer than
  /// range_min is reported as range_min (only possible once the robot is already in collision).
  void cast(const core::Pose2& sensor_pose, std::vector<double>& ranges);

  /// A full scan for a robot at `robot_pose` taken at `stamp`, with Gaussian noise drawn from
  /// `noise` (no noise if null or noise_stddev is 0).
  core::LaserScan scan(const core::Pose2& robot_pose, double stamp, core::FastNoise* noise);

  const LidarConfig& config() const { return config_; }

 private:
  template <bool kVariedRadii>
  void castCircles(const core::Pose2& sensor_pose, std::vector<double>& ranges);

  LidarConfig config_;
  const ObstacleField* field_;
  std::vector<double> beam_cos_;  // cos of each beam's angle in the sensor frame
  std::vector<double> beam_sin_;

  // Scratch for cast(): circles in range (sensor frame) and their near-first order.
  struct Candidate {
    double dx, dy;   // [m] centre
    double power;    // [m^2] |d|^2 - r^2, the sensor's power with respect to the circle
    double nearest;  // [m] |d| - r: no ray can hit the circle closer than this
    int bucket;      // distance bucket (0.25 m)
  };
  std::vector<Candidate> candidates_;
  std::vector<int> bucket_start_;
  std::vector<int> order_;
  std::vector<double> candidate_radius_;  // [m] beside candidates_ when circles have own radii
};

/// Adds the sensor's Gaussian range noise to finite `ranges` (clamped to [range_min,
/// range_max]; misses stay +inf), as scan() does.
void addRangeNoise(const LidarConfig& config, core::FastNoise& noise, std::vector<double>& ranges);

}  // namespace barn::sim
