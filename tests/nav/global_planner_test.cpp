#include "barn/nav/global_planner.hpp"

#include <limits>
#include <map>

#include <gtest/gtest.h>

#include "barn/core/rng.hpp"

#include "picture_map.hpp"

namespace barn::nav {
namespace {

// Exhaustive check: Bellman-Ford relaxation over every cell until nothing changes, with the
// planner's own step costs. Slow but obviously correct.
std::int64_t bruteForceCost(const GlobalPlanner& planner, const Costmap& map, CellIndex s, CellIndex g) {
  const int w = map.widthCells(), h = map.heightCells();
  constexpr std::int64_t kInf = std::numeric_limits<std::int64_t>::max() / 4;
  std::vector<std::int64_t> d(static_cast<std::size_t>(w * h), kInf);
  d[static_cast<std::size_t>(s.y * w + s.x)] = 0;
  const auto passable = [&](int x, int y) { return planner.stepCost(map.cost(x, y), false) >= 0; };
  bool changed = true;
  while (changed) {
    changed = false;
    for (int y = 0; y < h; ++y)
      for (int x = 0; x < w; ++x) {
        const std::int64_t here = d[static_cast<std::size_t>(y * w + x)];
        if (here >= kInf || (!passable(x, y) && !(CellIndex{x, y} == s))) continue;
        for (int dx = -1; dx <= 1; ++dx)
          for (int dy = -1; dy <= 1; ++dy) {
            if (dx == 0 && dy == 0) continue;
            const int nx = x + dx, ny = y + dy;
            if (nx < 0 || ny < 0 || nx >= w || ny >= h || !passable(nx, ny)) continue;
            const bool diagonal = dx != 0 && dy != 0;
            if (diagonal && (!passable(nx, y) || !passable(x, ny))) continue;
            const std::int64_t candidate = here + planner.stepCost(map.cost(nx, ny), diagonal);
            std::int64_t& there = d[static_cast<std::size_t>(ny * w + nx)];
            if (candidate < there) {
              there = candidate;
              changed = true;
            }
          }
      }
  }
  return d[static_cast<std::size_t>(g.y * w + g.x)];
}

TEST(GlobalPlanner, StraightLineInAnEmptyMap) {
  const Costmap map = pictureMap({"......", "......", "......"});
  GlobalPlanner planner({});
  const Plan plan = planner.plan(map, {0.5, 1.5}, {5.5, 1.5});
  ASSERT_TRUE(plan.found);
  // 5 straight steps into free cells: 5 * round(10 * 50) = 2500.
  EXPECT_EQ(plan.cost, 2500);
  EXPECT_EQ(plan.path.size(), 6u);
  EXPECT_EQ(plan.path.front(), Eigen::Vector2d(0.5, 1.5));
  EXPECT_EQ(plan.path.back(), Eigen::Vector2d(5.5, 1.5));
}

TEST(GlobalPlanner, GoesAroundAWallAndMatchesExhaustiveSearch) {
  const Costmap map = pictureMap({
      "........",
      "...#....",
      "...#....",
      "...#....",
      "........",
  });
  GlobalPlanner planner({});
  const Plan plan = planner.plan(map, {0.5, 2.5}, {7.5, 2.5});
  ASSERT_TRUE(plan.found);
  EXPECT_EQ(plan.cost, bruteForceCost(planner, map, {0, 2}, {7, 2}));
  for (const auto& p : plan.path) EXPECT_NE(map.costAt(p), kLethalCost);
}

TEST(GlobalPlanner, MatchesExhaustiveSearchOnRandomCostMaps) {
  core::Rng rng(3);
  for (int trial = 0; trial < 20; ++trial) {
    std::vector<std::string> rows(7, std::string(9, '.'));
    for (auto& row : rows)
      for (char& ch : row) ch = rng.uniform01() < 0.2 ? '#' : '.';
    rows[3][0] = rows[3][8] = '.';
    const Costmap map = pictureMap(rows);
    GlobalPlanner planner({});
    const Plan plan = planner.plan(map, {0.5, 3.5}, {8.5, 3.5});
    const std::int64_t expected = bruteForceCost(planner, map, {0, 3}, {8, 3});
    if (expected >= std::numeric_limits<std::int64_t>::max() / 4) {
      EXPECT_FALSE(plan.found) << "trial " << trial;
    } else {
      ASSERT_TRUE(plan.found) << "trial " << trial;
      EXPECT_EQ(plan.cost, expected) << "trial " << trial;
    }
  }
}

TEST(GlobalPlanner, PrefersCheapCellsOverShortOnes) {
  // A direct route through inflated cells vs a detour through free ones.
  CostmapConfig c;
  c.resolution = 1.0;
  c.width = 5.0;
  c.height = 3.0;
  c.origin_x = 0.0;
  c.origin_y = 0.0;
  c.inscribed_radius = 0.5;
  c.inflation_radius = 1.2;
  c.cost_scaling_factor = 0.5;
  Costmap map(c);
  GlobalPlanner planner({});
  const Plan plan = planner.plan(map, {0.5, 1.5}, {4.5, 1.5});
  ASSERT_TRUE(plan.found);
  EXPECT_EQ(plan.cost, bruteForceCost(planner, map, {0, 1}, {4, 1}));
}

TEST(GlobalPlanner, FailsWhenTheGoalIsWalledIn) {
  const Costmap map = pictureMap({
      "......###",
      "......#..",
      "......###",
  });
  GlobalPlanner planner({});
  EXPECT_FALSE(planner.plan(map, {0.5, 1.5}, {7.5, 1.5}).found);
  EXPECT_FALSE(planner.plan(map, {0.5, 1.5}, {6.5, 1.5}).found);  // goal in an obstacle
}

TEST(GlobalPlanner, LeavesAStartInsideAnObstacle) {
  const Costmap map = pictureMap({".....", ".#...", "....."});
  GlobalPlanner planner({});
  const Plan plan = planner.plan(map, {1.5, 1.5}, {4.5, 1.5});
  ASSERT_TRUE(plan.found);
  EXPECT_EQ(plan.path.size(), 4u);
}

TEST(GlobalPlanner, ReusesTheFieldWhileTheMapIsUnchanged) {
  const Costmap map = pictureMap({"........", "...#....", "........"});
  GlobalPlanner planner({});
  ASSERT_TRUE(planner.plan(map, {0.5, 1.5}, {7.5, 1.5}).found);
  EXPECT_GT(planner.lastExpanded(), 0u);
  const Plan second = planner.plan(map, {1.5, 0.5}, {7.5, 1.5});
  ASSERT_TRUE(second.found);
  EXPECT_EQ(second.cost, bruteForceCost(planner, map, {1, 0}, {7, 1}));
}

}  // namespace
}  // namespace barn::nav
