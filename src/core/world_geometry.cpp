#include "barn/core/world_geometry.hpp"

namespace barn::core {

Eigen::Vector2d cellCentre(Cell cell) {
  return {-4.425 + kBarnCellSize * cell.row, 5.175 + kBarnCellSize * cell.col};
}

bool hasCylinder(const Grid& grid, Cell cell) {
  if (!grid.at(cell)) return false;
  for (int dr = -1; dr <= 1; ++dr) {
    for (int dc = -1; dc <= 1; ++dc) {
      const int r = cell.row + dr;
      const int c = cell.col + dc;
      if (!grid.inBounds(r, c) || !grid.at(r, c)) return true;  // an open or off-map side shows
    }
  }
  return false;
}

std::vector<Eigen::Vector2d> fieldCylinders(const Grid& grid) {
  std::vector<Eigen::Vector2d> centres;
  for (int r = 0; r < grid.rows(); ++r) {
    for (int c = 0; c < grid.cols(); ++c) {
      if (hasCylinder(grid, {r, c})) centres.push_back(cellCentre({r, c}));
    }
  }
  return centres;
}

std::vector<Eigen::Vector2d> containmentCylinders() {
  // world_writer.py: 30 back-wall cylinders and 33 per side wall (contain_wall_length = 5 m).
  std::vector<Eigen::Vector2d> centres;
  for (int i = 0; i < kBarnGridSize; ++i) centres.emplace_back(-0.075 - kBarnCellSize * i, 0.075);
  for (int i = 0; i < 33; ++i) {
    const double y = 0.225 + kBarnCellSize * i;
    centres.emplace_back(-0.075, y);
    centres.emplace_back(-4.425, y);
  }
  return centres;
}

std::vector<Eigen::Vector2d> allCylinders(const Grid& grid) {
  std::vector<Eigen::Vector2d> centres = containmentCylinders();
  const std::vector<Eigen::Vector2d> field = fieldCylinders(grid);
  centres.insert(centres.end(), field.begin(), field.end());
  return centres;
}

}  // namespace barn::core
