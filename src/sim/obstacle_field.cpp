#include "barn/sim/obstacle_field.hpp"

#include "barn/core/world_geometry.hpp"

namespace barn::sim {

ObstacleField ObstacleField::fromWorld(const core::WorldSpec& world) {
  return {core::allCylinders(world.grid), core::kCylinderRadius};
}

}  // namespace barn::sim
