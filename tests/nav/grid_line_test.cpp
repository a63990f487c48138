#include "barn/nav/grid_line.hpp"

#include <algorithm>
#include <cmath>
#include <cstdlib>
#include <utility>
#include <vector>

#include <gtest/gtest.h>

namespace barn::nav {
namespace {

std::vector<std::pair<int, int>> cellsOf(int x0, int y0, int x1, int y1, int max_steps) {
  std::vector<std::pair<int, int>> cells;
  walkLine(x0, y0, x1, y1, max_steps, [&](int x, int y) {
    cells.emplace_back(x, y);
    return true;
  });
  return cells;
}

TEST(GridLine, WalksTheDominantAxisOneCellPerStepWithBothEnds) {
  // (0,0) -> (4,2): error starts at 4/2 = 2; each x step adds 2 and a y step happens when it
  // reaches 4: y steps after x = 1 and x = 3.
  const auto cells = cellsOf(0, 0, 4, 2, 100);
  const std::vector<std::pair<int, int>> expected = {{0, 0}, {1, 1}, {2, 1}, {3, 2}, {4, 2}};
  EXPECT_EQ(cells, expected);
}

TEST(GridLine, IsFourOrEightConnectedAndEndsAtTheEndCellInEveryOctant) {
  for (int x1 = -7; x1 <= 7; ++x1) {
    for (int y1 = -7; y1 <= 7; ++y1) {
      const auto cells = cellsOf(0, 0, x1, y1, 100);
      ASSERT_EQ(cells.front(), std::make_pair(0, 0));
      ASSERT_EQ(cells.back(), std::make_pair(x1, y1));
      ASSERT_EQ(static_cast<int>(cells.size()), std::max(std::abs(x1), std::abs(y1)) + 1);
      for (std::size_t i = 1; i < cells.size(); ++i) {
        ASSERT_LE(std::abs(cells[i].first - cells[i - 1].first), 1);
        ASSERT_LE(std::abs(cells[i].second - cells[i - 1].second), 1);
      }
    }
  }
}

TEST(GridLine, AStepLimitStopsTheWalkEarly) {
  // A 100-cell ray limited to 60 cells of Euclidean length: along an axis, 60 steps, 61 cells.
  EXPECT_EQ(rayStepLimit(0, 0, 100, 0, 60.0), 60);
  const auto cells = cellsOf(0, 0, 100, 0, rayStepLimit(0, 0, 100, 0, 60.0));
  EXPECT_EQ(cells.size(), 61u);
  EXPECT_EQ(cells.back(), std::make_pair(60, 0));
  // Diagonal (100, 100): length 141.4, scale 60 / 141.4 = 0.4243, 42 steps.
  EXPECT_EQ(rayStepLimit(0, 0, 100, 100, 60.0), 42);
}

TEST(GridLine, AStepLimitIsCostmap2dsScaledDominantAxisForEveryRay) {
  // costmap_2d: the dominant-axis length times min(1, max_cells / Euclidean length); rays at,
  // just under and over the limit, whole and fractional limits.
  for (const double max_cells : {60.0, 7.0, 5.5, 1.0}) {
    for (int dx = -70; dx <= 70; ++dx)
      for (int dy = -70; dy <= 70; ++dy) {
        const double length = std::hypot(static_cast<double>(dx), static_cast<double>(dy));
        const double scale = length == 0.0 ? 1.0 : std::min(1.0, max_cells / length);
        const int expected = static_cast<int>(scale * std::max(std::abs(dx), std::abs(dy)));
        ASSERT_EQ(rayStepLimit(3, -2, 3 + dx, -2 + dy, max_cells), expected) << dx << ", " << dy << " limit " << max_cells;
      }
  }
}

TEST(GridLine, TheFlatWalkVisitsTheSameCellsInTheSameOrder) {
  // Every segment between two cells of a 9 x 7 grid, with and without a step limit.
  const int width = 9, height = 7;
  for (int a = 0; a < width * height; ++a) {
    for (int b = 0; b < width * height; ++b) {
      const int x0 = a % width, y0 = a / width, x1 = b % width, y1 = b / width;
      for (const int limit : {100, 3, 0}) {
        std::vector<std::pair<int, int>> flat;
        walkLineFlat(x0, y0, x1, y1, limit, width, [&](std::ptrdiff_t at) {
          flat.emplace_back(static_cast<int>(at % width), static_cast<int>(at / width));
        });
        ASSERT_EQ(flat, cellsOf(x0, y0, x1, y1, limit)) << "(" << x0 << ", " << y0 << ") -> (" << x1 << ", " << y1 << ")";
      }
    }
  }
}

}  // namespace
}  // namespace barn::nav
