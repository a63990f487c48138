#pragma once
/// The Clearpath Jackal's description: collision shape, drive limits, planning footprint,
/// traction and slip.
///
/// It lives in core, not sim, because controllers plan with the footprint and drive limits
/// (EpisodeInfo), and a controller must build without the simulator. sim::Simulator drives it.

#include <string>
#include <vector>

#include "barn/core/errors.hpp"
#include "barn/core/rect.hpp"

namespace barn::core {

/// Defaults are the Jackal in Gazebo (jackal_description, jackal_control).
struct RobotConfig {
  // Collision shape: the Gazebo collision geometry, projected to 2D.
  double chassis_length = 0.420;      // [m] chassis collision box, x
  double chassis_width = 0.310;       // [m] chassis collision box, y
  double wheel_length = 0.196;        // [m] wheel cylinder seen from above (2 x radius 0.098)
  double wheel_width = 0.040;         // [m]
  double wheel_offset_x = 0.131;      // [m] half the wheelbase
  double wheel_offset_y = 0.187795;   // [m] half the track
  double mass = 18.431;               // [kg] chassis 16.523 + 4 wheels x 0.477

  // Spec-sheet size: what controllers plan with. Larger than the collision shape.
  double footprint_length = 0.508;    // [m]
  double footprint_width = 0.430;     // [m]

  // diff_drive_controller limits (jackal_control/config/control.yaml).
  double max_linear_speed = 2.0;      // [m/s]
  double max_linear_accel = 20.0;     // [m/s^2]
  double max_angular_speed = 4.0;     // [rad/s]
  double max_angular_accel = 25.0;    // [rad/s^2]
  double cmd_timeout = 0.25;          // [s] the robot stops without a fresh command

  // Traction: wheel-ground friction bounds the body's acceleration. Gazebo combines the
  // wheels' mu 0.5 with the ground's by the minimum, so about 0.5 g: braking from 2 m/s slides.
  double traction_coefficient = 0.5;  // [-] friction coefficient mu
  double gravity = 9.81;              // [m/s^2]
  double max_angular_traction_accel = 40.0;  // [rad/s^2] yaw acceleration friction allows
                                             // (mu g m (track/2) / I_zz, about 40 for the Jackal)
  // Skid-steer turning: the yaw rate the body reaches per unit of the drive's turn set-point.
  // diff_drive_controller scales wheel speeds by wheel_separation_multiplier (1.5 on the
  // Jackal) to make up for the wheels' sideways slip; where the ground slips more or less than
  // that assumes, the robot turns slower or faster than commanded. 1 = as commanded.
  double turn_efficiency = 1.0;              // [-]
  // Skid-steer slip while turning: the body wanders sideways and forward as its four wheels
  // skid, a random velocity (first-order Gauss-Markov, per episode seed) whose standard
  // deviation grows with the yaw rate. 0 = the body turns about its centre exactly, a perfect
  // fixed point no real skid-steer base (nor Gazebo's) has; on by default because it improves
  // agreement with Gazebo (docs/fidelity.md), the value a guess of a few cm per turn, not fitted.
  double turn_slip_speed = 0.02;             // [m/s per rad/s] slip velocity stddev per unit yaw rate
  double turn_slip_time = 0.5;               // [s] correlation time of the slip
  // Skid-steer pivot: where along the body the instantaneous centre of rotation lies, ahead of
  // the centre. A skid-steer base turns about the axle that carries more weight (its wheels
  // grip sideways, the other axle's slide), so the centre slides sideways at -icr_offset x yaw
  // rate, which wheel odometry cannot see. 0 = turns about the centre. The default is the
  // rigid-contact limit for Gazebo's Jackal, whose centre of mass sits 1.2 cm ahead of the
  // centre: the front axle (0.131 m ahead). It gives DWA Gazebo-like collisions on dense
  // worlds (docs/fidelity.md); the learned policies are trained on this plant.
  double icr_offset = 0.131;                 // [m]

  template <class V> void visit(V& v) {
    v("chassis_length", chassis_length); v("chassis_width", chassis_width);
    v("wheel_length", wheel_length); v("wheel_width", wheel_width);
    v("wheel_offset_x", wheel_offset_x); v("wheel_offset_y", wheel_offset_y); v("mass", mass);
    v("footprint_length", footprint_length); v("footprint_width", footprint_width);
    v("max_linear_speed", max_linear_speed); v("max_linear_accel", max_linear_accel);
    v("max_angular_speed", max_angular_speed); v("max_angular_accel", max_angular_accel);
    v("cmd_timeout", cmd_timeout); v("traction_coefficient", traction_coefficient); v("gravity", gravity);
    v("max_angular_traction_accel", max_angular_traction_accel); v("turn_efficiency", turn_efficiency);
    v("turn_slip_speed", turn_slip_speed); v("turn_slip_time", turn_slip_time); v("icr_offset", icr_offset);
  }

  /// The five collision rectangles: chassis and four wheels.
  std::vector<Rect> collisionRects() const;
  /// Largest distance from the robot centre to any point of the collision shape. [m]
  double collisionRadius() const;
};

/// Records every out-of-range field of `config` (prefix: the config's key path).
void validate(const RobotConfig& config, Errors& errors, const std::string& prefix = "robot");

}  // namespace barn::core
