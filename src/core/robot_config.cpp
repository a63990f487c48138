#include "barn/core/robot_config.hpp"

#include <algorithm>
#include <cmath>

#include "barn/core/text_io.hpp"

namespace barn::core {

std::vector<Rect> RobotConfig::collisionRects() const {
  std::vector<Rect> rects;
  rects.push_back(Rect::centred(chassis_length, chassis_width));
  for (double sx : {1.0, -1.0})
    for (double sy : {1.0, -1.0})
      rects.push_back(Rect::around(sx * wheel_offset_x, sy * wheel_offset_y, wheel_length / 2, wheel_width / 2));
  return rects;
}

double RobotConfig::collisionRadius() const {
  double radius = 0.0;
  for (const Rect& r : collisionRects())
    radius = std::max(radius, r.farthestCornerDistance());
  return radius;
}

void validate(const RobotConfig& c, Errors& errors, const std::string& prefix) {
  // Each must be > 0, and at most `max`: a bound far beyond any ground robot (our choice), so
  // a typo like 1e9 is an error rather than a robot that crosses the field in one step.
  const auto positive = [&](double value, const char* field, double max) {
    if (errors.check(value > 0.0, prefix + "." + field, "must be > 0"))
      errors.check(value <= max, prefix + "." + field, "must be <= " + formatDouble(max));
  };
  positive(c.chassis_length, "chassis_length", 10.0);  // [m]
  positive(c.chassis_width, "chassis_width", 10.0);
  positive(c.wheel_length, "wheel_length", 10.0);
  positive(c.wheel_width, "wheel_width", 10.0);
  positive(c.mass, "mass", 10000.0);  // [kg]
  positive(c.footprint_length, "footprint_length", 10.0);
  positive(c.footprint_width, "footprint_width", 10.0);
  positive(c.max_linear_speed, "max_linear_speed", 20.0);          // [m/s] (Jackal: 2)
  positive(c.max_linear_accel, "max_linear_accel", 1000.0);        // [m/s^2]
  positive(c.max_angular_speed, "max_angular_speed", 100.0);       // [rad/s] (Jackal: 4)
  positive(c.max_angular_accel, "max_angular_accel", 10000.0);     // [rad/s^2]
  positive(c.cmd_timeout, "cmd_timeout", 100.0);                   // [s] (an episode's length)
  positive(c.traction_coefficient, "traction_coefficient", 10.0);  // [-]
  positive(c.gravity, "gravity", 100.0);                           // [m/s^2]
  positive(c.max_angular_traction_accel, "max_angular_traction_accel", 10000.0);  // [rad/s^2]
  errors.check(c.turn_slip_speed >= 0.0 && c.turn_slip_speed <= 1.0, prefix + ".turn_slip_speed", "must be in [0, 1]");
  errors.check(c.turn_slip_time > 0.0, prefix + ".turn_slip_time", "must be > 0");
  errors.check(std::abs(c.icr_offset) <= 0.5, prefix + ".icr_offset", "must be in [-0.5, 0.5]");
  errors.check(c.turn_efficiency > 0.0 && c.turn_efficiency <= 2.0, prefix + ".turn_efficiency", "must be in (0, 2]");
  errors.check(c.wheel_offset_x >= 0.0, prefix + ".wheel_offset_x", "must be >= 0");
  errors.check(c.wheel_offset_y >= 0.0, prefix + ".wheel_offset_y", "must be >= 0");
}

}  // namespace barn::core
