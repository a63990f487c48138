#include "barn/nav/ros_global_planner.hpp"

#include <cmath>
#include <numbers>
#include <string>
#include <vector>

#include <gtest/gtest.h>

#include "barn/core/config.hpp"
#include "barn/nav/global_planner.hpp"
#include "barn/nav/navfn.hpp"

namespace barn::nav {
namespace {

constexpr double kPi = std::numbers::pi;

// A cost grid of 1 m cells drawn as a picture, row 0 at the top (largest y): '.' free (0),
// '#' lethal (254), '?' unknown (255), 'i' inscribed (253), a digit d: cost 10 d.
struct Picture {
  std::vector<std::uint8_t> costs;
  CostGrid grid;
  explicit Picture(const std::vector<std::string>& rows) {
    const int nx = static_cast<int>(rows.front().size());
    const int ny = static_cast<int>(rows.size());
    costs.assign(static_cast<std::size_t>(nx * ny), 0);
    for (int r = 0; r < ny; ++r)
      for (int x = 0; x < nx; ++x) {
        const char ch = rows[static_cast<std::size_t>(r)][static_cast<std::size_t>(x)];
        std::uint8_t c = 0;
        if (ch == '#') c = kLethalCost;
        else if (ch == '?') c = kUnknownCost;
        else if (ch == 'i') c = kInscribedCost;
        else if (ch >= '0' && ch <= '9') c = static_cast<std::uint8_t>(10 * (ch - '0'));
        costs[static_cast<std::size_t>(x + nx * (ny - 1 - r))] = c;
      }
    grid = CostGrid{costs.data(), nx, ny, Eigen::Vector2d::Zero(), 1.0};
  }
};

// The robot or goal at the centre of cell (x, y) of a 1 m grid at the origin.
core::Pose2 centreOf(int x, int y, double yaw = 0.0) { return {x + 0.5, y + 0.5, yaw}; }
Eigen::Vector2d centre(int x, int y) { return {x + 0.5, y + 0.5}; }

RosGlobalPlannerConfig oldNavFn(bool quadratic = true) {
  RosGlobalPlannerConfig c;
  c.old_navfn_behavior = true;
  c.use_quadratic = quadratic;
  return c;
}

int reachedCells(const RosGlobalPlanner& planner, const CostGrid& grid) {
  int reached = 0;
  for (int y = 0; y < grid.ny; ++y)
    for (int x = 0; x < grid.nx; ++x) reached += planner.potential(x, y) < RosGlobalPlanner::kPotHigh ? 1 : 0;
  return reached;
}

// ---------------------------------------------------------------------------------------------
// Configuration

TEST(RosGlobalPlannerConfig, DefaultsAreRosDefaults) {
  // planner_core.cpp's params and cfg/GlobalPlanner.cfg's defaults.
  const RosGlobalPlannerConfig c;
  EXPECT_TRUE(c.use_dijkstra);
  EXPECT_TRUE(c.use_quadratic);
  EXPECT_FALSE(c.use_grid_path);
  EXPECT_FALSE(c.old_navfn_behavior);
  EXPECT_TRUE(c.allow_unknown);
  EXPECT_TRUE(c.outline_map);
  EXPECT_EQ(c.default_tolerance, 0.0);
  EXPECT_EQ(c.cost_factor, 3.0);
  EXPECT_EQ(c.neutral_cost, 50);
  EXPECT_EQ(c.lethal_cost, 253);
  EXPECT_EQ(c.orientation_mode, 1);  // Forward
  EXPECT_EQ(c.orientation_window_size, 1);
  core::Errors errors;
  validate(c, errors, "planner.global_planner");
  EXPECT_TRUE(errors.empty());
}

TEST(RosGlobalPlannerConfig, OutOfRangeValuesAreErrorsNamingTheField) {
  RosGlobalPlannerConfig c;
  c.orientation_mode = 7;
  c.lethal_cost = 256;
  c.cost_factor = 0.0;
  core::Errors errors;
  validate(c, errors, "planner.global_planner");
  ASSERT_EQ(errors.messages().size(), 3u);
  std::string all;
  for (const std::string& m : errors.messages()) all += m + "\n";
  EXPECT_NE(all.find("planner.global_planner.orientation_mode"), std::string::npos) << all;
  EXPECT_NE(all.find("planner.global_planner.lethal_cost"), std::string::npos) << all;
  EXPECT_NE(all.find("planner.global_planner.cost_factor"), std::string::npos) << all;
}

TEST(RosGlobalPlannerConfig, ReadFromTheNestedBlockUnderRosNames) {
  const PlannerConfig c = core::readConfig<PlannerConfig>(core::ConfigNode::parseString(
      "algorithm: global_planner\n"
      "global_planner: {use_dijkstra: false, cost_factor: 0.55, lethal_cost: 240, orientation_mode: 3}\n",
      "planner.yaml"));
  EXPECT_EQ(c.algorithm, PlannerAlgorithm::GlobalPlanner);
  EXPECT_FALSE(c.global_planner.use_dijkstra);
  EXPECT_EQ(c.global_planner.cost_factor, 0.55);
  EXPECT_EQ(c.global_planner.lethal_cost, 240);
  EXPECT_EQ(c.global_planner.orientation_mode, 3);
  EXPECT_TRUE(c.global_planner.use_quadratic);  // not given: the ROS default
  // A misspelt ROS name is an error naming the key, as ROS would silently ignore it (LiCS-KI's
  // use_djikstra).
  EXPECT_THROW(core::readConfig<PlannerConfig>(
                   core::ConfigNode::parseString("global_planner: {use_djikstra: false}\n", "planner.yaml")),
               core::InputError);
}

// ---------------------------------------------------------------------------------------------
// Costs and potentials

TEST(RosGlobalPlanner, DijkstraCostIsNeutralPlusFactorTimesCostCappedBelowLethal) {
  const RosGlobalPlanner planner({});  // factor 3, neutral 50, lethal 253, allow_unknown
  EXPECT_EQ(planner.dijkstraCost(0), 50.0f);     // 50 + 3 * 0
  EXPECT_EQ(planner.dijkstraCost(40), 170.0f);   // 50 + 3 * 40
  EXPECT_EQ(planner.dijkstraCost(67), 251.0f);   // 50 + 201
  EXPECT_EQ(planner.dijkstraCost(68), 252.0f);   // 254, capped at lethal - 1
  EXPECT_EQ(planner.dijkstraCost(251), 252.0f);  // the last passable cost: 251 < 253 - 1
  EXPECT_EQ(planner.dijkstraCost(252), 253.0f);  // 252 is not < 252: lethal
  EXPECT_EQ(planner.dijkstraCost(253), 253.0f);  // inscribed
  EXPECT_EQ(planner.dijkstraCost(254), 253.0f);  // lethal
  EXPECT_EQ(planner.dijkstraCost(255), 252.0f);  // unknown with allow_unknown: 815, capped
  RosGlobalPlannerConfig strict;
  strict.allow_unknown = false;
  strict.cost_factor = 0.8;
  const RosGlobalPlanner navfn_like(strict);
  EXPECT_FLOAT_EQ(navfn_like.dijkstraCost(100), 130.0f);  // 50 + 0.8 * 100 (a float, not truncated)
  EXPECT_EQ(navfn_like.dijkstraCost(255), 253.0f);         // unknown: lethal
}

TEST(RosGlobalPlanner, OneCellCorridorAddsTheCellCostPerCell) {
  // A corridor one cell wide (the outline makes rows 0 and 2 lethal). Precise start at the
  // centre of (1,1): fractions 0, so the 2 x 2 block gets 2 * 50 * (dx dy, (1-dx) dy,
  // dx (1-dy), (1-dx)(1-dy)) = 0, 0, 0, 100 at (1,1), (2,1), (1,2), (2,2): the start cell and
  // the one to its right are both 0. Then + 50 per free cell: (3,1) 50 ... (6,1) 200.
  const Picture map({
      ".........",
      ".........",
      ".........",
  });
  RosGlobalPlannerConfig c;
  c.use_grid_path = true;  // see GradientPathStallsOnATieAtThePreciseStart
  RosGlobalPlanner planner(c);
  const Plan plan = planner.plan(map.grid, centreOf(1, 1), centre(6, 1), 0.0);
  EXPECT_TRUE(plan.found);
  EXPECT_EQ(planner.potential(1, 1), 0.0f);
  EXPECT_EQ(planner.potential(2, 1), 0.0f);
  EXPECT_EQ(planner.potential(1, 2), 0.0f);    // a lethal border cell, seeded all the same
  EXPECT_EQ(planner.potential(2, 2), 100.0f);
  EXPECT_EQ(planner.potential(3, 1), 50.0f);
  EXPECT_EQ(planner.potential(4, 1), 100.0f);
  EXPECT_EQ(planner.potential(6, 1), 200.0f);
  EXPECT_EQ(plan.cost, 200);
  // old_navfn_behavior: the start cell alone is 0, + 50 per cell: (6,1) is 250.
  RosGlobalPlanner old(oldNavFn());
  ASSERT_TRUE(old.plan(map.grid, centreOf(1, 1), centre(6, 1), 0.0).found);
  EXPECT_EQ(old.potential(2, 1), 50.0f);
  EXPECT_EQ(old.potential(6, 1), 250.0f);
}

TEST(RosGlobalPlanner, PreciseStartOnACellCornerWeighsTheFourCellsEqually) {
  // The robot at (3, 3) m, the corner of cells (2,2), (3,2), (2,3), (3,3): map coordinates
  // 3 - 0.5 = 2.5, so k = (2,2), dx = dy = 0.5 and each of the four gets 2 * 50 * 0.25 = 25.
  const Picture map({
      ".......",
      ".......",
      ".......",
      ".......",
      ".......",
      ".......",
  });
  RosGlobalPlanner planner({});
  ASSERT_TRUE(planner.plan(map.grid, {3.0, 3.0, 0.0}, centre(5, 4), 0.0).found);
  EXPECT_EQ(planner.potential(2, 2), 25.0f);
  EXPECT_EQ(planner.potential(3, 2), 25.0f);
  EXPECT_EQ(planner.potential(2, 3), 25.0f);
  EXPECT_EQ(planner.potential(3, 3), 25.0f);
}

// A 7 x 7 free map: with the outline, a 5 x 5 free interior, cells 1 ... 5.
const std::vector<std::string> kFree7 = {
    ".......", ".......", ".......", ".......", ".......", ".......", ".......",
};

TEST(RosGlobalPlanner, QuadraticCalculatorInterpolatesTheDiagonal) {
  // old_navfn_behavior (start cell 0, its 4 neighbours queued), from (1,1) to (5,5).
  // Cycle 1: (2,1) and (1,2) each have one reached neighbour (0): 0 + 50 = 50.
  // Cycle 2: (3,1), (1,3): one-sided again, 50 + 50 = 100. (2,2): both sides 50, so
  // difference 0 < 50 and the quadratic gives 50 + 50 * 0.7040 = 85.2.
  // Cycle 3: (3,2): left (2,2) 85.2, up (3,1) 100; difference 14.8, r = 0.296:
  // 85.2 + 50 (-0.2301 r^2 + 0.5307 r + 0.7040) = 85.2 + 50 * 0.840927 = 127.246.
  const Picture map(kFree7);
  RosGlobalPlanner planner(oldNavFn(true));
  ASSERT_TRUE(planner.plan(map.grid, centreOf(1, 1), centre(5, 5), 0.0).found);
  EXPECT_EQ(planner.potential(1, 1), 0.0f);
  EXPECT_EQ(planner.potential(2, 1), 50.0f);
  EXPECT_EQ(planner.potential(1, 2), 50.0f);
  EXPECT_EQ(planner.potential(3, 1), 100.0f);
  EXPECT_FLOAT_EQ(planner.potential(2, 2), 85.2f);
  EXPECT_NEAR(planner.potential(3, 2), 127.246f, 1e-3);
  EXPECT_NEAR(planner.potential(2, 3), 127.246f, 1e-3);
}

TEST(RosGlobalPlanner, SimpleCalculatorGivesManhattanDistanceTimesNeutral) {
  // PotentialCalculator: lowest neighbour + 50, so 50 (|x - 1| + |y - 1|) from (1,1):
  // (2,2) 100 (the quadratic's 85.2), (3,2) 150, (5,1) 200, goal (5,5) 400.
  const Picture map(kFree7);
  RosGlobalPlanner planner(oldNavFn(false));
  const Plan plan = planner.plan(map.grid, centreOf(1, 1), centre(5, 5), 0.0);
  ASSERT_TRUE(plan.found);
  EXPECT_EQ(planner.potential(2, 2), 100.0f);
  EXPECT_EQ(planner.potential(3, 2), 150.0f);
  EXPECT_EQ(planner.potential(5, 1), 200.0f);
  EXPECT_EQ(planner.potential(5, 5), 400.0f);
  EXPECT_EQ(plan.cost, 400);
}

TEST(RosGlobalPlanner, PathGoesThroughTheOnlyGapInAWall) {
  // A wall at x = 5 over rows 2 ... 5 of the free rows 1 ... 5: one gap, at y = 1; the robot
  // (a little off its cell's centre) left of the wall, the goal right of it.
  const Picture map({
      "...........",
      ".....#.....",
      ".....#.....",
      ".....#.....",
      ".....#.....",
      "...........",
      "...........",
  });
  for (const bool grid_path : {false, true}) {
    RosGlobalPlannerConfig c;
    c.use_grid_path = grid_path;
    RosGlobalPlanner planner(c);
    const Plan plan = planner.plan(map.grid, {2.7, 4.8, 0.0}, centre(8, 4), 0.0);
    ASSERT_TRUE(plan.found) << grid_path;
    bool through_gap = false;
    for (const Eigen::Vector2d& p : plan.path) {
      const int x = static_cast<int>(std::floor(p.x())), y = static_cast<int>(std::floor(p.y()));
      EXPECT_FALSE(x == 5 && y != 1) << "on the wall at " << p.transpose();
      through_gap = through_gap || (x == 5 && y == 1);
    }
    EXPECT_TRUE(through_gap) << grid_path;
  }
}

// ---------------------------------------------------------------------------------------------
// A* against Dijkstra

TEST(RosGlobalPlanner, AStarReachesFewerCellsAndFindsTheSameCostOnAnOpenMap) {
  // 12 x 9, free inside the outline; from (2,4) to (9,4), 7 cells right; old_navfn_behavior
  // and the simple calculator for both, so each step costs 50 and the goal 7 * 50 = 350.
  // A*: f = potential + 50 * Manhattan distance is 350 along row 4 and 450 beside it, so it
  // takes the 8 cells of row 4 from the queue and reaches those, the 7 cells above and the 7
  // below (2 ... 8) and (1,4): 23 cells. Dijkstra's wavefront reaches every cell within 6
  // steps of the start inside the walls (8 + 2 * 7 + 2 * 6 + 2 * 5 = 44) before the goal.
  const Picture map({
      "............",
      "............",
      "............",
      "............",
      "............",
      "............",
      "............",
      "............",
      "............",
  });
  RosGlobalPlannerConfig astar_config = oldNavFn(false);
  astar_config.use_dijkstra = false;
  astar_config.use_grid_path = true;
  RosGlobalPlannerConfig dijkstra_config = oldNavFn(false);
  dijkstra_config.use_grid_path = true;
  RosGlobalPlanner astar(astar_config);
  RosGlobalPlanner dijkstra(dijkstra_config);
  const Plan a = astar.plan(map.grid, centreOf(2, 4), centre(9, 4), 0.0);
  const int a_reached = reachedCells(astar, map.grid);
  const Plan d = dijkstra.plan(map.grid, centreOf(2, 4), centre(9, 4), 0.0);
  const int d_reached = reachedCells(dijkstra, map.grid);
  ASSERT_TRUE(a.found);
  ASSERT_TRUE(d.found);
  EXPECT_EQ(a.cost, 350);
  EXPECT_EQ(d.cost, 350);
  EXPECT_EQ(astar.lastExpanded(), 8u);
  EXPECT_EQ(a_reached, 23);
  EXPECT_GE(d_reached, 44);
  EXPECT_EQ(a.path, d.path);  // the straight row, cell centres
}

TEST(RosGlobalPlanner, AStarStepCostWrapsAsAnUnsignedChar) {
  // A*'s step cost is (costmap cost + neutral) as an unsigned char, without cost_factor: an
  // unknown cell (255) costs 305 mod 256 = 49, one less than a free cell; a cell of cost 90
  // costs 140. In the corridor (old_navfn_behavior, simple): (2,1) 50, (3,1) unknown 99,
  // (4,1) cost 90: 239, (5,1) 289.
  const Picture map({
      ".........",
      "...?9....",
      ".........",
  });
  RosGlobalPlannerConfig c = oldNavFn(false);
  c.use_dijkstra = false;
  RosGlobalPlanner planner(c);
  ASSERT_TRUE(planner.plan(map.grid, centreOf(1, 1), centre(5, 1), 0.0).found);
  EXPECT_EQ(planner.potential(2, 1), 50.0f);
  EXPECT_EQ(planner.potential(3, 1), 99.0f);
  EXPECT_EQ(planner.potential(4, 1), 239.0f);
  EXPECT_EQ(planner.potential(5, 1), 289.0f);
}

// ---------------------------------------------------------------------------------------------
// Unknown space, outline, tolerance

TEST(RosGlobalPlanner, UnknownCellsArePassableOnlyWithAllowUnknown) {
  // Two unknown cells across the corridor. allow_unknown: each costs 255 * 3 + 50, capped at
  // 252; from the precise start ((1,1) and (2,1) at 0): (3,1) 252, (4,1) 504, (6,1) 604.
  const Picture map({
      ".........",
      "...??....",
      ".........",
  });
  RosGlobalPlannerConfig lenient_config;
  lenient_config.use_grid_path = true;
  RosGlobalPlanner lenient(lenient_config);
  const Plan plan = lenient.plan(map.grid, centreOf(1, 1), centre(6, 1), 0.0);
  ASSERT_TRUE(plan.found);
  EXPECT_EQ(lenient.potential(3, 1), 252.0f);
  EXPECT_EQ(lenient.potential(4, 1), 504.0f);
  EXPECT_EQ(plan.cost, 604);
  RosGlobalPlannerConfig strict_config;
  strict_config.allow_unknown = false;
  RosGlobalPlanner strict(strict_config);
  EXPECT_FALSE(strict.plan(map.grid, centreOf(1, 1), centre(6, 1), 0.0).found);
  EXPECT_EQ(strict.potential(3, 1), RosGlobalPlanner::kPotHigh);
}

TEST(RosGlobalPlanner, OutlineMapMakesTheBorderLethal) {
  // The goal in the bottom row: lethal with outline_map, so never reached; without it the
  // row is free and the plan ends there.
  const Picture map(kFree7);
  RosGlobalPlannerConfig c;
  c.use_grid_path = true;
  RosGlobalPlanner outlined(c);
  EXPECT_FALSE(outlined.plan(map.grid, centreOf(3, 3), centre(3, 0), 0.0).found);
  EXPECT_EQ(outlined.potential(0, 3), RosGlobalPlanner::kPotHigh);
  c.outline_map = false;
  RosGlobalPlanner open(c);
  const Plan plan = open.plan(map.grid, centreOf(3, 3), centre(3, 0), 0.0);
  ASSERT_TRUE(plan.found);
  EXPECT_EQ(plan.path.back(), centre(3, 0));
}

TEST(RosGlobalPlanner, DefaultToleranceIsUnusedAsInNoetic) {
  // A lethal goal cell is never reached, so there is no plan; noetic's makePlan takes a
  // tolerance but never searches around the goal, so default_tolerance changes nothing.
  const Picture map({
      ".......",
      ".......",
      ".......",
      "....#..",
      ".......",
      ".......",
      ".......",
  });
  for (const double tolerance : {0.0, 2.0}) {
    RosGlobalPlannerConfig c;
    c.default_tolerance = tolerance;
    RosGlobalPlanner planner(c);
    EXPECT_FALSE(planner.plan(map.grid, centreOf(1, 3), centre(4, 3), 0.0).found) << tolerance;
  }
}

TEST(RosGlobalPlanner, ClearEndpointGivesEvenLethalCellsNearTheGoalAPotential) {
  // Simple calculator, precise start at (1,2) (seeds (1,2), (2,2), (1,3) 0 and (2,3) 100),
  // then 50 per step: (3,2) 50, (4,2) 100, round the lethal (5,2) through (5,1), (5,3) 200
  // to the goal (6,2) at 300. clearEndpoint then gives each cell of the 5 x 5 block round the
  // goal that has none the lowest neighbour + (cost + 50) as an unsigned char: the lethal
  // (5,2) gets 100 + (254 + 50 - 256) = 148, below its free neighbours, and the grid path
  // from the goal steps through it.
  const Picture map({
      ".........",
      ".........",
      ".....#...",
      ".........",
      ".........",
  });
  RosGlobalPlannerConfig c;
  c.use_quadratic = false;
  c.use_grid_path = true;
  RosGlobalPlanner planner(c);
  const Plan plan = planner.plan(map.grid, centreOf(1, 2), centre(6, 2), 0.0);
  ASSERT_TRUE(plan.found);
  EXPECT_EQ(planner.potential(4, 2), 100.0f);
  EXPECT_EQ(planner.potential(5, 1), 200.0f);
  EXPECT_EQ(planner.potential(6, 2), 300.0f);
  EXPECT_EQ(planner.potential(5, 2), 148.0f);
  const std::vector<Eigen::Vector2d> expected = {centre(1, 2), centre(2, 2), centre(3, 2), centre(4, 2),
                                                 centre(5, 2), centre(6, 2), centre(6, 2)};
  EXPECT_EQ(plan.path, expected);
  // old_navfn_behavior has no clearEndpoint: the lethal cell stays unreached.
  RosGlobalPlannerConfig old = c;
  old.old_navfn_behavior = true;
  RosGlobalPlanner old_planner(old);
  ASSERT_TRUE(old_planner.plan(map.grid, centreOf(1, 2), centre(6, 2), 0.0).found);
  EXPECT_EQ(old_planner.potential(5, 2), RosGlobalPlanner::kPotHigh);
}

TEST(RosGlobalPlanner, TheRobotCellIsTakenAsFree) {
  // clearRobotCell: a robot standing in a lethal cell still plans out of it.
  const Picture map({
      ".........",
      ".#.......",
      ".........",
  });
  RosGlobalPlanner planner(oldNavFn());
  const Plan plan = planner.plan(map.grid, centreOf(1, 1), centre(5, 1), 0.0);
  ASSERT_TRUE(plan.found);
  EXPECT_EQ(planner.potential(5, 1), 200.0f);  // 4 free cells of 50
}

// ---------------------------------------------------------------------------------------------
// Paths and poses

TEST(RosGlobalPlanner, GridPathIsCellCentresFromStartCellToGoal) {
  // use_grid_path in the corridor: the goal's map point (6, 1), then the lowest neighbour
  // each step down to the start cell; reversed and + 0.5: cell centres (1.5, 1.5) ...
  // (6.5, 1.5), then the goal pose appended.
  const Picture map({
      ".........",
      ".........",
      ".........",
  });
  RosGlobalPlannerConfig c;
  c.use_grid_path = true;
  RosGlobalPlanner planner(c);
  const Plan plan = planner.plan(map.grid, centreOf(1, 1), centre(6, 1), 0.0);
  ASSERT_TRUE(plan.found);
  const std::vector<Eigen::Vector2d> expected = {centre(1, 1), centre(2, 1), centre(3, 1), centre(4, 1),
                                                 centre(5, 1), centre(6, 1), centre(6, 1)};
  EXPECT_EQ(plan.path, expected);
  ASSERT_EQ(plan.yaw.size(), plan.path.size());
}

TEST(RosGlobalPlanner, GradientPathStallsOnATieAtThePreciseStart) {
  // In the one-cell corridor every descent step is a grid step (the walls are unreached).
  // Robot at the centre of (1,1): map point (1.0, 1.0), dy = 0, so (1,1) and (2,1) are both
  // 0. The descent reaches (2,1), 1 cell from the start's x (not < 0.5), and no neighbour is
  // below 0: it stays there until its 4 nx ny steps run out, and makePlan has no plan ("NO
  // PATH!"). With the robot at x = 2.1 m (map 1.6, dx = 0.6) (2,1) is 0.4 from the start:
  // the path ends there.
  const Picture map({
      ".........",
      ".........",
      ".........",
  });
  RosGlobalPlanner planner({});
  EXPECT_FALSE(planner.plan(map.grid, centreOf(1, 1), centre(6, 1), 0.0).found);
  EXPECT_TRUE(planner.lastReached());  // the expansion did reach the goal
  const Plan plan = planner.plan(map.grid, {2.1, 1.5, 0.0}, centre(6, 1), 0.0);
  ASSERT_TRUE(plan.found);
  EXPECT_NEAR(plan.path.front().x(), 2.1, 1e-6);  // the start's own point, (1.6 + 0.5) m
}

TEST(RosGlobalPlanner, OldNavFnBehaviorUsesCellCornersAndAppendsTheGoalTwice) {
  // old_navfn_behavior: no half-cell offset, so cell (x, y) is at (x, y) m; getPlanFromPotential
  // appends the goal and makePlan appends it again.
  const Picture map({
      ".........",
      ".........",
      ".........",
  });
  RosGlobalPlannerConfig c = oldNavFn();
  c.use_grid_path = true;
  RosGlobalPlanner planner(c);
  const Plan plan = planner.plan(map.grid, centreOf(1, 1), centre(4, 1), 0.0);
  ASSERT_TRUE(plan.found);
  const std::vector<Eigen::Vector2d> expected = {{1.0, 1.0}, {2.0, 1.0}, {3.0, 1.0}, {4.0, 1.0}, centre(4, 1), centre(4, 1)};
  EXPECT_EQ(plan.path, expected);
}

TEST(RosGlobalPlanner, GridPathStepsWholeCellsAndGradientPathHalfCellsOnADiagonal) {
  // From (2,2) to (9,9) on an open 12 x 12 map. GridPath: 7 diagonal cell steps (sqrt 2 m
  // each). GradientPath: steps of 0.5 cell along the gradient, near the diagonal.
  std::vector<std::string> rows(12, std::string(12, '.'));
  const Picture map(rows);
  RosGlobalPlannerConfig grid_config;
  grid_config.use_grid_path = true;
  RosGlobalPlanner grid(grid_config);
  const Plan g = grid.plan(map.grid, centreOf(2, 2), centre(9, 9), 0.0);
  ASSERT_TRUE(g.found);
  ASSERT_EQ(g.path.size(), 9u);  // 8 cells + the goal
  for (std::size_t i = 1; i + 1 < g.path.size(); ++i) EXPECT_EQ(g.path[i] - g.path[i - 1], Eigen::Vector2d(1.0, 1.0));

  RosGlobalPlanner gradient({});
  const Plan d = gradient.plan(map.grid, centreOf(2, 2), centre(9, 9), 0.0);
  ASSERT_TRUE(d.found);
  int half_steps = 0;
  for (std::size_t i = 1; i + 1 < d.path.size(); ++i) {
    const double step = (d.path[i] - d.path[i - 1]).norm();
    half_steps += std::fabs(step - 0.5) < 1e-4 ? 1 : 0;
    EXPECT_LT(std::fabs(d.path[i].x() - d.path[i].y()), 0.5) << "off the diagonal at " << i;
  }
  // sqrt(2) 7 = 9.9 cells of half steps: about 20, all but the grid steps at the ends.
  EXPECT_GE(half_steps, 15);
  EXPECT_EQ(d.path.front(), Eigen::Vector2d(2.5, 2.5));  // the start's own map point + 0.5
  EXPECT_EQ(d.path.back(), centre(9, 9));
}

// ---------------------------------------------------------------------------------------------
// Orientation filter

TEST(OrientationFilter, ModesOnAStraightPath) {
  // Four poses along +x; the goal's yaw 0.3, the robot's 1.0.
  const std::vector<Eigen::Vector2d> path = {{0, 0}, {1, 0}, {2, 0}, {3, 0}};
  const auto run = [&](OrientationMode mode) {
    std::vector<double> yaw = {0.0, 0.0, 0.0, 0.3};
    applyOrientationFilter(mode, 1, 1.0, path, yaw);
    return yaw;
  };
  using V = std::vector<double>;
  EXPECT_EQ(run(OrientationMode::None), (V{0.0, 0.0, 0.0, 0.3}));
  EXPECT_EQ(run(OrientationMode::Forward), (V{0.0, 0.0, 0.0, 0.3}));
  EXPECT_EQ(run(OrientationMode::Backward), (V{kPi, kPi, kPi, 0.3}));
  EXPECT_EQ(run(OrientationMode::Leftward), (V{-kPi / 2, -kPi / 2, -kPi / 2, 0.3}));
  EXPECT_EQ(run(OrientationMode::Rightward), (V{kPi / 2, kPi / 2, kPi / 2, 0.3}));
  // From the robot's 1.0 to the goal's 0.3 in 3 equal steps of -0.7 / 3.
  const V interpolated = run(OrientationMode::Interpolate);
  const V expected = {1.0, 1.0 - 0.7 / 3, 1.0 - 1.4 / 3, 0.3};
  for (std::size_t i = 0; i < 4; ++i) EXPECT_NEAR(interpolated[i], expected[i], 1e-12) << i;
  // Forward then interpolate: the whole path is one straight stretch, so the blend starts at
  // pose 0: the same as interpolate.
  const V ftoi = run(OrientationMode::ForwardThenInterpolate);
  for (std::size_t i = 0; i < 4; ++i) EXPECT_NEAR(ftoi[i], expected[i], 1e-12) << i;
}

TEST(OrientationFilter, ModesOnAnLShapedPath) {
  // Right 2, then up 2; the goal's yaw pi/2, the robot's 0.
  const std::vector<Eigen::Vector2d> path = {{0, 0}, {1, 0}, {2, 0}, {2, 1}, {2, 2}};
  const auto run = [&](OrientationMode mode, int window) {
    std::vector<double> yaw = {0.0, 0.0, 0.0, 0.0, kPi / 2};
    applyOrientationFilter(mode, window, 0.0, path, yaw);
    return yaw;
  };
  // Forward, window 1: pose i points from pose i-1 to pose i+1 (clamped): 0, 0,
  // (1,0)->(2,1) pi/4, (2,0)->(2,2) pi/2; the goal keeps pi/2.
  std::vector<double> f1 = run(OrientationMode::Forward, 1);
  const std::vector<double> e1 = {0.0, 0.0, kPi / 4, kPi / 2, kPi / 2};
  for (std::size_t i = 0; i < 5; ++i) EXPECT_NEAR(f1[i], e1[i], 1e-12) << i;
  // Window 2: (0,0)->(2,0) 0, (0,0)->(2,1) atan(1/2), (0,0)->(2,2) pi/4, (1,0)->(2,2) atan 2.
  std::vector<double> f2 = run(OrientationMode::Forward, 2);
  const std::vector<double> e2 = {0.0, std::atan(0.5), kPi / 4, std::atan(2.0), kPi / 2};
  for (std::size_t i = 0; i < 5; ++i) EXPECT_NEAR(f2[i], e2[i], 1e-12) << i;
  // Forward then interpolate: from pose n-3 = 2 (pi/4) back, pose 1 (0) turns by pi/4 > 0.35,
  // so the blend starts at 2: increment (pi/2 - pi/4) / 2 = pi/8, and ROS adds increment * i
  // from i = 2, not increment * (i - 2): pi/4 + 2 pi/8 = pi/2, 5 pi/8, 3 pi/4 (the goal's own
  // pi/2 is overshot). Pose 0 takes the robot's yaw.
  std::vector<double> ft = run(OrientationMode::ForwardThenInterpolate, 1);
  const std::vector<double> et = {0.0, 0.0, kPi / 2, 5 * kPi / 8, 3 * kPi / 4};
  for (std::size_t i = 0; i < 5; ++i) EXPECT_NEAR(ft[i], et[i], 1e-12) << i;
  // Backward: forward + pi, normalised to (-pi, pi].
  std::vector<double> b = run(OrientationMode::Backward, 1);
  const std::vector<double> eb = {kPi, kPi, -3 * kPi / 4, -kPi / 2, kPi / 2};
  for (std::size_t i = 0; i < 5; ++i) EXPECT_NEAR(b[i], eb[i], 1e-12) << i;
  // Leftward / rightward: forward -/+ pi/2.
  std::vector<double> l = run(OrientationMode::Leftward, 1);
  std::vector<double> r = run(OrientationMode::Rightward, 1);
  const std::vector<double> el = {-kPi / 2, -kPi / 2, -kPi / 4, 0.0, kPi / 2};
  const std::vector<double> er = {kPi / 2, kPi / 2, 3 * kPi / 4, kPi, kPi / 2};
  for (std::size_t i = 0; i < 5; ++i) {
    EXPECT_NEAR(l[i], el[i], 1e-12) << i;
    EXPECT_NEAR(r[i], er[i], 1e-12) << i;
  }
}

TEST(OrientationFilter, PlanPosesFaceAlongThePathByDefault) {
  // orientation_mode 1 (Forward) through makePlan on the corridor: every pose faces +x (0),
  // the goal pose keeps its yaw (0.5).
  const Picture map({
      ".........",
      ".........",
      ".........",
  });
  RosGlobalPlannerConfig c;
  c.use_grid_path = true;
  RosGlobalPlanner planner(c);
  const Plan plan = planner.plan(map.grid, centreOf(1, 1, 2.0), centre(6, 1), 0.5);
  ASSERT_TRUE(plan.found);
  ASSERT_EQ(plan.yaw.size(), 7u);
  for (std::size_t i = 0; i + 1 < plan.yaw.size(); ++i) EXPECT_EQ(plan.yaw[i], 0.0) << i;
  EXPECT_EQ(plan.yaw.back(), 0.5);
}

// ---------------------------------------------------------------------------------------------
// Against NavFn

// A 12 x 10 map of 1 m cells with an obstacle at (5, 4), inflated: the cell (3, 4) beside
// the robot at (2, 4) is 2 m from it.
Costmap inflatedMap() {
  CostmapConfig c;
  c.resolution = 1.0;
  c.width = 12.0;
  c.height = 10.0;
  c.origin_x = c.origin_y = 0.0;
  c.inflation_radius = 3.0;
  c.cost_scaling_factor = 1.0;
  Costmap map(c, 0.5);
  map.markObstacle(centre(5, 4));
  map.update();
  return map;
}

TEST(RosGlobalPlanner, WeighsCostsMoreThanNavFn) {
  // The cell right of the robot has costmap cost c (252 exp(-(2 - 0.5)) = 56). Both start
  // from a robot cell of 0 (old_navfn_behavior for GlobalPlanner), and that cell is reached
  // from one side: NavFn gives it int(50 + 0.8 c) = 94, GlobalPlanner 50 + 3 c = 218.
  const Costmap map = inflatedMap();
  const int c = map.cost(3, 4);
  ASSERT_EQ(c, 56);
  NavFn navfn(false);
  navfn.setCostmap(map);
  ASSERT_TRUE(navfn.propagate({2, 4}, {8, 4}));
  EXPECT_EQ(navfn.potential(3, 4), 94.0f);
  RosGlobalPlanner planner(oldNavFn());
  ASSERT_TRUE(planner.plan(map, centreOf(2, 4), centre(8, 4), 0.0).found);
  EXPECT_EQ(planner.potential(3, 4), 218.0f);
}

TEST(RosGlobalPlanner, CostFactorThreeLeavesCostlyCellsSoonerThanNavFnsWeight) {
  // From (1,1) to (11,1) along row 1, which has 6 cells of cost 10 (x = 4 ... 9); row 2 is
  // free. The grid path follows the potential down from the goal. In row 1 the potential
  // rises by 50 + 0.8 * 10 = 58 per costly cell with NavFn's weight, by 50 + 3 * 10 = 80 with
  // GlobalPlanner's; in the free row 2 beside it by about 47 (interpolated). So from the start
  // the path stays in row 1 for 4 costly cells with 0.8 and steps up after the first with 3.
  const Picture map({
      ".............",
      ".............",
      ".............",
      "....111111...",
      ".............",
  });
  for (const double factor : {0.8, 3.0}) {
    RosGlobalPlannerConfig c;
    c.cost_factor = factor;
    c.use_grid_path = true;
    RosGlobalPlanner planner(c);
    const Plan plan = planner.plan(map.grid, centreOf(1, 1), centre(11, 1), 0.0);
    ASSERT_TRUE(plan.found) << factor;
    int crossed = 0;
    for (const Eigen::Vector2d& p : plan.path) crossed += (std::floor(p.y()) == 1.0 && p.x() > 4.0 && p.x() < 10.0) ? 1 : 0;
    EXPECT_EQ(crossed, factor < 1.0 ? 4 : 1) << factor;
  }
}

// ---------------------------------------------------------------------------------------------
// Through nav::GlobalPlanner

TEST(GlobalPlanner, RunsRosGlobalPlannerAndKeepsNavFnsYaws) {
  const Costmap map = inflatedMap();
  PlannerConfig config;
  config.algorithm = PlannerAlgorithm::GlobalPlanner;
  GlobalPlanner planner(config);
  const Plan plan = planner.plan(map, {1.7, 1.8}, centre(8, 6), 0.0, 1.0);
  ASSERT_TRUE(plan.found);
  EXPECT_EQ(plan.path.back(), centre(8, 6));
  EXPECT_EQ(plan.yaw.back(), 1.0);
  EXPECT_GT(planner.lastExpanded(), 0u);
  // NavFn: identity orientation but for the appended goal pose.
  config.algorithm = PlannerAlgorithm::NavFn;
  GlobalPlanner navfn(config);
  const Plan n = navfn.plan(map, {1.7, 1.8}, centre(8, 6), 0.0, 1.0);
  ASSERT_TRUE(n.found);
  ASSERT_EQ(n.yaw.size(), n.path.size());
  for (std::size_t i = 0; i + 1 < n.yaw.size(); ++i) EXPECT_EQ(n.yaw[i], 0.0);
  EXPECT_EQ(n.yaw.back(), 1.0);
}

}  // namespace
}  // namespace barn::nav
