#pragma once
/// BARN's cellular-automaton obstacle maps (GEN gen_world_ca.py, ObstacleMap).

#include "barn/core/grid.hpp"
#include "barn/core/rng.hpp"

namespace barn::generator {

/// Random initial fill: the first and last rows are walls (no number is drawn for them);
/// every other cell, in row-major order, is filled iff uniform01() < fill_pct.
core::Grid randomFill(int rows, int cols, double fill_pct, core::Rng& rng);

/// Number of filled cells among the 8 neighbours of (r, c) under BARN's asymmetric
/// out-of-map rule: neighbours above the first or below the last row count as filled,
/// neighbours left or right of the map (row in range) count as empty.
int filledNeighbours(const core::Grid& grid, int r, int c);

/// One synchronous smoothing pass: >= 5 filled neighbours -> 1, <= 1 -> 0, else unchanged.
core::Grid smoothOnce(const core::Grid& grid);

/// randomFill followed by `smooth_iter` smoothing passes.
core::Grid cellularAutomatonMap(int rows, int cols, double fill_pct, int smooth_iter, core::Rng& rng);

}  // namespace barn::generator
