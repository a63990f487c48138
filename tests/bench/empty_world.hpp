#pragma once
// Test helper shared by the episode and controller tests: a world without obstacles in the way.

#include "barn/core/world.hpp"

namespace barn::bench {

// An empty field: only the wall rows 0 and 29 (cylinders at x = -4.425 and x = -0.075), far
// from the robot's line x = -2 (or -2.25 for barn2024). The path runs along row 15.
inline core::WorldSpec emptyWorld(int id = 42) {
  core::WorldSpec w;
  w.id = id;
  w.grid = core::Grid(core::kBarnGridSize, core::kBarnGridSize);
  for (int c = 0; c < core::kBarnGridSize; ++c) w.grid.at(0, c) = w.grid.at(29, c) = 1;
  w.start_cell = {15, 0};
  w.goal_cell = {15, 29};
  w.path.push_back(w.start_cell);
  for (int c = 0; c < core::kBarnGridSize; ++c) w.path.push_back({15, c});
  return w;
}

}  // namespace barn::bench
