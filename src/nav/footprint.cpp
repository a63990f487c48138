#include "barn/nav/footprint.hpp"

#include <algorithm>
#include <limits>

namespace barn::nav {
namespace {

/// Distance from the origin to the segment a-b.
double distanceToSegment(const Eigen::Vector2d& a, const Eigen::Vector2d& b) {
  const Eigen::Vector2d d = b - a;
  const double length_squared = d.squaredNorm();
  const double t = length_squared > 0.0 ? std::clamp(-a.dot(d) / length_squared, 0.0, 1.0) : 0.0;
  const Eigen::Vector2d nearest = a + t * d;
  return nearest.norm();
}

}  // namespace

FootprintRadii footprintRadii(std::span<const Eigen::Vector2d> polygon) {
  if (polygon.empty()) return {};
  FootprintRadii radii{std::numeric_limits<double>::infinity(), 0.0};
  for (std::size_t i = 0; i < polygon.size(); ++i) {
    const Eigen::Vector2d& vertex = polygon[i];
    radii.circumscribed = std::max(radii.circumscribed, vertex.norm());
    radii.inscribed = std::min(radii.inscribed, distanceToSegment(vertex, polygon[(i + 1) % polygon.size()]));
  }
  return radii;
}

}  // namespace barn::nav
