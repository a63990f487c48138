#include "generator/barn_astar.hpp"

#include <cstdlib>

#include <gtest/gtest.h>

#include "test_grids.hpp"

namespace barn::generator {
namespace {

int moveDirection(core::Cell a, core::Cell b) {
  constexpr int kMoves[8][2] = {{0, 1}, {1, 1}, {1, 0}, {1, -1}, {0, -1}, {-1, -1}, {-1, 0}, {-1, 1}};
  for (int k = 0; k < 8; ++k)
    if (b.row - a.row == kMoves[k][0] && b.col - a.col == kMoves[k][1]) return k;
  return -1;
}

TEST(BarnAStar, StraightCorridorGivesTheStraightPathWithTheStartTwice) {
  const core::Grid cspace = test::gridFromRows({
      "########",
      "........",
      "########",
  });
  const auto path = barnAStar(cspace, {1, 0}, {1, 7});
  ASSERT_TRUE(path);
  // start duplicated + 8 cells of the corridor = 9 entries
  ASSERT_EQ(path->size(), 9u);
  EXPECT_EQ((*path)[0], (core::Cell{1, 0}));
  EXPECT_EQ((*path)[1], (core::Cell{1, 0}));
  for (int c = 0; c < 8; ++c) EXPECT_EQ((*path)[static_cast<std::size_t>(c + 1)], (core::Cell{1, c}));
}

TEST(BarnAStar, ReturnsNoPathWhenGoalIsWalledIn) {
  const core::Grid cspace = test::gridFromRows({
      "......",
      "....##",
      "....#.",
      "....##",
  });
  EXPECT_FALSE(barnAStar(cspace, {0, 0}, {2, 5}));
}

TEST(BarnAStar, RefusesADiagonalSqueezeBetweenTwoBlockedCells) {
  // The only link between the halves is the diagonal (1,1)->(2,2) whose side cells (1,2) and
  // (2,1) are both blocked.
  const core::Grid cspace = test::gridFromRows({
      "..###",
      "..###",
      "##...",
      "##...",
  });
  EXPECT_FALSE(barnAStar(cspace, {0, 0}, {3, 4}));
}

TEST(BarnAStar, AllowsADiagonalWithOneFreeSideCell) {
  const core::Grid cspace = test::gridFromRows({
      "..###",
      "...##",
      "##...",
      "##...",
  });
  EXPECT_TRUE(barnAStar(cspace, {0, 0}, {3, 4}));
}

TEST(BarnAStar, NeverTurnsMoreThanFortyFiveDegrees) {
  core::Grid cspace(20, 20);
  for (int r = 0; r < 15; ++r) cspace.at(r, 10) = 1;  // a wall to get around
  const auto path = barnAStar(cspace, {2, 2}, {2, 17});
  ASSERT_TRUE(path);
  for (std::size_t i = 3; i < path->size(); ++i) {
    const int a = moveDirection((*path)[i - 2], (*path)[i - 1]);
    const int b = moveDirection((*path)[i - 1], (*path)[i]);
    const int turn = std::abs(a - b);
    EXPECT_TRUE(turn <= 1 || turn == 7) << "turn of " << turn * 45 << " degrees at step " << i;
  }
}

TEST(BarnAStar, TurnLimitCanMakeAReachableGoalUnreachable) {
  // The goal is reachable through a one-cell corridor that bends twice by 90 degrees; the
  // 45-degree limit forbids both bends. BARN discards such worlds.
  const core::Grid hook = test::gridFromRows({
      "######",
      "#....#",
      "####.#",
      "#....#",
      "######",
  });
  // From (1,1) east to (1,4), south to (3,4), then west back to (3,1): two 90-degree turns in
  // one-cell corridors.
  EXPECT_FALSE(barnAStar(hook, {1, 1}, {3, 1}));
}

}  // namespace
}  // namespace barn::generator
