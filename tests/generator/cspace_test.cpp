#include "generator/cspace.hpp"

#include <cmath>

#include <gtest/gtest.h>

#include "test_grids.hpp"

namespace barn::generator {
namespace {

TEST(Cspace, DilatesEachObstacleToAFiveByFiveSquare) {
  core::Grid grid(9, 9);
  grid.at(4, 4) = 1;
  const core::Grid cspace = dilateCspace(grid);
  EXPECT_EQ(cspace.countFilled(), 25);
  EXPECT_EQ(cspace.at(2, 2), 1);
  EXPECT_EQ(cspace.at(6, 6), 1);
  EXPECT_EQ(cspace.at(1, 4), 0);
  EXPECT_EQ(cspace.at(4, 7), 0);
}

TEST(Cspace, WallRowsBlockThreeRowsOnEachSide) {
  const core::Grid cspace = dilateCspace(test::emptyBarnGrid());
  for (int c = 0; c < 30; ++c) {
    for (int r : {0, 1, 2, 27, 28, 29}) EXPECT_EQ(cspace.at(r, c), 1);
    for (int r = 3; r <= 26; ++r) EXPECT_EQ(cspace.at(r, c), 0);
  }
}

TEST(Cspace, RegionsAreFourConnected) {
  // The two free cells touch only diagonally: two regions.
  const core::Grid cspace = test::gridFromRows({
      ".#",
      "#.",
  });
  const std::vector<int> labels = labelFreeRegions(cspace);
  EXPECT_GE(labels[0], 0);
  EXPECT_GE(labels[3], 0);
  EXPECT_NE(labels[0], labels[3]);
  EXPECT_EQ(labels[1], -1);
}

TEST(Cspace, BiggestRegionTouchingAColumnWinsAndListsItsRows) {
  const core::Grid cspace = test::gridFromRows({
      "..#...",
      "######",
      "......",
      "......",
      "######",
  });
  const std::vector<int> labels = labelFreeRegions(cspace);
  const Region left = biggestRegionTouchingColumn(cspace, labels, 0);
  EXPECT_EQ(left.open_rows, (std::vector<int>{2, 3}));  // 12 cells beat the 2 cells of row 0
  const Region right = biggestRegionTouchingColumn(cspace, labels, 5);
  EXPECT_EQ(right.label, left.label);
}

TEST(Cspace, DistanceToBlockedIsEuclidean) {
  core::Grid cspace(10, 10);
  cspace.at(0, 0) = 1;
  const std::vector<double> d = distanceToBlocked(cspace);
  EXPECT_DOUBLE_EQ(d[0], 0.0);
  EXPECT_DOUBLE_EQ(d[3 * 10 + 4], 5.0);  // (3, 4): sqrt(9 + 16)
  EXPECT_DOUBLE_EQ(d[1 * 10 + 1], std::sqrt(2.0));
}

}  // namespace
}  // namespace barn::generator
