#pragma once
/// Optional dead-reckoning odometry, a realism setting for fidelity studies (off by default).
///
/// BARN's controllers read `odometry/filtered`: robot_localization's EKF over the Jackal's wheel
/// odometry (forward speed and yaw rate from the encoders) and its IMU gyro. Such an estimate
/// is integrated, so its errors accumulate: a per-episode wheel scale error (tyre radius,
/// skid), wheel speed noise, a per-episode error of the turn rate (a skid-steer base's wheels
/// misjudge turns), a gyro bias and gyro noise, and no sight of sideways slip (the wheels
/// cannot measure it). The odom frame therefore drifts away from the world, the
/// costmaps smear, and a robot turning in place is not at a perfectly fixed point.
///
/// The defaults are typical of a wheeled robot's odometry, not fitted to any world; they are on
/// because they improve agreement with Gazebo (docs/fidelity.md: without drift a robot turning
/// in place is at a perfect fixed point and DWA can turn there forever). With every value 0 and
/// see_sideways_slip true the odometry is the ground truth shifted to the start.

#include <cstdint>

#include "barn/core/config.hpp"
#include "barn/core/errors.hpp"
#include "barn/core/rng.hpp"
#include "barn/core/types.hpp"

namespace barn::bench {

struct OdometryDriftConfig {
  double speed_scale_stddev = 0.01;
  double speed_noise_density = 0.005;
  double turn_scale_stddev = 0.0;
  double gyro_bias_stddev = 0.001;
  double gyro_noise_density = 0.002;
  bool see_sideways_slip = false;
  // Upper bounds, our choice: a hundred times and more what a wheel encoder or a MEMS gyro
  // shows, so a typo (1e6) is an error rather than an odometry that means nothing.
  template <class V> void visit(V& v) {
    v("speed_scale_stddev", speed_scale_stddev,
      {.range = core::closedOpen(0.0, 0.5), .doc = "per-episode relative error of the wheel speed"});
    v("speed_noise_density", speed_noise_density,
      {.unit = "m/s/sqrt(Hz)", .range = core::closed(0.0, 1.0), .doc = "white noise on the measured speed"});
    v("turn_scale_stddev", turn_scale_stddev,
      {.range = core::closedOpen(0.0, 0.5), .doc = "per-episode relative error of the estimated yaw rate (skid-steer wheels misjudge turns; the gyro corrects only part of it in the filter)"});
    v("gyro_bias_stddev", gyro_bias_stddev,
      {.unit = "rad/s", .range = core::closed(0.0, 1.0), .doc = "per-episode constant gyro bias"});
    v("gyro_noise_density", gyro_noise_density,
      {.unit = "rad/s/sqrt(Hz)", .range = core::closed(0.0, 1.0), .doc = "white noise on the measured yaw rate"});
    v("see_sideways_slip", see_sideways_slip, {.doc = "false: sideways slip is not in the estimate (wheels)"});
  }
  /// No errors at all: the estimate is the ground truth.
  static OdometryDriftConfig groundTruth() {
    OdometryDriftConfig c;
    c.speed_scale_stddev = c.speed_noise_density = c.turn_scale_stddev = c.gyro_bias_stddev = c.gyro_noise_density = 0.0;
    c.see_sideways_slip = true;
    return c;
  }
  bool enabled() const {
    return speed_scale_stddev > 0.0 || speed_noise_density > 0.0 || turn_scale_stddev > 0.0 || gyro_bias_stddev > 0.0 ||
           gyro_noise_density > 0.0 || !see_sideways_slip;
  }
};

void validate(const OdometryDriftConfig& config, core::Errors& errors, const std::string& prefix);

/// The integrated estimate: feed it the true pose after every physics step.
class DriftingOdometry {
 public:
  /// `start` is the true pose at which the estimate equals the odom origin with the true yaw.
  DriftingOdometry(const OdometryDriftConfig& config, const core::Pose2& start, std::uint64_t seed);

  /// Integrates the motion from the previous true pose to `now` over `dt` seconds.
  void update(const core::Pose2& now, double dt);

  /// The estimate in the odom frame (origin at the start position, yaw as the world's).
  const core::Pose2& pose() const { return estimate_; }

 private:
  OdometryDriftConfig config_;
  core::FastNoise noise_;
  core::Pose2 previous_;   // true pose at the last update
  core::Pose2 estimate_;   // odom frame
  double speed_scale_ = 1.0;
  double turn_scale_ = 1.0;
  double gyro_bias_ = 0.0;
};

}  // namespace barn::bench
