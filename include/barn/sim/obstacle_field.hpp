#pragma once
/// The static obstacles of a world in the world frame: BARN's cylinders, all of one radius, or
/// circles of several radii (LfLH's hallucinated obstacles, see barn/learning/hallucination.hpp).

#include <vector>

#include <Eigen/Core>

#include "barn/core/world.hpp"

namespace barn::sim {

struct ObstacleField {
  std::vector<Eigen::Vector2d> centres;  // [m] cylinder centres (field and containment walls)
  double radius = 0.075;                 // [m] radius of every cylinder when `radii` is empty
  std::vector<double> radii;             // [m] per-centre radii (same length as centres), or empty

  /// True if the circles have their own radii (`radii` is used, `radius` is not).
  bool hasRadii() const { return !radii.empty(); }
  /// Radius of circle i. [m]
  double radiusOf(std::size_t i) const { return radii.empty() ? radius : radii[i]; }
  /// The largest radius of any circle (`radius` if there are none). [m]
  double maxRadius() const;

  /// Every cylinder BARN puts in the world's .world file (core::allCylinders).
  static ObstacleField fromWorld(const core::WorldSpec& world);
};

}  // namespace barn::sim
