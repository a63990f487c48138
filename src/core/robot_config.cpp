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
  core::validateFields(c, errors, prefix);
}

}  // namespace barn::core
