#include "generator/cellular_automaton.hpp"

namespace barn::generator {

namespace {
constexpr int kFillThreshold = 5;   // a cell with at least this many filled neighbours fills
constexpr int kClearThreshold = 1;  // a cell with at most this many filled neighbours clears
}  // namespace

core::Grid randomFill(int rows, int cols, double fill_pct, core::Rng& rng) {
  core::Grid grid(rows, cols);
  for (int r = 0; r < rows; ++r) {
    for (int c = 0; c < cols; ++c) {
      if (r == 0 || r == rows - 1) {
        grid.at(r, c) = 1;
      } else {
        grid.at(r, c) = rng.uniform01() < fill_pct ? 1 : 0;
      }
    }
  }
  return grid;
}

int filledNeighbours(const core::Grid& grid, int r, int c) {
  int n = 0;
  for (int dr = -1; dr <= 1; ++dr) {
    for (int dc = -1; dc <= 1; ++dc) {
      if (dr == 0 && dc == 0) continue;
      const int nr = r + dr;
      const int nc = c + dc;
      if (nr < 0 || nr >= grid.rows()) {
        ++n;  // beyond the wall rows: solid, corners included
      } else if (nc >= 0 && nc < grid.cols()) {
        n += grid.at(nr, nc) != 0;
      }  // left/right of the map: open (the robot enters and leaves there)
    }
  }
  return n;
}

core::Grid smoothOnce(const core::Grid& grid) {
  core::Grid next = grid;  // synchronous: read the old grid, write the new one
  for (int r = 0; r < grid.rows(); ++r) {
    for (int c = 0; c < grid.cols(); ++c) {
      const int n = filledNeighbours(grid, r, c);
      if (n >= kFillThreshold) {
        next.at(r, c) = 1;
      } else if (n <= kClearThreshold) {
        next.at(r, c) = 0;
      }
    }
  }
  return next;
}

core::Grid cellularAutomatonMap(int rows, int cols, double fill_pct, int smooth_iter, core::Rng& rng) {
  core::Grid grid = randomFill(rows, cols, fill_pct, rng);
  for (int i = 0; i < smooth_iter; ++i) grid = smoothOnce(grid);
  return grid;
}

}  // namespace barn::generator
