#include "barn/controllers/in2bot.hpp"

#include <gtest/gtest.h>

#include <cmath>
#include <limits>
#include <numbers>
#include <vector>

#include "barn/controllers/in2bot_map.hpp"
#include "tests/controllers/scan_fixtures.hpp"

namespace barn::controllers {
namespace {

constexpr double kInf = std::numeric_limits<double>::infinity();

std::int8_t& at(std::vector<std::int8_t>& grid, int width, int x, int y) {
  return grid[static_cast<std::size_t>(y) * width + x];
}

// ---------------------------------------------------------------------------------------------
// The count grid
// ---------------------------------------------------------------------------------------------

/// A 720-beam scan seeing nothing but `range` on beam `beam`.
core::LaserScan oneBeam(std::size_t beam, double range) {
  core::LaserScan scan = uniformScan(core::LidarConfig{}, kInf);
  scan.ranges[beam] = range;
  return scan;
}

/// The sensor on the centre of cell (100, 125) (the odom origin's cell), turned so that beam
/// 359 points exactly along +x.
core::Pose2 alongX() { return {0.02, 0.02, -uniformScan(core::LidarConfig{}, kInf).angle(359)}; }

TEST(ScanCountGrid, ABeamClearsItsCellsAndMarksItsEnd) {
  ScanCountGrid grid{In2botMapConfig{}};
  EXPECT_EQ(grid.width(), 200);   // 8 m / 0.04
  EXPECT_EQ(grid.height(), 425);  // 17 m / 0.04
  // 1 m along +x from (0.02, 0.02): the return in cell (125, 125), cells 100..124 passed.
  grid.integrate(oneBeam(359, 1.0), alongX());
  const std::vector<std::int8_t> map = grid.occupancy();
  const auto cell = [&](int x, int y) { return map[static_cast<std::size_t>(y) * grid.width() + x]; };
  EXPECT_EQ(cell(100, 125), kFreeCell);
  EXPECT_EQ(cell(124, 125), kFreeCell);
  EXPECT_EQ(cell(125, 125), kOccupiedCell);
  EXPECT_EQ(cell(126, 125), kUnknownCell);  // past the return
  // Every other beam saw nothing: +inf becomes 20 m, past max_range 10, and is not used.
  EXPECT_EQ(cell(100, 135), kUnknownCell);
}

TEST(ScanCountGrid, ALongReadingClearsToTheUsableRangeAndMarksNothing) {
  In2botMapConfig config;
  ScanCountGrid grid{config};
  // 9 m (between maxUrange 8 and maxRange 10) straight ahead along +y from (0, -4): cleared to
  // y = 4 (cell 225), nothing marked.
  grid.integrate(oneBeam(359, 9.0), {0.0, -4.0, std::numbers::pi / 2});
  const std::vector<std::int8_t> map = grid.occupancy();
  int occupied = 0;
  for (std::int8_t v : map) occupied += v == kOccupiedCell;
  EXPECT_EQ(occupied, 0);
  EXPECT_EQ(map[static_cast<std::size_t>(220) * grid.width() + 100], kFreeCell);
  EXPECT_EQ(map[static_cast<std::size_t>(230) * grid.width() + 100], kUnknownCell);
}

TEST(ScanCountGrid, ACellIsOccupiedWhenOverAQuarterOfItsVisitsEndThere) {
  ScanCountGrid grid{In2botMapConfig{}};
  const auto value = [&] { return grid.occupancy()[static_cast<std::size_t>(125) * grid.width() + 125]; };
  // Three scans end in cell (125, 125) (1 m), then six pass through it to 2 m: 3 hits in 9
  // visits, 0.33 > 0.25: occupied. Six more: 3 in 15, 0.2: free.
  for (int i = 0; i < 3; ++i) grid.integrate(oneBeam(359, 1.0), alongX());
  for (int i = 0; i < 6; ++i) grid.integrate(oneBeam(359, 2.0), alongX());
  EXPECT_EQ(value(), kOccupiedCell);
  for (int i = 0; i < 6; ++i) grid.integrate(oneBeam(359, 2.0), alongX());
  EXPECT_EQ(value(), kFreeCell);
}

// ---------------------------------------------------------------------------------------------
// Costs
// ---------------------------------------------------------------------------------------------

TEST(In2botEsdf, CostFallsWithDistanceAndUnknownCellsAreDecayed) {
  // One occupied cell at (10, 10) of a free 21 x 21 grid of 0.04 m; no wall rule.
  const int w = 21;
  std::vector<std::int8_t> occupancy(static_cast<std::size_t>(w) * w, kFreeCell);
  at(occupancy, w, 10, 10) = kOccupiedCell;
  at(occupancy, w, 10, 14) = kUnknownCell;
  In2botEsdfConfig config;
  config.wall_rule = false;
  std::vector<std::int8_t> c = esdfCosts(occupancy, w, w, 0.04, config);
  EXPECT_EQ(at(c, w, 10, 10), 100);
  // Float arithmetic as the team's: (1 - 0.04f) * 100 = 96.0000001 -> 96; 3 cells 0.12 -> 88;
  // 4 cells 0.16 -> 84 (the first passable value below 85); sqrt(13) cells 0.144 -> 85.
  EXPECT_EQ(at(c, w, 11, 10), 96);
  EXPECT_EQ(at(c, w, 13, 10), 88);
  EXPECT_EQ(at(c, w, 14, 10), 84);
  EXPECT_EQ(at(c, w, 13, 12), 85);
  // sqrt(200) cells = 0.566 m: (1 - 0.5657) * 100 = 43.4 -> 43.
  EXPECT_EQ(at(c, w, 0, 0), 43);
  // The unknown cell 4 cells away: 84 * 0.8 = 67.2 -> 67.
  EXPECT_EQ(at(c, w, 10, 14), 67);
}

TEST(In2botEsdf, TheWallRuleFindsTheContainmentWallsOnRowHundred) {
  // The team's grid: 200 x 425. Row 100 (1 m behind the start) as the LiDAR sees it at the
  // start: unknown beyond the left wall (cell 47), free inside, the right wall at 152,
  // unknown beyond. The rule takes x1 = 47 and x2 = 153, the first unknown cell past it.
  const int w = 200, h = 425;
  std::vector<std::int8_t> occupancy(static_cast<std::size_t>(w) * h, kUnknownCell);
  for (int x = 48; x < 152; ++x) at(occupancy, w, x, 100) = kFreeCell;
  at(occupancy, w, 47, 100) = kOccupiedCell;
  at(occupancy, w, 152, 100) = kOccupiedCell;
  In2botEsdfConfig config;
  EXPECT_EQ(containmentWalls(occupancy, w, h, config), std::make_pair(47, 153));
  // The rule's columns become obstacles: cost 100 left of 47 on a free row (row 200), and,
  // unknown there (row 300), 100 * 0.8 = 80.
  for (int x = 0; x < w; ++x) at(occupancy, w, x, 200) = kFreeCell;
  const std::vector<std::int8_t> costs = esdfCosts(occupancy, w, h, 0.04, config);
  EXPECT_EQ(costs[static_cast<std::size_t>(200) * w + 20], 100);
  EXPECT_EQ(costs[static_cast<std::size_t>(300) * w + 20], 80);
  // 53 cells (2.1 m) from the nearest wall column: beyond D_MAX, 0.
  EXPECT_EQ(costs[static_cast<std::size_t>(200) * w + 100], 0);
}

TEST(In2botEsdf, TheWallRuleMovesUpWhileRowHundredIsPartlyUnseen) {
  // Row 100 with an unseen stretch inside (80..119): the last wall run starts at 152 and ends
  // at 153, so x1 = 152 is not left of column 96; row 101 is whole and gives (47, 153).
  const int w = 200, h = 425;
  std::vector<std::int8_t> occupancy(static_cast<std::size_t>(w) * h, kUnknownCell);
  for (int row : {100, 101}) {
    for (int x = 48; x < 152; ++x) at(occupancy, w, x, row) = (row == 100 && x >= 80 && x < 120) ? kUnknownCell : kFreeCell;
    at(occupancy, w, 47, row) = kOccupiedCell;
    at(occupancy, w, 152, row) = kOccupiedCell;
  }
  EXPECT_EQ(containmentWalls(occupancy, w, h, In2botEsdfConfig{}), std::make_pair(47, 153));
  // Without any wall seen the rule gives up (the team's loop would run off the map).
  const std::vector<std::int8_t> unseen(static_cast<std::size_t>(w) * h, kUnknownCell);
  EXPECT_FALSE(containmentWalls(unseen, w, h, In2botEsdfConfig{}).has_value());
}

// ---------------------------------------------------------------------------------------------
// A*
// ---------------------------------------------------------------------------------------------

/// A point robot (no box) on a small grid.
In2botPlannerConfig pointRobot() {
  In2botPlannerConfig c;
  c.vehicle_width = 0.0;
  c.vehicle_length = 0.0;
  return c;
}

TEST(In2botAStar, GoesAroundAWallThroughItsGap) {
  // 7 x 5 cells, a wall at x = 3 for y = 0..3, the gap at (3, 4). From (1, 2) to (5, 2): up
  // the diagonal to the gap and down again, 4 x 1.414 = 5.66; any path with a straight move
  // is longer.
  const int w = 7, h = 5;
  std::vector<std::int8_t> costs(static_cast<std::size_t>(w) * h, 0);
  for (int y = 0; y <= 3; ++y) at(costs, w, 3, y) = 100;
  const std::vector<GridCell> path = planGridPath(costs, w, h, {1, 2}, {5, 2}, 0.04, pointRobot());
  EXPECT_EQ(path, (std::vector<GridCell>{{1, 2}, {2, 3}, {3, 4}, {4, 3}, {5, 2}}));
}

TEST(In2botAStar, PaysForCostlyCellsInProportion) {
  // A 5 x 3 corridor from (0, 1) to (4, 1). The straight middle row costs 60 per cell: three
  // cells entered at 1 x 1.6 plus the goal 1 = 5.8. Over the top row: 1.414 + 1 + 1 + 1.414 =
  // 4.83. The detour wins.
  const int w = 5, h = 3;
  std::vector<std::int8_t> costs(static_cast<std::size_t>(w) * h, 0);
  for (int x = 1; x <= 3; ++x) at(costs, w, x, 1) = 60;
  const std::vector<GridCell> path = planGridPath(costs, w, h, {0, 1}, {4, 1}, 0.04, pointRobot());
  ASSERT_EQ(path.size(), 5u);
  EXPECT_NE(path[2].y, 1);
  // At cost 20 the middle row is 3 x 1.2 + 1 = 4.6 < 4.83: straight.
  for (int x = 1; x <= 3; ++x) at(costs, w, x, 1) = 20;
  EXPECT_EQ(planGridPath(costs, w, h, {0, 1}, {4, 1}, 0.04, pointRobot()),
            (std::vector<GridCell>{{0, 1}, {1, 1}, {2, 1}, {3, 1}, {4, 1}}));
}

TEST(In2botAStar, TheFootprintBoxKeepsThePathFromAnObstacle) {
  // The team's box: ceil(0.3 / 0.08) = 4 cells either side in x, ceil(0.35 / 0.08) = 5 in y.
  // On a 21 x 30 free grid a blocked cell at (10, 15) closes x = 6..14 for y = 10..20; the
  // path from (10, 6) to (10, 24) must pass at x <= 5 or x >= 15, and the box keeps it 5
  // cells off the grid's edges too.
  const int w = 21, h = 30;
  std::vector<std::int8_t> costs(static_cast<std::size_t>(w) * h, 0);
  at(costs, w, 10, 15) = 100;
  const std::vector<GridCell> path = planGridPath(costs, w, h, {10, 6}, {10, 24}, 0.04, In2botPlannerConfig{});
  ASSERT_FALSE(path.empty());
  for (const GridCell& c : path) {
    if (c.y >= 10 && c.y <= 20) {
      EXPECT_TRUE(c.x <= 5 || c.x >= 15) << c.x << "," << c.y;
    }
    EXPECT_GE(c.x, 4);
    EXPECT_LE(c.x, 16);
  }
  // A goal whose box is not clear moves to the first clear cell on the rings around it: the
  // goal (10, 15) is the obstacle itself, cost 100, so nothing is clear within 5 cells in y.
  EXPECT_TRUE(planGridPath(costs, w, h, {10, 6}, {10, 15}, 0.04, [] {
                In2botPlannerConfig c;
                c.goal_search_radius = 3;
                return c;
              }()).empty());
}

TEST(In2botAStar, ThePathCheckLooksAtTheTurnedBoxCorners) {
  // A path up +y at x = 10: the box (length 0.35 along the path, width 0.3 across) turned
  // 90 deg puts its corners at (-0.15, +-0.175) and (+0.15, +-0.175): cells (-4, +-4) and
  // (+4, +-4) from each path cell (0.15 / 0.04 = 3.75 -> 4, 0.175 / 0.04 = 4.375 -> 4).
  const int w = 21, h = 40;
  std::vector<std::int8_t> costs(static_cast<std::size_t>(w) * h, 0);
  std::vector<GridCell> path;
  for (int y = 10; y <= 30; ++y) path.push_back({10, y});
  EXPECT_FALSE(pathCollides(path, costs, w, h, 0.04, In2botPlannerConfig{}));
  at(costs, w, 6, 24) = 85;  // (10 - 4, 20 + 4): a corner of path cell (10, 20)
  EXPECT_TRUE(pathCollides(path, costs, w, h, 0.04, In2botPlannerConfig{}));
  at(costs, w, 6, 24) = 84;  // passable
  EXPECT_FALSE(pathCollides(path, costs, w, h, 0.04, In2botPlannerConfig{}));
  at(costs, w, 8, 24) = 100;  // inside the box but not on a corner: unchecked, as the team's
  EXPECT_FALSE(pathCollides(path, costs, w, h, 0.04, In2botPlannerConfig{}));
}

// ---------------------------------------------------------------------------------------------
// The local planner's target and the turn in place
// ---------------------------------------------------------------------------------------------

TEST(In2botLookahead, PointsZeroPointEightMetresAlongThePathFromItsNearestPoint) {
  std::vector<Eigen::Vector2d> path;
  std::vector<double> arc;
  for (int i = 0; i <= 10; ++i) {
    path.emplace_back(i, 0.0);
    arc.push_back(i);
  }
  const In2botConfig config;
  std::size_t nearest = 0;
  // Robot at (2.1, 0.3): nearest point (2, 0); 2 + 0.8 = 2.8 m along: (2.8, 0).
  const Eigen::Vector2d target = lookaheadTarget(path, arc, {2.1, 0.3}, nearest, config);
  EXPECT_EQ(nearest, 2u);
  EXPECT_NEAR(target.x(), 2.8, 1e-12);
  EXPECT_NEAR(target.y(), 0.0, 1e-12);
  // Within 3 m of the end (10, 0): the end.
  EXPECT_EQ(lookaheadTarget(path, arc, {7.5, 0.0}, nearest, config), Eigen::Vector2d(10.0, 0.0));
}

TEST(In2botTurnInPlace, TurnsTowardATargetMoreThan42DegreesOff) {
  const core::Pose2 pose{0.0, 0.0, 0.0};
  const auto at_deg = [](double deg) {
    return Eigen::Vector2d(std::cos(deg * std::numbers::pi / 180), std::sin(deg * std::numbers::pi / 180));
  };
  EXPECT_EQ(turnInPlaceRate(pose, at_deg(43.0), 42.0, 1.0), 1.0);    // left
  EXPECT_EQ(turnInPlaceRate(pose, at_deg(-43.0), 42.0, 1.0), -1.0);  // right
  EXPECT_FALSE(turnInPlaceRate(pose, at_deg(41.0), 42.0, 1.0).has_value());
  // Straight behind, 180 deg, wraps to -180: turns right, as the team's sign test does.
  EXPECT_EQ(turnInPlaceRate(pose, {-1.0, 0.0}, 42.0, 1.0), -1.0);
}

TEST(In2botController, WaitsForItsFirstPathThenDrives) {
  // An empty world: the first tick maps the scan, plans to the goal 10 m ahead and drives;
  // the clear field aligned with the target gives the clear-path speed.
  In2botController controller{In2botConfig{}};
  EpisodeInfo info;
  info.goal = {0.0, 10.0};
  controller.reset(info);
  const core::LaserScan scan = uniformScan(core::LidarConfig{}, kInf);
  Observation obs;
  obs.scan = &scan;
  obs.goal = info.goal;
  obs.odom_pose = obs.scan_odom_pose = {0.0, 0.0, std::numbers::pi / 2};
  const core::Twist command = controller.act(obs);
  EXPECT_EQ(controller.stateLabel(), "ClearPath");
  EXPECT_EQ(command.linear, 2.0);
}

}  // namespace
}  // namespace barn::controllers
