#pragma once
/// The static obstacles of a world in the world frame: BARN's cylinders, all of one radius.

#include <vector>

#include <Eigen/Core>

#include "barn/core/world.hpp"

namespace barn::sim {

struct ObstacleField {
  std::vector<Eigen::Vector2d> centres;  // [m] cylinder centres (field and containment walls)
  double radius = 0.075;                 // [m]

  /// Every cylinder BARN puts in the world's .world file (core::allCylinders).
  static ObstacleField fromWorld(const core::WorldSpec& world);
};

}  // namespace barn::sim
