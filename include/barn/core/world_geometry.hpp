#pragma once
/// How a BARN grid becomes obstacles in the world frame (GEN world_writer.py, as in the
/// competition .world files): static cylinders of radius 0.075 m.

#include <vector>

#include <Eigen/Core>

#include "barn/core/grid.hpp"

namespace barn::core {

inline constexpr double kCylinderRadius = 0.075;  // [m]

/// Centre of obstacle cell (r, c) in the world frame: (-4.425 + 0.15 r, 5.175 + 0.15 c). [m]
Eigen::Vector2d cellCentre(Cell cell);

/// True if the filled cell gets a cylinder: BARN skips cells whose 8 neighbours are all
/// in the map and filled (blob interiors are hollow).
bool hasCylinder(const Grid& grid, Cell cell);

/// Cylinder centres of the obstacle field (grid rows 0 and 29 included). [m]
std::vector<Eigen::Vector2d> fieldCylinders(const Grid& grid);

/// Cylinder centres of the containment walls behind the field: the back wall at y = 0.075
/// (x = -0.075 ... -4.425) and the side walls at x = -0.075 and x = -4.425 (y = 0.225 ...
/// 5.025). The far (+y) side is open. [m]
std::vector<Eigen::Vector2d> containmentCylinders();

/// Field plus containment cylinders: every obstacle of the world.
std::vector<Eigen::Vector2d> allCylinders(const Grid& grid);

}  // namespace barn::core
