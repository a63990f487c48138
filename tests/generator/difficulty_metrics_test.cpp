#include "generator/difficulty_metrics.hpp"

#include <cmath>

#include <gtest/gtest.h>

#include "test_grids.hpp"

namespace barn::generator {
namespace {

TEST(DifficultyMetrics, VisibilityCountsTheCellAndDropsDirectionsThatLeaveTheMap) {
  const core::Grid cspace = test::gridFromRows({
      "#######",
      "#.....#",
      "#.....#",
      "#######",
  });
  // From (1,1): east 5 free cells (cell included) then '#'; west 1; north 1; south 2;
  // NE: (1,1),(0,2)# -> 1; SE: (1,1),(2,2),(3,3)# -> 2; SW: (1,1),(2,0)# -> 1; NW: 1.
  // sum 14 over 8 directions -> floor(1.75) = 1.
  EXPECT_EQ(cellVisibility(cspace, {1, 1}), 1);
  const core::Grid open_right = test::gridFromRows({
      "###########",
      "#..........",
      "###########",
  });
  // From (1,1): east runs 10 cells and leaves the map, so it is dropped; the other 7
  // directions give 1 each -> 7 / 7 = 1. Keeping it would give (7 + 10) / 8 -> 2.
  EXPECT_EQ(cellVisibility(open_right, {1, 1}), 1);
}

TEST(DifficultyMetrics, VisibilityFloorsTheMeanLikePython2) {
  const core::Grid cspace = test::gridFromRows({
      "#########",
      "#.......#",
      "#########",
  });
  // From (1,1): east 7, west 1, north 1, south 1, diagonals 1 each -> 14 / 8 = 1.75 -> 1.
  EXPECT_EQ(cellVisibility(cspace, {1, 1}), 1);
  // From (1,4): east 4, west 4, the other six 1 each -> 14 / 8 -> 1.
  EXPECT_EQ(cellVisibility(cspace, {1, 4}), 1);
}

TEST(DifficultyMetrics, DispersionIsZeroWithNoWallsAndCountsChanges) {
  const core::Grid open(15, 15);
  EXPECT_EQ(cellDispersion(open, {7, 7}), 0);  // every ray leaves the radius without a wall
  core::Grid one_wall(15, 15);
  one_wall.at(7, 8) = 1;  // hit by ray (0,1) only (the first ray, index 0)
  // rays: index 0 wall, all others free -> changes at 15->0 and 0->1 = 2
  EXPECT_EQ(cellDispersion(one_wall, {7, 7}), 2);
  EXPECT_EQ(cellDispersion(one_wall, {7, 8}), -1);  // a blocked cell
}

TEST(DifficultyMetrics, DispersionRaysWithMinusTwoTakeThreeSteps) {
  // Ray (1,-2) from (7,14): steps land on (8,12), (9,10), (10,8). With the literal "+2" rule
  // a -2 component adds 1 per step, so the ray reaches the third cell; ray (1,2) from (7,0)
  // stops after two steps and never sees (10,6).
  core::Grid minus(15, 15);
  minus.at(10, 8) = 1;
  EXPECT_EQ(cellDispersion(minus, {7, 14}), 2);
  core::Grid plus(15, 15);
  plus.at(10, 6) = 1;
  EXPECT_EQ(cellDispersion(plus, {7, 0}), 0);
}

TEST(DifficultyMetrics, CharacteristicDimensionIsTheNarrowestAxis) {
  const core::Grid cspace = test::gridFromRows({
      "#########",
      "#.......#",
      "#.......#",
      "#########",
  });
  // At (1,3): vertical axis 0 up + 1 down = 1; horizontal 2 + 4 = 6; diagonals
  // (1,1): down-right (2,4) then (3,5)# -> sqrt2, up-left (0,2)# -> 0 -> sqrt2;
  // (1,-1): down-left (2,2) -> sqrt2, up-right (0,4)# -> sqrt2 total. Minimum = 1.
  EXPECT_DOUBLE_EQ(cellCharacteristicDimension(cspace, {1, 3}), 1.0);
  EXPECT_DOUBLE_EQ(cellCharacteristicDimension(cspace, {0, 0}), -1.0);
}

TEST(DifficultyMetrics, TortuosityIsArcOverChord) {
  const std::vector<core::Cell> straight = {{3, 0}, {3, 0}, {3, 1}, {3, 2}, {3, 3}};
  EXPECT_DOUBLE_EQ(tortuosity(straight), 1.0);
  // (0,0) -> (1,1) -> (2,0): arc 2 sqrt2, chord 2 -> sqrt2.
  const std::vector<core::Cell> bent = {{0, 0}, {1, 1}, {2, 0}};
  EXPECT_DOUBLE_EQ(tortuosity(bent), std::sqrt(2.0));
}

TEST(DifficultyMetrics, NormalisationUsesPopulationStd) {
  std::vector<core::DifficultyMetrics> set(2);
  set[0].closest_wall = 1.0;
  set[1].closest_wall = 3.0;
  const auto norm = metricsNormalisation(set);
  // mean 2, population std sqrt(((1-2)^2 + (3-2)^2) / 2) = 1 (the sample std would be sqrt2)
  EXPECT_DOUBLE_EQ(norm.mean.closest_wall, 2.0);
  EXPECT_DOUBLE_EQ(norm.std_dev.closest_wall, 1.0);
  EXPECT_DOUBLE_EQ(normaliseMetrics(set[1], norm).closest_wall, 1.0);
  EXPECT_DOUBLE_EQ(normaliseMetrics(set[1], norm).tortuosity, 0.0);  // no spread -> 0
}

}  // namespace
}  // namespace barn::generator
