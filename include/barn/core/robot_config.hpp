#pragma once
/// The Clearpath Jackal's description: collision shape, drive limits, planning footprint,
/// traction and slip.
///
/// It lives in core, not sim, because controllers plan with the footprint and drive limits
/// (EpisodeInfo), and a controller must build without the simulator. sim::Simulator drives it.

#include <string>
#include <vector>

#include "barn/core/config.hpp"
#include "barn/core/errors.hpp"
#include "barn/core/rect.hpp"

namespace barn::core {

/// Defaults are the Jackal in Gazebo (jackal_description, jackal_control).
struct RobotConfig {
  // Collision shape: the Gazebo collision geometry, projected to 2D.
  double chassis_length = 0.420;
  double chassis_width = 0.310;
  double wheel_length = 0.196;
  double wheel_width = 0.040;
  double wheel_offset_x = 0.131;
  double wheel_offset_y = 0.187795;
  double mass = 18.431;

  // Spec-sheet size: what controllers plan with. Larger than the collision shape.
  double footprint_length = 0.508;
  double footprint_width = 0.430;

  // diff_drive_controller limits (jackal_control/config/control.yaml).
  double max_linear_speed = 2.0;
  double max_linear_accel = 20.0;
  double max_angular_speed = 4.0;
  double max_angular_accel = 25.0;
  double cmd_timeout = 0.25;

  // Traction: wheel-ground friction bounds the body's acceleration. Gazebo combines the
  // wheels' mu 0.5 with the ground's by the minimum, so about 0.5 g: braking from 2 m/s slides.
  double traction_coefficient = 0.5;
  double gravity = 9.81;
  double max_angular_traction_accel = 40.0;
  // Skid-steer turning: the yaw rate the body reaches per unit of the drive's turn set-point.
  // diff_drive_controller scales wheel speeds by wheel_separation_multiplier (1.5 on the
  // Jackal) to make up for the wheels' sideways slip; where the ground slips more or less than
  // that assumes, the robot turns slower or faster than commanded. 1 = as commanded.
  double turn_efficiency = 1.0;
  // Skid-steer slip while turning: the body wanders sideways and forward as its four wheels
  // skid, a random velocity (first-order Gauss-Markov, per episode seed) whose standard
  // deviation grows with the yaw rate. 0 = the body turns about its centre exactly, a perfect
  // fixed point no real skid-steer base (nor Gazebo's) has; on by default because it improves
  // agreement with Gazebo (docs/fidelity.md), the value a guess of a few cm per turn, not fitted.
  double turn_slip_speed = 0.02;
  double turn_slip_time = 0.5;
  // Skid-steer pivot: where along the body the instantaneous centre of rotation lies, ahead of
  // the centre. A skid-steer base turns about the axle that carries more weight (its wheels
  // grip sideways, the other axle's slide), so the centre slides sideways at -icr_offset x yaw
  // rate, which wheel odometry cannot see. 0 = turns about the centre. The default is the
  // rigid-contact limit for Gazebo's Jackal, whose centre of mass sits 1.2 cm ahead of the
  // centre: the front axle (0.131 m ahead). It gives DWA Gazebo-like collisions on dense
  // worlds (docs/fidelity.md); the learned policies are trained on this plant.
  double icr_offset = 0.131;

  // The upper bounds (our choice) lie far beyond any ground robot, so a typo like 1e9 is an
  // error rather than a robot that crosses the field in one step.
  template <class V> void visit(V& v) {
    v("chassis_length", chassis_length, {.unit = "m", .range = core::openClosed(0.0, 10.0), .doc = "chassis collision box, x"});
    v("chassis_width", chassis_width, {.unit = "m", .range = core::openClosed(0.0, 10.0), .doc = "chassis collision box, y"});
    v("wheel_length", wheel_length, {.unit = "m", .range = core::openClosed(0.0, 10.0), .doc = "wheel cylinder seen from above (2 x radius 0.098)"});
    v("wheel_width", wheel_width, {.unit = "m", .range = core::openClosed(0.0, 10.0)});
    v("wheel_offset_x", wheel_offset_x, {.unit = "m", .range = core::kNonNegative, .doc = "half the wheelbase"});
    v("wheel_offset_y", wheel_offset_y, {.unit = "m", .range = core::kNonNegative, .doc = "half the track"});
    v("mass", mass, {.unit = "kg", .range = core::openClosed(0.0, 10000.0), .doc = "chassis 16.523 + 4 wheels x 0.477"});
    v("footprint_length", footprint_length, {.unit = "m", .range = core::openClosed(0.0, 10.0)});
    v("footprint_width", footprint_width, {.unit = "m", .range = core::openClosed(0.0, 10.0)});
    v("max_linear_speed", max_linear_speed, {.unit = "m/s", .range = core::openClosed(0.0, 20.0)});
    v("max_linear_accel", max_linear_accel, {.unit = "m/s^2", .range = core::openClosed(0.0, 1000.0)});
    v("max_angular_speed", max_angular_speed, {.unit = "rad/s", .range = core::openClosed(0.0, 100.0)});
    v("max_angular_accel", max_angular_accel, {.unit = "rad/s^2", .range = core::openClosed(0.0, 10000.0)});
    v("cmd_timeout", cmd_timeout, {.unit = "s", .range = core::openClosed(0.0, 100.0), .doc = "the robot stops without a fresh command"});
    v("traction_coefficient", traction_coefficient, {.range = core::openClosed(0.0, 10.0), .doc = "friction coefficient mu"});
    v("gravity", gravity, {.unit = "m/s^2", .range = core::openClosed(0.0, 100.0)});
    v("max_angular_traction_accel", max_angular_traction_accel,
      {.unit = "rad/s^2",
       .range = core::openClosed(0.0, 10000.0),
       .doc = "yaw acceleration friction allows (mu g m (track/2) / I_zz, about 40 for the Jackal)"});
    v("turn_efficiency", turn_efficiency, {.range = core::openClosed(0.0, 2.0)});
    v("turn_slip_speed", turn_slip_speed,
      {.unit = "m/s per rad/s", .range = core::closed(0.0, 1.0), .doc = "slip velocity stddev per unit yaw rate"});
    v("turn_slip_time", turn_slip_time, {.unit = "s", .range = core::kPositive, .doc = "correlation time of the slip"});
    v("icr_offset", icr_offset, {.unit = "m", .range = core::closed(-0.5, 0.5)});
  }

  /// The five collision rectangles: chassis and four wheels.
  std::vector<Rect> collisionRects() const;
  /// Largest distance from the robot centre to any point of the collision shape. [m]
  double collisionRadius() const;
};

/// Records every out-of-range field of `config` (prefix: the config's key path).
void validate(const RobotConfig& config, Errors& errors, const std::string& prefix = "robot");

}  // namespace barn::core
