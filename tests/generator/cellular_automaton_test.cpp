#include "generator/cellular_automaton.hpp"

#include <gtest/gtest.h>

#include "test_grids.hpp"

namespace barn::generator {
namespace {

TEST(CellularAutomaton, RandomFillKeepsWallRowsAndHitsTheFillFraction) {
  core::Rng rng(42);
  const core::Grid grid = randomFill(30, 30, 0.25, rng);
  for (int c = 0; c < 30; ++c) {
    EXPECT_EQ(grid.at(0, c), 1);
    EXPECT_EQ(grid.at(29, c), 1);
  }
  // 28 x 30 = 840 random cells; binomial sd = sqrt(840 * 0.25 * 0.75) = 12.5 cells, allow 5 sd.
  const int random_filled = grid.countFilled() - 60;
  EXPECT_NEAR(random_filled, 210, 63);
}

TEST(CellularAutomaton, SameSeedGivesSameMap) {
  core::Rng a(7), b(7), c(8);
  const core::Grid ga = cellularAutomatonMap(30, 30, 0.2, 3, a);
  EXPECT_EQ(ga, cellularAutomatonMap(30, 30, 0.2, 3, b));
  EXPECT_NE(ga, cellularAutomatonMap(30, 30, 0.2, 3, c));
}

TEST(CellularAutomaton, OutOfMapRowsCountAsFilledColumnsAsEmpty) {
  const core::Grid grid(3, 3);  // all free
  // Top-left corner: 3 neighbours above the map (filled), 2 left of the map (empty), 3 in the
  // map (free) -> 3.
  EXPECT_EQ(filledNeighbours(grid, 0, 0), 3);
  // Centre of the middle row: all 8 neighbours in the map -> 0.
  EXPECT_EQ(filledNeighbours(grid, 1, 1), 0);
  // Left end of the middle row: 3 neighbours off the left edge, all empty -> 0.
  EXPECT_EQ(filledNeighbours(grid, 1, 0), 0);
}

TEST(CellularAutomaton, SmoothingFillsAtFiveAndClearsAtOne) {
  const core::Grid grid = test::gridFromRows({
      ".......",
      ".##....",
      ".#.#...",
      ".###...",
      ".......",
      ".....#.",
      ".......",
  });
  const core::Grid next = smoothOnce(grid);
  EXPECT_EQ(next.at(2, 2), 1);  // 7 filled neighbours >= 5: fills
  EXPECT_EQ(next.at(5, 5), 0);  // 0 filled neighbours <= 1: clears
  EXPECT_EQ(next.at(1, 1), 1);  // 2 filled neighbours (2..4): unchanged (stays filled)
  EXPECT_EQ(next.at(2, 4), 0);  // 2 filled neighbours: unchanged (stays free)
}

TEST(CellularAutomaton, SmoothingIsSynchronous) {
  // Y = (2, 2) has 5 filled neighbours and fills. X = (2, 3) has 4 without Y: a synchronous pass
  // reads the old grid and leaves X free; an in-place pass would count the new Y and fill X.
  const core::Grid grid = test::gridFromRows({
      ".......",
      ".####..",
      ".#..#..",
      ".#.....",
      ".......",
      ".......",
      ".......",
  });
  const core::Grid next = smoothOnce(grid);
  EXPECT_EQ(next.at(2, 2), 1);
  EXPECT_EQ(next.at(2, 3), 0);
}

}  // namespace
}  // namespace barn::generator
