#include "barn/nav/global_planner.hpp"

#include <cmath>
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

// Exhaustive cost-to-goal field (Bellman-Ford toward the goal) and the steepest descent on it
// that the planner documents: from each cell to the neighbour with the least g + step; among
// equals the one with the least g, then the one pointing most nearly at the goal, then the
// first in the planner's direction order (straight +x, -x, +y, -y, then diagonals).
std::vector<CellIndex> bruteForceDescent(const GlobalPlanner& planner, const Costmap& map, CellIndex s, CellIndex g) {
  const int w = map.widthCells(), h = map.heightCells();
  constexpr std::int64_t kInf = std::numeric_limits<std::int64_t>::max() / 4;
  constexpr int kOrder[8][2] = {{1, 0}, {-1, 0}, {0, 1}, {0, -1}, {1, 1}, {1, -1}, {-1, 1}, {-1, -1}};
  const auto passable = [&](int x, int y) {
    return x >= 0 && y >= 0 && x < w && y < h && planner.stepCost(map.cost(x, y), false) >= 0;
  };
  const auto step = [&](int x, int y, int dir) -> std::int64_t {  // entering the neighbour, -1 if not allowed
    const int nx = x + kOrder[dir][0], ny = y + kOrder[dir][1];
    if (!passable(nx, ny)) return -1;
    const bool diagonal = dir >= 4;
    if (diagonal && (!passable(nx, y) || !passable(x, ny))) return -1;
    return planner.stepCost(map.cost(nx, ny), diagonal);
  };
  std::vector<std::int64_t> to_goal(static_cast<std::size_t>(w * h), kInf);
  to_goal[static_cast<std::size_t>(g.y * w + g.x)] = 0;
  for (bool changed = true; changed;) {
    changed = false;
    for (int y = 0; y < h; ++y)
      for (int x = 0; x < w; ++x)
        for (int dir = 0; dir < 8; ++dir) {
          const std::int64_t c = step(x, y, dir);
          const std::int64_t there = c < 0 ? kInf : to_goal[static_cast<std::size_t>((y + kOrder[dir][1]) * w + x + kOrder[dir][0])];
          std::int64_t& here = to_goal[static_cast<std::size_t>(y * w + x)];
          if (there < kInf && there + c < here) {
            here = there + c;
            changed = true;
          }
        }
  }
  std::vector<CellIndex> path;
  if (to_goal[static_cast<std::size_t>(s.y * w + s.x)] >= kInf) return path;
  for (CellIndex c = s;;) {
    path.push_back(c);
    if (c == g) return path;
    std::int64_t best = kInf, best_g = kInf;
    double best_cos = -2.0;
    CellIndex next = c;
    const double gx = g.x - c.x, gy = g.y - c.y;
    for (int dir = 0; dir < 8; ++dir) {
      const std::int64_t cost = step(c.x, c.y, dir);
      if (cost < 0) continue;
      const CellIndex n{c.x + kOrder[dir][0], c.y + kOrder[dir][1]};
      const std::int64_t there = to_goal[static_cast<std::size_t>(n.y * w + n.x)];
      const std::int64_t through = there + cost;
      const double cos = (kOrder[dir][0] * gx + kOrder[dir][1] * gy) /
                         (std::hypot(kOrder[dir][0], kOrder[dir][1]) * std::hypot(gx, gy));
      if (through < best || (through == best && (there < best_g || (there == best_g && cos > best_cos)))) {
        best = through;
        best_g = there;
        best_cos = cos;
        next = n;
      }
    }
    c = next;
  }
}

// Whether `plan` is the descent `expected` (empty: no path) point by point, with the first
// difference as the message.
::testing::AssertionResult isDescent(const Plan& plan, const std::vector<CellIndex>& expected, const Costmap& map) {
  if (plan.found != !expected.empty())
    return ::testing::AssertionFailure() << "found " << plan.found << ", the exhaustive search " << !expected.empty();
  if (plan.path.size() != expected.size())
    return ::testing::AssertionFailure() << plan.path.size() << " points, the exhaustive descent " << expected.size();
  for (std::size_t k = 0; k < expected.size(); ++k)
    if (plan.path[k] != map.cellCentre(expected[k])) return ::testing::AssertionFailure() << "point " << k << " differs";
  return ::testing::AssertionSuccess();
}

// A map of 1 m cells whose inflation (scaling 1) makes costs vary from cell to cell.
CostmapConfig inflatedMapConfig(int width, int height, double inflation_radius) {
  CostmapConfig c;
  c.resolution = 1.0;
  c.width = width;
  c.height = height;
  c.inflation_radius = inflation_radius;
  c.cost_scaling_factor = 1.0;
  return c;
}

// Marks an obstacle at p with probability `mark`, else clears the 3 x 3 m square around it.
void markOrClearAround(Costmap& map, core::Rng& rng, const Eigen::Vector2d& p, double mark) {
  if (rng.uniform01() < mark) map.markObstacle(p);
  else map.clearPolygon({p + Eigen::Vector2d(-1.5, -1.5), p + Eigen::Vector2d(1.5, -1.5), p + Eigen::Vector2d(1.5, 1.5),
                         p + Eigen::Vector2d(-1.5, 1.5)});
  map.update();
}

// The exhaustive descent, or none when the goal cannot be entered.
std::vector<CellIndex> expectedPath(const GlobalPlanner& planner, const Costmap& map, CellIndex start, CellIndex goal) {
  if (planner.stepCost(map.cost(goal.x, goal.y), false) < 0) return {};
  return bruteForceDescent(planner, map, start, goal);
}

// Such a map with random obstacles.
Costmap randomInflatedMap(core::Rng& rng, int width, int height, double obstacle_fraction) {
  Costmap map(inflatedMapConfig(width, height, 2.5), 0.0);
  for (int y = 0; y < height; ++y)
    for (int x = 0; x < width; ++x)
      if (rng.uniform01() < obstacle_fraction) map.markObstacle({x + 0.5, y + 0.5});
  map.update();
  return map;
}

TEST(GlobalPlanner, PathIsTheSteepestDescentOfTheExactField) {
  // The path depends on the costs, start and goal only, not on the order the search settled
  // cells in: it equals the descent on an exhaustively computed field, ties included (free
  // maps have many equal routes).
  core::Rng rng(11);
  for (int trial = 0; trial < 30; ++trial) {
    const Costmap map = randomInflatedMap(rng, 12, 9, trial % 3 == 0 ? 0.0 : 0.12);
    const CellIndex start{static_cast<int>(rng.uniform01() * 12), static_cast<int>(rng.uniform01() * 9)};
    const CellIndex goal{static_cast<int>(rng.uniform01() * 12), static_cast<int>(rng.uniform01() * 9)};
    GlobalPlanner planner({});
    if (planner.stepCost(map.cost(goal.x, goal.y), false) < 0) continue;
    const Plan plan = planner.plan(map, map.cellCentre(start), map.cellCentre(goal));
    const std::vector<CellIndex> expected = bruteForceDescent(planner, map, start, goal);
    ASSERT_TRUE(isDescent(plan, expected, map)) << "trial " << trial;
    // A later start on the path reuses the field and still gets the exhaustive descent.
    if (expected.size() > 2) {
      const CellIndex later = expected[expected.size() / 2];
      const Plan reused = planner.plan(map, map.cellCentre(later), map.cellCentre(goal));
      const std::vector<CellIndex> expected_later = bruteForceDescent(planner, map, later, goal);
      ASSERT_TRUE(isDescent(reused, expected_later, map)) << "trial " << trial;
    }
  }
}

TEST(GlobalPlanner, OnePlannerOnMapsOfOtherShapesMatchesExhaustiveSearch) {
  // The search keeps tables shaped like the last map (the heuristic by row and column
  // offset): one planner on 12 x 9, then 9 x 12 (padded 14 x 11 and 11 x 14, the same cell
  // count), then 20 x 6, must give the exhaustive descent on each.
  core::Rng rng(23);
  GlobalPlanner planner({});
  for (int trial = 0; trial < 18; ++trial) {
    const int shapes[3][2] = {{12, 9}, {9, 12}, {20, 6}};
    const int w = shapes[trial % 3][0], h = shapes[trial % 3][1];
    const Costmap map = randomInflatedMap(rng, w, h, 0.1);
    const CellIndex start{static_cast<int>(rng.uniform01() * w), static_cast<int>(rng.uniform01() * h)};
    const CellIndex goal{static_cast<int>(rng.uniform01() * w), static_cast<int>(rng.uniform01() * h)};
    if (planner.stepCost(map.cost(goal.x, goal.y), false) < 0) continue;
    const Plan plan = planner.plan(map, map.cellCentre(start), map.cellCentre(goal));
    const std::vector<CellIndex> expected = bruteForceDescent(planner, map, start, goal);
    ASSERT_TRUE(isDescent(plan, expected, map)) << "trial " << trial;
  }
}

TEST(GlobalPlanner, NavFnReusesAPlanOnlyWhenItWouldComputeTheSame) {
  // One NavFn planner through robot moves (within a cell, to the next, jumps) and obstacles
  // appearing and disappearing must plan what a new planner plans from scratch each time.
  core::Rng rng(31);
  PlannerConfig config;
  config.algorithm = PlannerAlgorithm::NavFn;
  // NavFn stops after max(cells / 20, width + height) cycles, so a small map must be mostly
  // free for it to reach the goal: a narrow inflation, a few obstacles.
  CostmapConfig c;
  c.resolution = 1.0;
  c.width = 40;
  c.height = 30;
  c.origin_x = c.origin_y = 0.0;
  c.inflation_radius = 1.5;
  c.cost_scaling_factor = 3.0;
  Costmap map(c, 0.0);
  for (int k = 0; k < 40; ++k) map.markObstacle({5.0 + rng.uniform01() * 28.0, 1.0 + rng.uniform01() * 28.0});
  GlobalPlanner planner(config);
  const Eigen::Vector2d goal(36.5, 15.3);
  map.clearPolygon({goal + Eigen::Vector2d(-2, -2), goal + Eigen::Vector2d(2, -2), goal + Eigen::Vector2d(2, 2),
                    goal + Eigen::Vector2d(-2, 2)});
  map.update();
  Eigen::Vector2d robot(3.2, 15.5);
  int reused_inputs = 0, found = 0;
  for (int step = 0; step < 300; ++step) {
    const double u = rng.uniform01();
    if (u < 0.4) robot += Eigen::Vector2d(0.2, rng.uniform01() - 0.5) * 0.25;  // usually the same cell
    else if (u < 0.5) robot = Eigen::Vector2d(2.0 + rng.uniform01() * 30.0, 2.0 + rng.uniform01() * 26.0);
    else if (u < 0.6) map.markObstacle({5.0 + rng.uniform01() * 28.0, 2.0 + rng.uniform01() * 26.0});
    else if (u < 0.7) {
      const Eigen::Vector2d p(5.0 + rng.uniform01() * 28.0, 2.0 + rng.uniform01() * 26.0);
      map.clearPolygon({p + Eigen::Vector2d(-1.5, -1.5), p + Eigen::Vector2d(1.5, -1.5), p + Eigen::Vector2d(1.5, 1.5),
                        p + Eigen::Vector2d(-1.5, 1.5)});
    } else {
      ++reused_inputs;  // nothing changed: the inputs of the last plan
    }
    map.update();
    const Plan kept = planner.plan(map, robot, goal);
    const Plan fresh = GlobalPlanner(config).plan(map, robot, goal);
    ASSERT_EQ(kept.found, fresh.found) << "step " << step;
    ASSERT_EQ(kept.cost, fresh.cost) << "step " << step;
    ASSERT_EQ(kept.path, fresh.path) << "step " << step;
    found += fresh.found ? 1 : 0;
  }
  EXPECT_GT(reused_inputs, 30);
  EXPECT_GT(found, 150);  // the comparison is about real plans
}

TEST(GlobalPlanner, RepairedFieldGivesTheExhaustivePathAfterMapChangesAndMoves) {
  // One planner on one costmap through a sequence of obstacles appearing and disappearing
  // and starts moving (along the path or jumping): the repaired field must give, every time,
  // the path and cost an exhaustive search gives on the map as it is then.
  core::Rng rng(5);
  for (int trial = 0; trial < 12; ++trial) {
    Costmap map(inflatedMapConfig(14, 10, 2.5), trial % 2 == 0 ? 0.0 : 1.0);
    GlobalPlanner planner({});
    const CellIndex goal{13, static_cast<int>(rng.uniform01() * 10)};
    CellIndex start{0, static_cast<int>(rng.uniform01() * 10)};
    for (int step = 0; step < 25; ++step) {
      const int changes = static_cast<int>(rng.uniform01() * 4);
      for (int k = 0; k < changes; ++k) {
        const Eigen::Vector2d p(rng.uniform01() * 14, rng.uniform01() * 10);
        if ((p - map.cellCentre(goal)).norm() < 1.0) continue;
        markOrClearAround(map, rng, p, 0.7);
      }
      const Plan plan = planner.plan(map, map.cellCentre(start), map.cellCentre(goal));
      const std::vector<CellIndex> expected = expectedPath(planner, map, start, goal);
      ASSERT_TRUE(isDescent(plan, expected, map)) << "trial " << trial << " step " << step;
      // Next start: a step or two along the path, or somewhere else.
      if (expected.size() > 3 && rng.uniform01() < 0.7) start = expected[1 + static_cast<std::size_t>(rng.uniform01() * 2)];
      else start = {static_cast<int>(rng.uniform01() * 14), static_cast<int>(rng.uniform01() * 10)};
    }
  }
}

TEST(GlobalPlanner, NewSearchKeepsTheFieldBeyondTheChangesAndGivesTheExhaustivePath) {
  // Many cells change at once near the start, as a scan changes the costmap around the robot,
  // so the planner searches again rather than repair, keeping the part of its last field the
  // changes cannot reach. Every plan must be the exhaustive descent, and the kept planner must
  // expand fewer cells than a new planner does on the same map.
  core::Rng rng(11);
  std::size_t kept_expanded = 0, new_expanded = 0;
  for (int trial = 0; trial < 8; ++trial) {
    Costmap map(inflatedMapConfig(24, 40, 3.5), trial % 2 == 0 ? 0.0 : 1.0);
    GlobalPlanner planner({});
    const CellIndex goal{static_cast<int>(rng.uniform01() * 24), 39};
    CellIndex start{static_cast<int>(rng.uniform01() * 24), 0};
    for (int step = 0; step < 20; ++step) {
      // Obstacles come and go within 6 cells of the start (now and then anywhere).
      const bool anywhere = rng.uniform01() < 0.15;
      for (int k = 0; k < 6; ++k) {
        const Eigen::Vector2d centre = anywhere ? Eigen::Vector2d(12.0, 20.0) : map.cellCentre(start);
        const double reach = anywhere ? 20.0 : 6.0;
        const Eigen::Vector2d p = centre + reach * Eigen::Vector2d(2 * rng.uniform01() - 1, 2 * rng.uniform01() - 1);
        if (p.x() < 0 || p.y() < 0 || p.x() >= 24 || p.y() >= 40 || (p - map.cellCentre(goal)).norm() < 1.5) continue;
        markOrClearAround(map, rng, p, 0.75);
      }
      const Plan plan = planner.plan(map, map.cellCentre(start), map.cellCentre(goal));
      const std::vector<CellIndex> expected = expectedPath(planner, map, start, goal);
      ASSERT_TRUE(isDescent(plan, expected, map)) << "trial " << trial << " step " << step;
      if (plan.found) {
        ASSERT_EQ(plan.cost, bruteForceCost(planner, map, start, goal)) << "trial " << trial << " step " << step;
      }
      GlobalPlanner fresh({});
      fresh.plan(map, map.cellCentre(start), map.cellCentre(goal));
      kept_expanded += planner.lastExpanded();
      new_expanded += fresh.lastExpanded();
      // The robot moves a few cells along the path.
      if (expected.size() > 4) start = expected[1 + static_cast<std::size_t>(rng.uniform01() * 3)];
    }
  }
  EXPECT_LT(kept_expanded, new_expanded * 3 / 4) << kept_expanded << " cells expanded, " << new_expanded << " by new planners";
}

TEST(GlobalPlanner, KeptFieldPlansAsAFreshOneWhileARobotRevealsAnObstacleField) {
  // The run's own case at its own scale: BARN's 6 x 15 m global costmap at 5 cm with LfLH's 5 m
  // inflation, a robot driving its own path through a field of 15 cm cylinders that it marks
  // as they come within 2.5 m, while returns it marked flicker out and back (the scan noise, so
  // costs fall as well as rise, near the robot and ahead of it). Small random maps miss what
  // this finds: a kept planner must plan exactly what a new one plans, at every replan.
  for (int trial = 0; trial < 6; ++trial) {
    core::Rng rng(7 + static_cast<std::uint64_t>(trial));
    CostmapConfig config;
    config.width = 6.0;
    config.height = 15.0;
    config.origin_x = -3.0;
    config.origin_y = -2.0;
    config.inflation_radius = 5.0;
    config.cost_scaling_factor = 3.0;
    Costmap map(config, 0.24);
    std::vector<Eigen::Vector2d> cylinders;
    while (cylinders.size() < 70) {
      const Eigen::Vector2d c(-2.25 + 4.5 * rng.uniform01(), 1.5 + 6.0 * rng.uniform01());
      if (std::abs(c.x()) > 0.45 || c.y() > 3.0) cylinders.push_back(c);  // a way through stays likely
    }
    std::vector<bool> seen(cylinders.size(), false);
    const Eigen::Vector2d goal(0.0, 10.0);
    Eigen::Vector2d robot(0.0, 0.0);
    GlobalPlanner planner({});
    const auto stampCylinder = [&](const Eigen::Vector2d& c, bool mark) {
      for (double dy = -0.075; dy <= 0.075; dy += 0.05)
        for (double dx = -0.075; dx <= 0.075; dx += 0.05)
          if (std::hypot(dx, dy) <= 0.08) {
            if (mark) map.markObstacle(c + Eigen::Vector2d(dx, dy));
            else map.clearPolygon({c + Eigen::Vector2d(dx - 0.02, dy - 0.02), c + Eigen::Vector2d(dx + 0.02, dy - 0.02),
                                   c + Eigen::Vector2d(dx + 0.02, dy + 0.02), c + Eigen::Vector2d(dx - 0.02, dy + 0.02)});
          }
      map.update();
    };
    int plans = 0, found = 0;
    for (int step = 0; step < 120 && (robot - goal).norm() > 0.3; ++step) {
      for (std::size_t k = 0; k < cylinders.size(); ++k) {
        const double range = (cylinders[k] - robot).norm();
        if (!seen[k] && range < 2.5) {
          seen[k] = true;
          stampCylinder(cylinders[k], true);
        } else if (seen[k] && rng.uniform01() < 0.05) {
          stampCylinder(cylinders[k], rng.uniform01() < 0.5);  // flickers out, or back
        }
      }
      const Plan kept = planner.plan(map, robot, goal);
      const Plan fresh = GlobalPlanner({}).plan(map, robot, goal);
      ASSERT_EQ(kept.found, fresh.found) << "trial " << trial << " step " << step;
      ASSERT_EQ(kept.cost, fresh.cost) << "trial " << trial << " step " << step;
      ASSERT_EQ(kept.path, fresh.path) << "trial " << trial << " step " << step;
      ++plans;
      found += kept.found ? 1 : 0;
      // The robot drives 5-15 cm along its path (or sidesteps if there is none).
      if (kept.found && kept.path.size() > 3) robot = kept.path[1 + static_cast<std::size_t>(rng.uniform01() * 2.5)];
      else robot += Eigen::Vector2d(rng.uniform01() - 0.5, 0.2) * 0.1;
    }
    EXPECT_GT(plans, 60);
    EXPECT_GT(found, plans * 9 / 10);  // the comparison is about real plans
  }
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
  c.inflation_radius = 1.2;
  c.cost_scaling_factor = 0.5;
  Costmap map(c, 0.5);
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
