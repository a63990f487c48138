#include "barn/core/robot_config.hpp"

#include <algorithm>
#include <cmath>

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
  const auto positive = [&](double value, const char* field) {
    errors.check(value > 0.0, prefix + "." + field, "must be > 0");
  };
  positive(c.chassis_length, "chassis_length");
  positive(c.chassis_width, "chassis_width");
  positive(c.wheel_length, "wheel_length");
  positive(c.wheel_width, "wheel_width");
  positive(c.mass, "mass");
  positive(c.footprint_length, "footprint_length");
  positive(c.footprint_width, "footprint_width");
  positive(c.max_linear_speed, "max_linear_speed");
  positive(c.max_linear_accel, "max_linear_accel");
  positive(c.max_angular_speed, "max_angular_speed");
  positive(c.max_angular_accel, "max_angular_accel");
  positive(c.cmd_timeout, "cmd_timeout");
  positive(c.traction_coefficient, "traction_coefficient");
  positive(c.gravity, "gravity");
  positive(c.max_angular_traction_accel, "max_angular_traction_accel");
  errors.check(c.turn_slip_speed >= 0.0 && c.turn_slip_speed <= 1.0, prefix + ".turn_slip_speed", "must be in [0, 1]");
  errors.check(c.turn_slip_time > 0.0, prefix + ".turn_slip_time", "must be > 0");
  errors.check(std::abs(c.icr_offset) <= 0.5, prefix + ".icr_offset", "must be in [-0.5, 0.5]");
  errors.check(c.turn_efficiency > 0.0 && c.turn_efficiency <= 2.0, prefix + ".turn_efficiency", "must be in (0, 2]");
  errors.check(c.wheel_offset_x >= 0.0, prefix + ".wheel_offset_x", "must be >= 0");
  errors.check(c.wheel_offset_y >= 0.0, prefix + ".wheel_offset_y", "must be >= 0");
}

}  // namespace barn::core
