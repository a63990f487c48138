#include "barn/nav/costmap.hpp"

#include <cmath>
#include <limits>

#include <gtest/gtest.h>

namespace barn::nav {
namespace {

constexpr double kInf = std::numeric_limits<double>::infinity();

// A 9-beam scan over +-0.4 rad with every beam at `range` except beam 4 (straight ahead).
core::LaserScan scanAhead(double ahead, double others = kInf) {
  core::LaserScan scan;
  scan.angle_min = -0.4;
  scan.angle_increment = 0.1;
  scan.range_min = 0.1;
  scan.range_max = 30.0;
  scan.ranges.assign(9, others);
  scan.ranges[4] = ahead;
  return scan;
}

CostmapConfig smallMap() {
  CostmapConfig c;
  c.width = 6.0;
  c.height = 6.0;
  c.origin_x = -3.0;
  c.origin_y = -3.0;
  return c;
}

TEST(Costmap, MarksAReturnWithinObstacleRange) {
  Costmap map(smallMap());
  map.integrateScan(scanAhead(1.0), {0.0, 0.0, 0.0}, {0.0, 0.0});
  CellIndex cell;
  ASSERT_TRUE(map.toCell({1.0, 0.0}, cell));
  EXPECT_TRUE(map.isObstacle(cell.x, cell.y));
  EXPECT_EQ(map.costAt({1.0, 0.0}), kLethalCost);
  EXPECT_EQ(map.costAt({0.5, 0.0}), kFreeCost);  // the ray's cells stay free
}

TEST(Costmap, IgnoresReturnsBeyondObstacleRange) {
  Costmap map(smallMap());
  map.integrateScan(scanAhead(2.7), {0.0, 0.0, 0.0}, {0.0, 0.0});  // 2.7 m > 2.5 m
  EXPECT_EQ(map.costAt({2.7, 0.0}), kFreeCost);
}

TEST(Costmap, RayTraceClearingRemovesAnObstacleThatMoved) {
  Costmap map(smallMap());
  map.integrateScan(scanAhead(1.0), {0.0, 0.0, 0.0}, {0.0, 0.0});
  ASSERT_EQ(map.costAt({1.0, 0.0}), kLethalCost);
  // The obstacle moved away: the beam now returns at 2.0 m and its ray clears 1.0 m.
  map.integrateScan(scanAhead(2.0), {0.0, 0.0, 0.0}, {0.0, 0.0});
  EXPECT_EQ(map.costAt({1.0, 0.0}), kFreeCost);
  EXPECT_EQ(map.costAt({2.0, 0.0}), kLethalCost);
  // No return at all clears up to the 3 m raytrace range.
  map.integrateScan(scanAhead(kInf), {0.0, 0.0, 0.0}, {0.0, 0.0});
  EXPECT_EQ(map.costAt({2.0, 0.0}), kFreeCost);
}

TEST(Costmap, InflationCostFollowsTheExponentialDecay) {
  CostmapConfig c = smallMap();  // inscribed 0.265 m, inflation 0.30 m, scaling 10
  Costmap map(c);
  // 252 exp(-10 (0.28 - 0.265)) = 252 exp(-0.15) = 216.9 -> 216
  EXPECT_EQ(map.inflationCost(0.28), 216);
  EXPECT_EQ(map.inflationCost(0.2), kInscribedCost);
  EXPECT_EQ(map.inflationCost(0.31), kFreeCost);
  EXPECT_EQ(map.inflationCost(0.0), kLethalCost);
}

TEST(Costmap, InflatesAroundAnObstacleAtKnownDistances) {
  CostmapConfig c = smallMap();
  c.inscribed_radius = 0.1;
  c.inflation_radius = 0.5;
  c.cost_scaling_factor = 3.0;
  Costmap map(c);
  map.integrateScan(scanAhead(1.0), {0.0, 0.0, 0.0}, {0.0, 0.0});
  CellIndex hit;
  ASSERT_TRUE(map.toCell({1.0, 0.0}, hit));
  // Cell centres 4 cells (0.2 m) and 8 cells (0.4 m) away along y.
  // 0.2 m: 252 exp(-3 * 0.1) = 186.7 -> 186; 0.4 m: 252 exp(-3 * 0.3) = 102.5 -> 102.
  EXPECT_EQ(map.cost(hit.x, hit.y + 4), 186);
  EXPECT_EQ(map.cost(hit.x, hit.y - 8), 102);
  EXPECT_EQ(map.cost(hit.x + 2, hit.y), kInscribedCost);   // 0.1 m: inscribed
  EXPECT_EQ(map.cost(hit.x, hit.y + 11), kFreeCost);       // 0.55 m: beyond the radius
  // 3-4-5 cells: exactly 5 cells = 0.25 m -> 252 exp(-0.45) = 160.7 -> 160
  EXPECT_EQ(map.cost(hit.x + 3, hit.y + 4), 160);
}

TEST(Costmap, ClearingAnObstacleRemovesItsInflation) {
  Costmap map(smallMap());
  map.integrateScan(scanAhead(1.0), {0.0, 0.0, 0.0}, {0.0, 0.0});
  EXPECT_GT(map.costAt({1.0, 0.2}), kFreeCost);
  map.integrateScan(scanAhead(2.0), {0.0, 0.0, 0.0}, {0.0, 0.0});
  EXPECT_EQ(map.costAt({1.0, 0.2}), kFreeCost);
}

TEST(Costmap, RollingWindowKeepsObstaclesSeenEarlierWhileTheyStayInside) {
  CostmapConfig c;
  c.rolling = true;  // 10 x 10 m around the robot
  Costmap map(c);
  map.integrateScan(scanAhead(1.0), {0.0, 0.0, 0.0}, {0.0, 0.0});
  // The robot drives 3 m away, facing away: the LiDAR no longer sees the obstacle.
  map.recentre({-3.0, 0.0});
  EXPECT_EQ(map.costAt({1.0, 0.0}), kLethalCost);
  // 7 m away the obstacle has left the window and is forgotten.
  map.recentre({-7.0, 0.0});
  map.recentre({0.0, 0.0});
  EXPECT_EQ(map.costAt({1.0, 0.0}), kFreeCost);
}

TEST(Costmap, TracksUnknownSpaceWhenAsked) {
  CostmapConfig c = smallMap();
  c.track_unknown = true;
  Costmap map(c);
  EXPECT_EQ(map.costAt({2.0, 2.0}), kUnknownCost);
  map.integrateScan(scanAhead(1.0), {0.0, 0.0, 0.0}, {0.0, 0.0});
  EXPECT_EQ(map.costAt({0.5, 0.0}), kFreeCost);
  EXPECT_EQ(map.costAt({2.0, 2.0}), kUnknownCost);
}

TEST(Costmap, ClearOutsideForgetsDistantObstacles) {
  Costmap map(smallMap());
  map.integrateScan(scanAhead(2.0), {0.0, 0.0, 0.0}, {0.0, 0.0});
  map.clearOutside({0.0, 0.0}, 1.5);
  EXPECT_EQ(map.costAt({2.0, 0.0}), kFreeCost);
}

}  // namespace
}  // namespace barn::nav
