#include "barn/bench/odometry_drift.hpp"

#include <cmath>

namespace barn::bench {

void validate(const OdometryDriftConfig& c, core::Errors& errors, const std::string& prefix) {
  core::validateFields(c, errors, prefix);  // every rule is a field's range
}

DriftingOdometry::DriftingOdometry(const OdometryDriftConfig& config, const core::Pose2& start, std::uint64_t seed)
    : config_(config), noise_(seed), previous_(start), estimate_{0.0, 0.0, start.yaw} {
  speed_scale_ = 1.0 + config.speed_scale_stddev * noise_.normal();
  gyro_bias_ = config.gyro_bias_stddev * noise_.normal();
  turn_scale_ = 1.0 + config.turn_scale_stddev * noise_.normal();
}

void DriftingOdometry::update(const core::Pose2& now, double dt) {
  // The true motion of this step in the robot frame at its start.
  const double c = std::cos(previous_.yaw), s = std::sin(previous_.yaw);
  const double dx = now.x - previous_.x, dy = now.y - previous_.y;
  const double forward = c * dx + s * dy;
  const double sideways = -s * dx + c * dy;
  const double turn = core::wrapAngle(now.yaw - previous_.yaw);
  previous_ = now;
  // What the encoders and the gyro report, integrated (white noise of density q over dt
  // integrates to a displacement of standard deviation q sqrt(dt)).
  const double sqrt_dt = std::sqrt(dt);
  const double measured_forward = forward * speed_scale_ + config_.speed_noise_density * sqrt_dt * noise_.normal();
  const double measured_sideways = config_.see_sideways_slip ? sideways : 0.0;
  const double measured_turn = turn * turn_scale_ + gyro_bias_ * dt + config_.gyro_noise_density * sqrt_dt * noise_.normal();
  const double ec = std::cos(estimate_.yaw), es = std::sin(estimate_.yaw);
  estimate_.x += ec * measured_forward - es * measured_sideways;
  estimate_.y += es * measured_forward + ec * measured_sideways;
  estimate_.yaw = core::wrapAngle(estimate_.yaw + measured_turn);
}

}  // namespace barn::bench
