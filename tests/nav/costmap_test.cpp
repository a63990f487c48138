#include "barn/nav/costmap.hpp"
#include "barn/nav/nav_stack.hpp"

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

// BARN's costmaps' inscribed radius: the 0.42 x 0.33 footprint padded by 0.1, 0.33 / 2 + 0.1.
const double kBarnInscribed = NavStackConfig{}.inscribedRadius(CostmapConfig{});
// The LfLH / Inventec stack's: padding 0.075, 0.165 + 0.075.
const double kLflhInscribed = 0.24;

// The LfLH / Inventec stack's global inflation (LflhConfig::lflhNav): 5 m at scaling 3 around
// an inscribed radius of 0.24 m; its cost reaches 0 at about 2.1 m.
CostmapConfig withLflhInflation(CostmapConfig c) {
  c.inflation_radius = 5.0;
  c.cost_scaling_factor = 3.0;
  return c;
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
  Costmap map(smallMap(), kBarnInscribed);
  map.integrateScan(scanAhead(1.0), {0.0, 0.0, 0.0}, {0.0, 0.0});
  map.update();
  CellIndex cell;
  ASSERT_TRUE(map.toCell({1.0, 0.0}, cell));
  EXPECT_TRUE(map.isObstacle(cell.x, cell.y));
  EXPECT_EQ(map.costAt({1.0, 0.0}), kLethalCost);
  EXPECT_EQ(map.costAt({0.5, 0.0}), kFreeCost);  // the ray's cells stay free
}

TEST(Costmap, IgnoresReturnsBeyondObstacleRange) {
  Costmap map(smallMap(), kBarnInscribed);
  map.integrateScan(scanAhead(2.7), {0.0, 0.0, 0.0}, {0.0, 0.0});  // 2.7 m > 2.5 m
  map.update();
  EXPECT_EQ(map.costAt({2.7, 0.0}), kFreeCost);
}

TEST(Costmap, RayTraceClearingRemovesAnObstacleThatMoved) {
  Costmap map(smallMap(), kBarnInscribed);
  map.integrateScan(scanAhead(1.0), {0.0, 0.0, 0.0}, {0.0, 0.0});
  map.update();
  ASSERT_EQ(map.costAt({1.0, 0.0}), kLethalCost);
  // The obstacle moved away: the beam now returns at 2.0 m and its ray clears 1.0 m.
  map.integrateScan(scanAhead(2.0), {0.0, 0.0, 0.0}, {0.0, 0.0});
  map.update();
  EXPECT_EQ(map.costAt({1.0, 0.0}), kFreeCost);
  EXPECT_EQ(map.costAt({2.0, 0.0}), kLethalCost);
}

TEST(Costmap, ASourceThatDoesNotClearKeepsAnObstacleThatMoved) {
  // `clearing: false` (KUL+FM's scan source): the ray of the 2.0 m return passes 1.0 m without
  // freeing it; only marking happens.
  CostmapConfig c = smallMap();
  c.clearing = false;
  Costmap map(c, kBarnInscribed);
  map.integrateScan(scanAhead(1.0), {0.0, 0.0, 0.0}, {0.0, 0.0});
  map.update();
  map.integrateScan(scanAhead(2.0), {0.0, 0.0, 0.0}, {0.0, 0.0});
  map.update();
  EXPECT_EQ(map.costAt({1.0, 0.0}), kLethalCost);
  EXPECT_EQ(map.costAt({2.0, 0.0}), kLethalCost);
}

TEST(Costmap, ABeamWithoutAReturnNeitherMarksNorClears) {
  // laser_geometry drops +inf (and range_max) beams, so nothing is traced along them.
  Costmap map(smallMap(), kBarnInscribed);
  map.integrateScan(scanAhead(2.0), {0.0, 0.0, 0.0}, {0.0, 0.0});
  map.update();
  map.integrateScan(scanAhead(kInf), {0.0, 0.0, 0.0}, {0.0, 0.0});
  map.update();
  EXPECT_EQ(map.costAt({2.0, 0.0}), kLethalCost);
  map.integrateScan(scanAhead(30.0), {0.0, 0.0, 0.0}, {0.0, 0.0});  // exactly range_max
  map.update();
  EXPECT_EQ(map.costAt({2.0, 0.0}), kLethalCost);
  // With inf_is_valid a no-return beam clears the raytrace range (3 m) and marks nothing.
  CostmapConfig c = smallMap();
  c.inf_is_valid = true;
  Costmap valid(c, kBarnInscribed);
  valid.integrateScan(scanAhead(2.0), {0.0, 0.0, 0.0}, {0.0, 0.0});
  valid.update();
  valid.integrateScan(scanAhead(kInf), {0.0, 0.0, 0.0}, {0.0, 0.0});
  valid.update();
  EXPECT_EQ(valid.costAt({2.0, 0.0}), kFreeCost);
}

TEST(Costmap, AReturnBetweenObstacleAndRaytraceRangeClearsItsOwnCell) {
  // costmap_2d clears the hit cell too and marks only returns closer than obstacle_range:
  // a return at 2.7 m (inside 3.0, beyond 2.5) frees the cell an earlier return marked.
  Costmap map(smallMap(), kBarnInscribed);
  map.markObstacle({2.7, 0.0});
  map.update();
  ASSERT_EQ(map.costAt({2.7, 0.0}), kLethalCost);
  map.integrateScan(scanAhead(2.7), {0.0, 0.0, 0.0}, {0.0, 0.0});
  map.update();
  EXPECT_EQ(map.costAt({2.7, 0.0}), kFreeCost);
}

TEST(Costmap, RayTraceStopsAtTheRaytraceRange) {
  // A return at 5 m clears 60 cells (3.0 m / 0.05 m) of its ray and no more. Origin -3.01:
  // the sensor at x = 0 is in cell 60, so the walk ends in cell 120 = [2.99, 3.04).
  CostmapConfig c = smallMap();
  c.origin_x = -3.01;
  c.width = 8.0;
  Costmap map(c, kBarnInscribed);
  map.markObstacle({2.0, 0.0});
  map.update();
  map.markObstacle({3.02, 0.0});  // cell 120: the last one cleared
  map.update();
  map.markObstacle({3.06, 0.0});  // cell 121: beyond the raytrace range
  map.update();
  map.integrateScan(scanAhead(5.0), {0.0, 0.0, 0.0}, {0.0, 0.0});
  map.update();
  EXPECT_EQ(map.costAt({2.0, 0.0}), kFreeCost);
  EXPECT_NE(map.costAt({3.02, 0.0}), kLethalCost);
  EXPECT_EQ(map.costAt({3.06, 0.0}), kLethalCost);
}

TEST(Costmap, InflationCostFollowsTheExponentialDecay) {
  CostmapConfig c = smallMap();  // inscribed 0.265 m, inflation 0.30 m, scaling 10
  Costmap map(c, kBarnInscribed);
  // 252 exp(-10 (0.28 - 0.265)) = 252 exp(-0.15) = 216.9 -> 216
  EXPECT_EQ(map.inflationCost(0.28), 216);
  EXPECT_EQ(map.inflationCost(0.2), kInscribedCost);
  EXPECT_EQ(map.inflationCost(0.31), kFreeCost);
  EXPECT_EQ(map.inflationCost(0.0), kLethalCost);
}

TEST(Costmap, BarnInflationTableInCells) {
  // BARN's table (res 0.05, inscribed 0.265, k 10, radius 0.30 = 6 cells), in cell units:
  // (5,1) 5.099 cells = 0.255 m -> 253; (5,2) 5.385 -> 252 exp(-10 * 0.00426) = 241.5 -> 241;
  // (4,4) 5.657 -> 210; (6,0) exactly 6 cells -> 252 exp(-0.35) = 177.6 -> 177 (not cut off
  // by rounding 6 x 0.05 above 0.30); (6,1) 6.083 cells -> beyond the radius -> 0.
  Costmap map(smallMap(), kBarnInscribed);
  map.markObstacle({0.025, 0.025});
  map.update();
  CellIndex hit;
  ASSERT_TRUE(map.toCell({0.025, 0.025}, hit));
  EXPECT_EQ(map.cost(hit.x + 5, hit.y + 1), kInscribedCost);
  EXPECT_EQ(map.cost(hit.x + 5, hit.y + 2), 241);
  EXPECT_EQ(map.cost(hit.x + 4, hit.y + 4), 210);
  EXPECT_EQ(map.cost(hit.x + 6, hit.y), 177);
  EXPECT_EQ(map.cost(hit.x + 6, hit.y + 1), kFreeCost);
}

TEST(Costmap, FootprintClearingFreesEveryCellTheOutlineTouches) {
  // The polygon's right edge is at x = 0.32, in cell [0.30, 0.35) (origin -3 m: cell 66).
  // An obstacle at x = 0.34 lies in that cell, whose centre (0.325) is outside the polygon:
  // the rasterised outline still covers it, so it is cleared (convexFillCells). Inside cells
  // are cleared; a cell beyond the outline is not.
  Costmap map(smallMap(), kBarnInscribed);
  const auto cellOf = [&](double x, double y) {
    CellIndex cell;
    EXPECT_TRUE(map.toCell({x, y}, cell));
    return cell;
  };
  const CellIndex edge = cellOf(0.34, 0.01), inside = cellOf(0.12, 0.12), beyond = cellOf(0.40, 0.01);
  map.markObstacle({0.34, 0.01});
  map.update();
  map.markObstacle({0.12, 0.12});
  map.update();
  map.markObstacle({0.40, 0.01});
  map.update();
  const std::vector<Eigen::Vector2d> polygon = {{0.32, 0.22}, {-0.32, 0.22}, {-0.32, -0.22}, {0.32, -0.22}};
  map.clearPolygon(polygon);
  map.update();
  EXPECT_FALSE(map.isObstacle(edge.x, edge.y));
  EXPECT_FALSE(map.isObstacle(inside.x, inside.y));
  EXPECT_TRUE(map.isObstacle(beyond.x, beyond.y));
  // A corner off the map clears nothing (costmap_2d gives up on the whole polygon).
  map.markObstacle({0.12, 0.12});
  map.update();
  map.clearPolygon({{0.32, 0.22}, {-0.32, 0.22}, {-0.32, -0.22}, {9.0, -0.22}});
  map.update();
  EXPECT_TRUE(map.isObstacle(inside.x, inside.y));
}

TEST(Costmap, InflatesAroundAnObstacleAtKnownDistances) {
  CostmapConfig c = smallMap();
  c.inflation_radius = 0.5;
  c.cost_scaling_factor = 3.0;
  Costmap map(c, 0.1);
  map.integrateScan(scanAhead(1.0), {0.0, 0.0, 0.0}, {0.0, 0.0});
  map.update();
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

TEST(Costmap, AWideRadiusCostsWhatItsTableSaysAtEveryCellOutToTheRadius) {
  // The Inventec team's global inflation stops where its cost reaches 0 (about 2.1 m); every
  // cell of the map, near or beyond, must still cost what the formula gives at its cell
  // distance, before and after the obstacle is cleared again.
  CostmapConfig c;
  c.width = 12.0;
  c.height = 12.0;
  c.origin_x = -6.0;
  c.origin_y = -6.0;
  Costmap map(withLflhInflation(c), kLflhInscribed);
  map.markObstacle({0.025, 0.025});
  map.update();
  CellIndex hit;
  ASSERT_TRUE(map.toCell({0.025, 0.025}, hit));
  int nonzero_beyond_two_metres = 0;
  for (int y = 0; y < map.heightCells(); ++y)
    for (int x = 0; x < map.widthCells(); ++x) {
      const double cells = std::hypot(x - hit.x, y - hit.y);
      const std::uint8_t expected = cells > 100.0 ? kFreeCost : map.inflationCostAtCells(cells);
      ASSERT_EQ(map.cost(x, y), expected) << "cell (" << x << ", " << y << ")";
      if (cells > 40.0 && expected > kFreeCost) ++nonzero_beyond_two_metres;
    }
  EXPECT_GT(nonzero_beyond_two_metres, 0);  // the tail is there: costs 1 out to 2.08 m
  EXPECT_EQ(map.inflationCost(2.2), kFreeCost);
  map.clearPolygon({{0.2, 0.2}, {-0.2, 0.2}, {-0.2, -0.2}, {0.2, -0.2}});
  map.update();
  for (int y = 0; y < map.heightCells(); ++y)
    for (int x = 0; x < map.widthCells(); ++x) ASSERT_EQ(map.cost(x, y), kFreeCost);
}

TEST(Costmap, NewInflationSettingsCostWhatAFreshMapWithThemCosts) {
  // dynamic_reconfigure of the inflation: after setInflation every cell costs what a map made
  // with those settings from the start costs, wider and narrower than before.
  CostmapConfig c = smallMap();
  for (const auto& [radius, scaling] : {std::pair{0.6, 3.0}, std::pair{0.1, 10.0}, std::pair{0.35, 5.0}}) {
    Costmap changed(c, kBarnInscribed);
    changed.integrateScan(scanAhead(1.0), {0.0, 0.0, 0.0}, {0.0, 0.0});
    changed.update();
    changed.costAt({0.0, 0.0});  // inflated with the old settings first
    changed.setInflation(radius, scaling);
    changed.update();
    CostmapConfig fresh_config = c;
    fresh_config.inflation_radius = radius;
    fresh_config.cost_scaling_factor = scaling;
    Costmap fresh(fresh_config, kBarnInscribed);
    fresh.integrateScan(scanAhead(1.0), {0.0, 0.0, 0.0}, {0.0, 0.0});
    fresh.update();
    for (int y = 0; y < fresh.heightCells(); ++y)
      for (int x = 0; x < fresh.widthCells(); ++x)
        ASSERT_EQ(changed.cost(x, y), fresh.cost(x, y)) << "radius " << radius << ", cell (" << x << ", " << y << ")";
  }
  // A radius below the inscribed one (0.1 < 0.265) inflates only out to itself, as costmap_2d's
  // does: 2 cells of 253, then free.
  CostmapConfig narrow = c;
  narrow.inflation_radius = 0.1;
  Costmap map(narrow, kBarnInscribed);
  map.integrateScan(scanAhead(1.0), {0.0, 0.0, 0.0}, {0.0, 0.0});
  map.update();
  CellIndex hit;
  ASSERT_TRUE(map.toCell({1.0, 0.0}, hit));
  EXPECT_EQ(map.cost(hit.x, hit.y + 2), kInscribedCost);
  EXPECT_EQ(map.cost(hit.x, hit.y + 3), kFreeCost);
}

TEST(Costmap, ClearingAnObstacleRemovesItsInflation) {
  Costmap map(smallMap(), kBarnInscribed);
  map.integrateScan(scanAhead(1.0), {0.0, 0.0, 0.0}, {0.0, 0.0});
  map.update();
  EXPECT_GT(map.costAt({1.0, 0.2}), kFreeCost);
  map.integrateScan(scanAhead(2.0), {0.0, 0.0, 0.0}, {0.0, 0.0});
  map.update();
  EXPECT_EQ(map.costAt({1.0, 0.2}), kFreeCost);
}

// The cost every cell should have, from scratch: the inflation cost at the nearest obstacle
// cell within the reach (cell units), lethal on obstacles, unknown where unseen.
std::uint8_t bruteForceCost(const Costmap& map, int x, int y) {
  if (map.isObstacle(x, y)) return kLethalCost;
  if (map.isUnknown(x, y)) return kUnknownCost;  // not inflated (inflate_unknown: false)
  const int reach = static_cast<int>(std::ceil(map.config().inflation_radius / map.resolution()));
  double nearest = kInf;
  for (int oy = y - reach; oy <= y + reach; ++oy)
    for (int ox = x - reach; ox <= x + reach; ++ox)
      if (map.isObstacle(ox, oy)) nearest = std::min(nearest, std::hypot(ox - x, oy - y));
  return nearest > reach ? kFreeCost : map.inflationCostAtCells(nearest);
}

// Scans of random ranges from random poses mark and clear cells in many places; after some of
// them the changes are folded in (update(), so several at once, or one), and with
// `moves` the robot's footprint is cleared and a rolling window re-centres. At the end every
// cell must cost what a from-scratch inflation gives; in a rolling window, every cell farther
// than the inflation reach from the edges (at the edge the window left, a cell keeps the cost
// of an obstacle that left with it, as costmap_2d's copied master grid does).
void expectIncrementalInflationEqualsInflatingFromScratch(const CostmapConfig& config, bool moves) {
  Costmap map(config, kBarnInscribed);
  core::LaserScan scan = scanAhead(1.0);
  std::uint64_t state = 12345;
  const auto uniform = [&state] {
    state = state * 6364136223846793005ULL + 1442695040888963407ULL;
    return static_cast<double>(state >> 11) / 9007199254740992.0;
  };
  for (int step = 0; step < 200; ++step) {
    for (double& r : scan.ranges) r = 0.3 + 2.5 * uniform();
    const core::Pose2 pose{-1.5 + 3.0 * uniform(), -1.5 + 3.0 * uniform(), 6.283 * uniform()};
    map.integrateScan(scan, pose, pose.position());
    if (moves && step % 4 == 1) {
      const Eigen::Vector2d c = pose.position();
      map.clearPolygon({c + Eigen::Vector2d(-0.3, -0.25), c + Eigen::Vector2d(0.3, -0.25), c + Eigen::Vector2d(0.3, 0.25),
                        c + Eigen::Vector2d(-0.3, 0.25)});
    }
    if (step % 3 == 0) map.update();  // several changes folded in at once, or one
  }
  map.update();
  int obstacles = 0, inflated = 0;
  const int margin = config.rolling ? static_cast<int>(std::ceil(config.inflation_radius / config.resolution)) : 0;
  for (int y = margin; y < map.heightCells() - margin; ++y)
    for (int x = margin; x < map.widthCells() - margin; ++x) {
      ASSERT_EQ(map.cost(x, y), bruteForceCost(map, x, y)) << "cell " << x << ", " << y;
      obstacles += map.isObstacle(x, y);
      inflated += map.cost(x, y) > kFreeCost && map.cost(x, y) < kLethalCost;
    }
  EXPECT_GT(obstacles, 50);  // the scans left a real map behind
  EXPECT_GT(inflated, 200);
}

TEST(Costmap, IncrementalInflationEqualsInflatingFromScratch) {
  expectIncrementalInflationEqualsInflatingFromScratch(smallMap(), false);
}

TEST(Costmap, IncrementalInflationEqualsInflatingFromScratchWithTheLflhStacksWideInflation) {
  // The Inventec team's global inflation (5 m at scaling 3) over a sparse field: a few dozen
  // obstacles come and go, so most cells owe their cost to one 1-2 m away, in the tail where
  // many obstacles tie at the same low cost. What a cleared obstacle leaves must come from the
  // distances the map keeps, not from the costs. Checked every fifth step.
  Costmap map(withLflhInflation(smallMap()), kLflhInscribed);
  std::uint64_t state = 777;
  const auto uniform = [&state] {
    state = state * 6364136223846793005ULL + 1442695040888963407ULL;
    return static_cast<double>(state >> 11) / 9007199254740992.0;
  };
  std::vector<Eigen::Vector2d> marked;
  int far_cells = 0;
  for (int step = 0; step < 40; ++step) {
    for (int k = 0; k < 2; ++k) {
      marked.push_back({-2.9 + 5.8 * uniform(), -2.9 + 5.8 * uniform()});
      map.markObstacle(marked.back());
    }
    if (marked.size() > 6) {  // clear one at random, with the cells around it
      const std::size_t gone = static_cast<std::size_t>(uniform() * static_cast<double>(marked.size()));
      const Eigen::Vector2d p = marked[gone];
      map.clearPolygon({p + Eigen::Vector2d(-0.06, -0.06), p + Eigen::Vector2d(0.06, -0.06), p + Eigen::Vector2d(0.06, 0.06),
                        p + Eigen::Vector2d(-0.06, 0.06)});
      marked.erase(marked.begin() + static_cast<std::ptrdiff_t>(gone));
    }
    if (step % 5 != 4) continue;
    map.update();  // five steps' changes at once
    // From scratch: the cost at the nearest obstacle cell, over the few obstacle cells there are.
    std::vector<CellIndex> obstacles;
    for (int y = 0; y < map.heightCells(); ++y)
      for (int x = 0; x < map.widthCells(); ++x)
        if (map.isObstacle(x, y)) obstacles.push_back({x, y});
    for (int y = 0; y < map.heightCells(); ++y)
      for (int x = 0; x < map.widthCells(); ++x) {
        double nearest = kInf;
        for (const CellIndex& o : obstacles) nearest = std::min(nearest, std::hypot(o.x - x, o.y - y));
        const std::uint8_t expected = nearest > 100.0 ? kFreeCost : map.inflationCostAtCells(nearest);
        ASSERT_EQ(map.cost(x, y), expected) << "step " << step << ", cell " << x << ", " << y;
        far_cells += expected > kFreeCost && expected < 10;  // 1.4-2.1 m from the nearest obstacle
      }
  }
  EXPECT_GT(far_cells, 1000);  // the tail was exercised
}

CostmapConfig smallRollingMap() {
  CostmapConfig c = smallMap();
  c.width = c.height = 5.0;
  c.rolling = true;
  return c;
}

TEST(Costmap, IncrementalInflationEqualsInflatingFromScratchWhileTheWindowRollsAndTheFootprintClears) {
  expectIncrementalInflationEqualsInflatingFromScratch(smallRollingMap(), true);
}

TEST(Costmap, IncrementalInflationEqualsInflatingFromScratchWhenUnknownSpaceIsTracked) {
  CostmapConfig tracking = smallRollingMap();
  tracking.track_unknown = true;
  expectIncrementalInflationEqualsInflatingFromScratch(tracking, true);
}

TEST(Costmap, RollingWindowKeepsObstaclesSeenEarlierWhileTheyStayInside) {
  CostmapConfig c;
  c.rolling = true;  // 10 x 10 m around the robot
  Costmap map(c, kBarnInscribed);
  map.integrateScan(scanAhead(1.0), {0.0, 0.0, 0.0}, {0.0, 0.0});
  map.update();
  // The robot drives 3 m away, facing away: the LiDAR no longer sees the obstacle.
  map.recentre({-3.0, 0.0});
  map.update();
  EXPECT_EQ(map.costAt({1.0, 0.0}), kLethalCost);
  // 7 m away the obstacle has left the window and is forgotten.
  map.recentre({-7.0, 0.0});
  map.update();
  map.recentre({0.0, 0.0});
  map.update();
  EXPECT_EQ(map.costAt({1.0, 0.0}), kFreeCost);
}

TEST(Costmap, RollingWindowMovesByWholeCellsOnceTheRobotIsACellFromTheCentre) {
  // costmap_2d's updateOrigin: a robot jittering across a cell boundary does not move the
  // window back and forth.
  CostmapConfig c;
  c.rolling = true;  // 10 x 10 m at 0.05 m
  Costmap map(c, kBarnInscribed);
  const auto expectOrigin = [&](const Eigen::Vector2d& position, double x, double y) {
    const Eigen::Vector2d predicted = map.windowOriginFor(map.origin(), position);
    map.recentre(position);
    map.update();
    EXPECT_NEAR(map.origin().x(), x, 1e-9) << position.transpose();
    EXPECT_NEAR(map.origin().y(), y, 1e-9) << position.transpose();
    EXPECT_EQ(predicted, map.origin()) << position.transpose();
  };
  expectOrigin({0.0, 0.0}, -5.0, -5.0);
  expectOrigin({0.049, -0.049}, -5.0, -5.0);  // within a cell of the centre
  expectOrigin({0.051, 0.0}, -4.95, -5.0);    // a full cell along x
  expectOrigin({0.02, 0.0}, -4.95, -5.0);     // back across the boundary: it stays
  expectOrigin({-0.031, 0.0}, -5.0, -5.0);    // a full cell back from the new centre
  expectOrigin({1.0, -2.0}, -4.0, -7.0);      // many cells at once
}

TEST(Costmap, TracksUnknownSpaceWhenAsked) {
  CostmapConfig c = smallMap();
  c.track_unknown = true;
  Costmap map(c, kBarnInscribed);
  EXPECT_EQ(map.costAt({2.0, 2.0}), kUnknownCost);
  map.integrateScan(scanAhead(1.0), {0.0, 0.0, 0.0}, {0.0, 0.0});
  map.update();
  EXPECT_EQ(map.costAt({0.5, 0.0}), kFreeCost);
  EXPECT_EQ(map.costAt({2.0, 2.0}), kUnknownCost);
}

TEST(Costmap, ClearOutsideForgetsDistantObstacles) {
  Costmap map(smallMap(), kBarnInscribed);
  map.integrateScan(scanAhead(2.0), {0.0, 0.0, 0.0}, {0.0, 0.0});
  map.update();
  map.clearOutside({0.0, 0.0}, 1.5);
  map.update();
  EXPECT_EQ(map.costAt({2.0, 0.0}), kFreeCost);
}

TEST(Costmap, ResetForgetsEverythingUntilTheNextScan) {
  // costmap_2d's resetLayers (eband's answer to a plan it cannot turn into a band).
  Costmap map(smallMap(), kBarnInscribed);
  map.integrateScan(scanAhead(1.0), {0.0, 0.0, 0.0}, {0.0, 0.0});
  map.update();
  ASSERT_EQ(map.costAt({1.0, 0.0}), kLethalCost);
  ASSERT_GT(map.costAt({0.8, 0.0}), kFreeCost);
  const std::uint64_t version = map.version();
  map.reset();
  map.update();
  EXPECT_NE(map.version(), version);
  for (int y = 0; y < map.heightCells(); ++y)
    for (int x = 0; x < map.widthCells(); ++x) ASSERT_EQ(map.cost(x, y), kFreeCost);
  EXPECT_FALSE(map.isObstacle(0, 0));
  // The next scan marks and inflates as on a fresh map.
  map.integrateScan(scanAhead(1.0), {0.0, 0.0, 0.0}, {0.0, 0.0});
  map.update();
  Costmap fresh(smallMap(), kBarnInscribed);
  fresh.integrateScan(scanAhead(1.0), {0.0, 0.0, 0.0}, {0.0, 0.0});
  fresh.update();
  for (int y = 0; y < map.heightCells(); ++y)
    for (int x = 0; x < map.widthCells(); ++x) ASSERT_EQ(map.cost(x, y), fresh.cost(x, y));
}

}  // namespace
}  // namespace barn::nav
