#pragma once
/// The unit direction of each beam of a scan in the sensor frame: the cosine and sine of its
/// angle. They are the same for every scan of one sensor, so they are computed for a scan
/// layout (first angle, increment, beam count) once, and again only when the layout changes,
/// as laser_geometry caches them.

#include <cmath>
#include <cstddef>
#include <vector>

#include "barn/core/types.hpp"

namespace barn::core {

class BeamDirections {
 public:
  /// Brings the table to `scan`'s layout (a no-op while it is the same).
  void update(const LaserScan& scan) {
    if (cos_.size() == scan.ranges.size() && angle_min_ == scan.angle_min && angle_increment_ == scan.angle_increment) return;
    cos_.resize(scan.ranges.size());
    sin_.resize(scan.ranges.size());
    for (std::size_t i = 0; i < scan.ranges.size(); ++i) {
      cos_[i] = std::cos(scan.angle(i));
      sin_[i] = std::sin(scan.angle(i));
    }
    angle_min_ = scan.angle_min;
    angle_increment_ = scan.angle_increment;
  }
  double cos(std::size_t beam) const { return cos_[beam]; }
  double sin(std::size_t beam) const { return sin_[beam]; }

 private:
  std::vector<double> cos_, sin_;
  double angle_min_ = 0.0, angle_increment_ = 0.0;
};

}  // namespace barn::core
