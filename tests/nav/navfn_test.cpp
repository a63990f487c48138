#include "barn/nav/navfn.hpp"

#include <cmath>

#include <gtest/gtest.h>

#include "barn/core/config.hpp"
#include "barn/nav/global_planner.hpp"

#include "picture_map.hpp"

namespace barn::nav {
namespace {

Costmap emptyMap(int width, int height, double resolution = 1.0, bool track_unknown = false) {
  CostmapConfig c;
  c.resolution = resolution;
  c.width = width * resolution;
  c.height = height * resolution;
  c.origin_x = 0.0;
  c.origin_y = 0.0;
  c.inflation_radius = 0.0;
  c.track_unknown = track_unknown;
  return Costmap(c, 0.0);
}

PlannerConfig navfnConfig(bool allow_unknown = false) {
  PlannerConfig c;
  c.algorithm = PlannerAlgorithm::NavFn;
  c.allow_unknown = allow_unknown;
  return c;
}

// Distance from p to the segment a-b.
double segmentDistance(const Eigen::Vector2d& p, const Eigen::Vector2d& a, const Eigen::Vector2d& b) {
  const Eigen::Vector2d ab = b - a;
  const double t = std::clamp((p - a).dot(ab) / ab.squaredNorm(), 0.0, 1.0);
  return (a + t * ab - p).norm();
}

TEST(NavFn, CellCostsFollowRosMode) {
  const NavFn strict(false);
  EXPECT_EQ(strict.cellCost(0), 50);    // int(50 + 0)
  EXPECT_EQ(strict.cellCost(128), 152);  // int(50 + 102.4)
  EXPECT_EQ(strict.cellCost(177), 191);  // int(50 + 141.6): BARN's first inflated ring
  EXPECT_EQ(strict.cellCost(252), 251);  // int(50 + 201.6)
  EXPECT_EQ(strict.cellCost(253), 254);  // inscribed: impassable
  EXPECT_EQ(strict.cellCost(254), 254);  // lethal: impassable
  EXPECT_EQ(strict.cellCost(255), 254);  // unknown, allow_unknown false: impassable
  const NavFn lenient(true);
  EXPECT_EQ(lenient.cellCost(255), 253);  // unknown, allow_unknown true: the dearest passable
  EXPECT_EQ(lenient.cellCost(253), 254);
}

// An empty 61 x 61 map of 1 m cells, robot at (30, 30), goal at the far corner (58, 58) so
// that the field within 15 cells of the robot is settled by the time the goal is reached.
class EmptyField : public ::testing::Test {
 protected:
  void SetUp() override {
    navfn.setCostmap(map);
    ASSERT_TRUE(navfn.propagate({30, 30}, {58, 58}));
  }
  Costmap map = emptyMap(61, 61);
  NavFn navfn{false};
};

TEST_F(EmptyField, PotentialIsExactlyFiftyPerCellAlongTheAxes) {
  // Along an axis the wave arrives from one side only (the cells beside are higher by at
  // least a cell cost), so each step adds exactly h = 50: potential 50 k.
  EXPECT_EQ(navfn.potential(30, 30), 0.0f);
  for (int k = 1; k <= 15; ++k) {
    EXPECT_EQ(navfn.potential(30 + k, 30), 50.0f * k) << k;
    EXPECT_EQ(navfn.potential(30 - k, 30), 50.0f * k) << k;
    EXPECT_EQ(navfn.potential(30, 30 + k), 50.0f * k) << k;
    EXPECT_EQ(navfn.potential(30, 30 - k), 50.0f * k) << k;
  }
}

TEST_F(EmptyField, PotentialApproximatesFiftyTimesEuclideanDistance) {
  // Off the axes NavFn's update approximates the planar wave 50 |(dx, dy)|, overestimating
  // it: the quadratic fits the 2D solution a + h (r + sqrt(2 - r^2)) / 2 closely (r = 0:
  // 0.704 vs 0.7071; r = 0.5: 0.9119 vs 0.9114), but the scheme is first-order and starts
  // from a point, so the error is largest near the robot and shrinks slowly with distance.
  // (1, 1): both neighbours 50, r = 0: 50 + 50 * 0.704 = 85.2 vs 70.7 (+20 %).
  EXPECT_NEAR(navfn.potential(31, 31), 85.2f, 1e-3);
  // (1, 2): left 100, below 85.2, r = 14.8 / 50 = 0.296,
  //   85.2 + 50 (-0.2301 * 0.0876 + 0.5307 * 0.296 + 0.704) = 85.2 + 42.046 = 127.246;
  // (2, 2): both 127.246, r = 0: 127.246 + 35.2 = 162.446 vs 141.42 (+14.9 %).
  EXPECT_NEAR(navfn.potential(31, 32), 127.246f, 1e-2);
  EXPECT_NEAR(navfn.potential(32, 32), 162.446f, 1e-2);
  // Never below the Euclidean distance (exact on the axes); at 5-10 cells within 11 %, at
  // 10-15 cells within 7 % (measured: 10.6 % and 7.0 %, then 5.4 % at 15-20, 4.4 % at 30-40).
  for (int dx = -15; dx <= 15; ++dx)
    for (int dy = -15; dy <= 15; ++dy) {
      const double distance = std::hypot(dx, dy);
      if (distance < 5.0 || distance > 15.0) continue;
      const double ratio = navfn.potential(30 + dx, 30 + dy) / (50.0 * distance);
      EXPECT_GE(ratio, 1.0 - 1e-6) << dx << ", " << dy;
      EXPECT_LT(ratio, distance < 10.0 ? 1.11 : 1.07) << dx << ", " << dy;
    }
}

TEST_F(EmptyField, BorderIsImpassable) {
  // The outer rows and columns are never reached, although the costmap is free there.
  for (int k = 0; k < 61; ++k) {
    EXPECT_EQ(navfn.potential(k, 0), NavFn::kPotHigh);
    EXPECT_EQ(navfn.potential(0, k), NavFn::kPotHigh);
  }
  // The row next to the border is.
  EXPECT_LT(navfn.potential(30, 1), NavFn::kPotHigh);
  GlobalPlanner planner(navfnConfig());
  EXPECT_FALSE(planner.plan(map, {30.5, 30.5}, {30.5, 0.5}).found);  // goal on the border
  EXPECT_TRUE(planner.plan(map, {30.5, 30.5}, {30.5, 1.5}).found);
  EXPECT_FALSE(planner.plan(map, {60.5, 30.5}, {30.5, 30.5}).found);  // robot on the border
}

// The largest distance of the plan's points (the appended goal excluded) from the segment
// between the robot's and the goal's cells, in cells (1 m cells, origin 0: points are NavFn's
// fractional cell indices, no half-cell offset).
double worstDeviation(const Plan& plan, const Eigen::Vector2d& robot_cell, const Eigen::Vector2d& goal_cell) {
  double worst = 0.0;
  for (std::size_t i = 0; i + 1 < plan.path.size(); ++i) worst = std::max(worst, segmentDistance(plan.path[i], robot_cell, goal_cell));
  return worst;
}

TEST(NavFnPlan, StraightLineInAnEmptyMap) {
  const Costmap map = emptyMap(41, 41);
  GlobalPlanner planner(navfnConfig());
  // Along an axis and along the diagonal the field is symmetric about the line, so the
  // descent follows it: within half a cell (no 45-degree staircase).
  for (const auto& [robot, goal] : std::vector<std::pair<Eigen::Vector2d, Eigen::Vector2d>>{
           {{5, 20}, {35, 20}}, {{20, 35}, {20, 5}}, {{5, 5}, {35, 35}}, {{35, 8}, {8, 35}}}) {
    const Plan plan = planner.plan(map, robot + Eigen::Vector2d(0.5, 0.5), goal + Eigen::Vector2d(0.5, 0.5));
    ASSERT_TRUE(plan.found);
    EXPECT_EQ(plan.path.front(), robot);                      // the robot cell's index
    EXPECT_EQ(plan.path[plan.path.size() - 2], goal);         // the goal cell's index
    EXPECT_EQ(plan.path.back(), goal + Eigen::Vector2d(0.5, 0.5));  // the requested goal
    EXPECT_LT(worstDeviation(plan, robot, goal), 0.5) << robot.transpose() << " -> " << goal.transpose();
    // Half-cell steps: about 2 |goal - robot| points, plus the two end cells.
    EXPECT_NEAR(static_cast<double>(plan.path.size()), 2.0 * (goal - robot).norm() + 2.0, 3.0);
  }
}

TEST(NavFnPlan, NearlyStraightLineAtAnOddAngle) {
  // At 21.8 degrees the field is not symmetric about the line: near the robot the axes are
  // exact and the diagonals overestimated (see PotentialApproximates...), so the descent
  // bends toward the x axis there (0.67 cell off at 2.7 cells from the robot); near the goal
  // the field stops at the wavefront (propagation ends when the goal is reached), so the
  // first step is a grid-mode jump to the lowest 8-neighbour (34, 21), 0.56 cell off.
  // A 45-degree staircase would be up to 4.5 cells off.
  const Costmap map = emptyMap(41, 31);
  GlobalPlanner planner(navfnConfig());
  const Plan plan = planner.plan(map, {5.5, 10.5}, {35.5, 22.5});
  ASSERT_TRUE(plan.found);
  EXPECT_LT(worstDeviation(plan, {5.0, 10.0}, {35.0, 22.0}), 0.75);
  EXPECT_EQ(plan.path[plan.path.size() - 3], Eigen::Vector2d(34.0, 21.0));
  // The goal's potential, 50 per cell over |(30, 12)| = 32.3 cells = 1615, overestimated by
  // the scheme's few %.
  EXPECT_GT(static_cast<double>(plan.cost), 50.0 * std::hypot(30.0, 12.0));
  EXPECT_LT(static_cast<double>(plan.cost), 1.05 * 50.0 * std::hypot(30.0, 12.0));
}

TEST(NavFnPlan, HalfCellOffsetOfRosMapToWorld) {
  // 0.05 m cells with the origin at (-1, -2): the robot at (0.01, 0.01) is in cell (20, 40),
  // whose centre is (0.025, 0.025) but whose NavfnROS point is -1 + 20 * 0.05 = 0.0 and
  // -2 + 40 * 0.05 = 0.0, 0.025 m below and left of the centre.
  CostmapConfig c;
  c.resolution = 0.05;
  c.width = 3.0;
  c.height = 4.0;
  c.origin_x = -1.0;
  c.origin_y = -2.0;
  const Costmap map(c, 0.0);
  GlobalPlanner planner(navfnConfig());
  const Plan plan = planner.plan(map, {0.01, 0.01}, {0.51, 1.01});
  ASSERT_TRUE(plan.found);
  EXPECT_NEAR(plan.path.front().x(), 0.0, 1e-9);
  EXPECT_NEAR(plan.path.front().y(), 0.0, 1e-9);
  EXPECT_NEAR((plan.path.front() - map.cellCentre({20, 40})).norm(), 0.025 * std::sqrt(2.0), 1e-9);
  EXPECT_EQ(plan.path.back(), Eigen::Vector2d(0.51, 1.01));
}

TEST(NavFnPlan, GoesThroughTheGapInAWall) {
  // A wall at x = 10 from y = 1 to 19 with a gap at y = 15..16; robot and goal at y = 5.
  std::vector<std::string> rows(21, std::string(21, '.'));
  for (int y = 1; y <= 19; ++y)
    if (y != 15 && y != 16) rows[static_cast<std::size_t>(20 - y)][10] = '#';
  const Costmap map = pictureMap(rows);
  GlobalPlanner planner(navfnConfig());
  const Plan plan = planner.plan(map, {3.5, 5.5}, {17.5, 5.5});
  ASSERT_TRUE(plan.found);
  // Points are NavFn's fractional cell indices (origin 0, 1 m cells), where index i is the
  // sample of cell i: the nearest sample, round(p), is never an obstacle, and the path
  // crosses the wall's column only in the gap.
  bool crossed = false;
  for (std::size_t i = 0; i + 1 < plan.path.size(); ++i) {
    const Eigen::Vector2d& p = plan.path[i];
    const int x = static_cast<int>(std::lround(p.x()));
    const int y = static_cast<int>(std::lround(p.y()));
    EXPECT_NE(map.cost(x, y), kLethalCost) << p.transpose();
    if (x == 10) {
      crossed = true;
      EXPECT_TRUE(y == 15 || y == 16) << p.transpose();
    }
  }
  EXPECT_TRUE(crossed);
  // Detour: up 10 cells, across, down 10: the path is far longer than the 14-cell line.
  EXPECT_GT(plan.cost, 50 * 25);
}

TEST(NavFnPlan, ImpassableOrWalledInGoalIsNotFound) {
  // (The outer rows and columns are impassable, hence the margin of two.)
  const Costmap map = pictureMap({
      "...........",
      "...........",
      "......###..",
      "......#.#..",
      "......###..",
      "...........",
      "...........",
  });
  GlobalPlanner planner(navfnConfig());
  EXPECT_FALSE(planner.plan(map, {1.5, 3.5}, {6.5, 3.5}).found);   // goal in an obstacle
  EXPECT_FALSE(planner.plan(map, {1.5, 3.5}, {7.5, 3.5}).found);   // goal walled in
  EXPECT_FALSE(planner.plan(map, {1.5, 3.5}, {20.5, 3.5}).found);  // goal off the map
  EXPECT_TRUE(planner.plan(map, {1.5, 3.5}, {9.5, 3.5}).found);    // around the box
}

TEST(NavFnPlan, ToleranceEndsThePlanAtTheNearestReachablePointAroundTheGoal) {
  // NavfnROS default_tolerance. The box covers cells x 6-8, y 2-4, the walled-in goal (7.5, 3.5)
  // its hole. At 1 m the grid of points 1 m apart (x and y 6.5 ... 8.5) is all box: no plan. At
  // 2 m it reaches x 5.5 / 9.5 and y 1.5 / 5.5, outside the box; the nearest reachable points
  // are 2 m away, and the first of them in NavFn's order (rows from y - 2 up, each from x - 2)
  // is (7.5, 1.5).
  const Costmap map = pictureMap({
      "...........",
      "...........",
      "......###..",
      "......#.#..",
      "......###..",
      "...........",
      "...........",
  });
  PlannerConfig config = navfnConfig();
  config.tolerance = 1.0;
  EXPECT_FALSE(GlobalPlanner(config).plan(map, {1.5, 3.5}, {7.5, 3.5}).found);
  config.tolerance = 2.0;
  const Plan plan = GlobalPlanner(config).plan(map, {1.5, 3.5}, {7.5, 3.5});
  ASSERT_TRUE(plan.found);
  EXPECT_EQ(plan.path.back(), Eigen::Vector2d(7.5, 1.5));
  // A reachable goal is the plan's end whatever the tolerance.
  EXPECT_EQ(GlobalPlanner(config).plan(map, {1.5, 3.5}, {9.5, 3.5}).path.back(), Eigen::Vector2d(9.5, 3.5));
}

TEST(NavFnPlan, UnknownSpaceFollowsAllowUnknown) {
  // A never-seen map: every cell unknown (255) except the robot's, which NavfnROS clears.
  const Costmap map = emptyMap(20, 10, 1.0, true);
  ASSERT_EQ(map.cost(10, 5), kUnknownCost);
  GlobalPlanner strict(navfnConfig(false));
  EXPECT_FALSE(strict.plan(map, {3.5, 5.5}, {15.5, 5.5}).found);
  GlobalPlanner lenient(navfnConfig(true));
  const Plan plan = lenient.plan(map, {3.5, 5.5}, {15.5, 5.5});
  ASSERT_TRUE(plan.found);
  // 12 cells along the axis at 253 each: 12 * 253 = 3036.
  EXPECT_EQ(plan.cost, 12 * 253);
}

TEST(NavFnPlan, LeavesAStartInsideAnObstacle) {
  // The robot's cell is treated as free, as NavfnROS clears it before planning.
  const Costmap map = pictureMap({".......", ".......", "..#....", ".......", "......."});
  GlobalPlanner planner(navfnConfig());
  const Plan plan = planner.plan(map, {2.5, 2.5}, {5.5, 2.5});
  ASSERT_TRUE(plan.found);
  EXPECT_EQ(plan.path.front(), Eigen::Vector2d(2.0, 2.0));
  // The clearing is not kept: the next plan from elsewhere sees the obstacle again, so a
  // goal in it fails.
  EXPECT_FALSE(planner.plan(map, {5.5, 2.5}, {2.5, 2.5}).found);
}

TEST(NavFnPlan, SameAnswerOnRepeatedPlans) {
  const Costmap map = pictureMap({
      "..........",
      "...#......",
      "...#..#...",
      "......#...",
      "..........",
  });
  GlobalPlanner planner(navfnConfig());
  const Plan first = planner.plan(map, {1.5, 2.5}, {8.5, 2.5});
  const Plan second = planner.plan(map, {1.5, 2.5}, {8.5, 2.5});
  ASSERT_TRUE(first.found);
  EXPECT_EQ(first.path, second.path);
}

TEST(PlannerConfig, AlgorithmIsReadByItsName) {
  PlannerConfig c;
  EXPECT_EQ(c.algorithm, PlannerAlgorithm::Dijkstra);
  core::Errors ok;
  validate(c, ok, "planner");
  EXPECT_TRUE(ok.empty());
  // The YAML spellings of the enum, as configs and recorded manifests have them.
  PlannerAlgorithm a = PlannerAlgorithm::Dijkstra;
  EXPECT_TRUE(core::enumFromName("navfn", a));
  EXPECT_EQ(a, PlannerAlgorithm::NavFn);
  EXPECT_TRUE(core::enumFromName("global_planner", a));
  EXPECT_EQ(a, PlannerAlgorithm::GlobalPlanner);
  EXPECT_TRUE(core::enumFromName("dijkstra", a));
  EXPECT_EQ(a, PlannerAlgorithm::Dijkstra);
  EXPECT_FALSE(core::enumFromName("astar", a));
}

}  // namespace
}  // namespace barn::nav
