#pragma once
// Builds small grids from inline pictures: '#' (or '1') blocked, anything else free.

#include <string>
#include <vector>

#include "barn/core/grid.hpp"

namespace barn::test {

inline core::Grid gridFromRows(const std::vector<std::string>& rows) {
  core::Grid grid(static_cast<int>(rows.size()), static_cast<int>(rows.front().size()));
  for (int r = 0; r < grid.rows(); ++r)
    for (int c = 0; c < grid.cols(); ++c) {
      const char ch = rows[static_cast<std::size_t>(r)][static_cast<std::size_t>(c)];
      grid.at(r, c) = (ch == '#' || ch == '1') ? 1 : 0;
    }
  return grid;
}

/// A 30 x 30 BARN grid with only the wall rows 0 and 29 filled.
inline core::Grid emptyBarnGrid() {
  core::Grid grid(core::kBarnGridSize, core::kBarnGridSize);
  for (int c = 0; c < core::kBarnGridSize; ++c) {
    grid.at(0, c) = 1;
    grid.at(core::kBarnGridSize - 1, c) = 1;
  }
  return grid;
}

}  // namespace barn::test
