#pragma once
/// The Jackal's configuration space on the BARN grid and its free regions
/// (GEN gen_world_ca.py, JackalMap).

#include <optional>
#include <vector>

#include "barn/core/grid.hpp"

namespace barn::generator {

/// A cell is blocked iff an obstacle lies in the 5 x 5 square centred on it (jackal_radius = 2
/// cells); off-map cells count as free.
core::Grid dilateCspace(const core::Grid& grid, int radius_cells = 2);

/// Labels of the 4-connected components of free cells: -1 for blocked cells, else 0, 1, ...
std::vector<int> labelFreeRegions(const core::Grid& cspace);

/// The free 4-connected region reachable from column `col`: among the regions touching that
/// column, the largest, the first one (lowest row) winning ties. Empty if the column is blocked.
struct Region {
  int label = -1;                  // component label from labelFreeRegions, -1 if none
  std::vector<int> open_rows;      // rows r (ascending) with (r, col) in the region
};
Region biggestRegionTouchingColumn(const core::Grid& cspace, const std::vector<int>& labels, int col);

/// Euclidean distance [cells] from every cell to the nearest blocked cell of `cspace`
/// (0 on blocked cells; 14.5, BARN's "nothing found" value, if no cell is blocked).
std::vector<double> distanceToBlocked(const core::Grid& cspace);

}  // namespace barn::generator
