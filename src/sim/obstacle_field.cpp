#include "barn/sim/obstacle_field.hpp"

#include <algorithm>

#include "barn/core/world_geometry.hpp"

namespace barn::sim {

ObstacleField ObstacleField::fromWorld(const core::WorldSpec& world) {
  return {core::allCylinders(world.grid), core::kCylinderRadius, {}};
}

double ObstacleField::maxRadius() const {
  if (radii.empty()) return radius;
  return *std::max_element(radii.begin(), radii.end());
}

}  // namespace barn::sim
