#pragma once
/// The simulated 2D LiDAR's exact caster (the sensor's description is core::LidarConfig).
///
/// The caster rasterises each cylinder into the beams it can cover: for a cylinder at distance
/// d and bearing b it visits only the beams within asin(r / d) of b and intersects each beam's
/// ray with the circle exactly. A scan costs one pass over the obstacles plus a few beams per
/// obstacle, instead of a ray march per beam. Box2D's RayCast (Simulator::referenceScan) is
/// the reference it is tested against.

#include <vector>

#include "barn/core/lidar_config.hpp"
#include "barn/core/rng.hpp"
#include "barn/core/types.hpp"
#include "barn/sim/obstacle_field.hpp"

namespace barn::sim {

/// One caster per episode (thread): it keeps scratch buffers between scans.
class LidarCaster {
 public:
  LidarCaster(const core::LidarConfig& config, const ObstacleField& field);

  /// Exact noise-free ranges from a sensor at `sensor_pose` (world frame) into `ranges`
  /// (resized to the beam count). No return within range_max -> +inf; a return closer than
  /// range_min is reported as range_min (only possible once the robot is already in collision).
  void cast(const core::Pose2& sensor_pose, std::vector<double>& ranges);

  /// A full scan for a robot at `robot_pose` taken at `stamp`, with Gaussian noise drawn from
  /// `noise` (no noise if null or noise_stddev is 0).
  core::LaserScan scan(const core::Pose2& robot_pose, double stamp, core::FastNoise* noise);

  const core::LidarConfig& config() const { return config_; }

 private:
  template <bool kVariedRadii>
  void castCircles(const core::Pose2& sensor_pose, std::vector<double>& ranges);

  core::LidarConfig config_;
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
void addRangeNoise(const core::LidarConfig& config, core::FastNoise& noise, std::vector<double>& ranges);

}  // namespace barn::sim
