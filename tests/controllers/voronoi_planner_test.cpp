// UT AMRL's LiDAR-Voronoi global planner: the graph of a Voronoi diagram, the two searches, the
// hysteresis, the clearing polygon and the point memory, against worked examples.
#include "barn/controllers/voronoi_planner.hpp"

#include <cmath>
#include <limits>
#include <numbers>
#include <vector>

#include <gtest/gtest.h>

#include "scan_fixtures.hpp"

namespace barn::controllers {
namespace {

constexpr double kInf = std::numeric_limits<double>::infinity();
using V = Eigen::Vector2d;

/// The out-edge of `graph` from node `from` to node `to`, or nullptr.
const GraphEdge* edge(const VoronoiGraph& graph, int from, int to) {
  for (const GraphEdge& e : graph.adjacency[static_cast<std::size_t>(from)])
    if (e.to == to) return &e;
  return nullptr;
}

/// The index of the node at `p`, -1 if none.
int nodeAt(const VoronoiGraph& graph, const V& p) {
  for (std::size_t i = 0; i < graph.nodes.size(); ++i)
    if ((graph.nodes[i] - p).norm() < 1e-6) return static_cast<int>(i);
  return -1;
}

// ---- The graph ----

TEST(VoronoiGraph, FourCornersOfASquareMeetInOneVertexAtTheCentreOnInfiniteEdgesOnly) {
  // The four corners of a 20 dm square are cocircular: one Voronoi vertex, at the centre
  // (10, 10), where the four bisectors meet; each runs off to infinity, so no edge is finite.
  const std::vector<V> sites = {{0, 0}, {20, 0}, {20, 20}, {0, 20}};
  const VoronoiGraph g = buildVoronoiGraph(sites, 0, 2, 10.0);
  ASSERT_EQ(g.nodes.size(), 3u);  // the vertex, the start, the goal
  EXPECT_NEAR(g.nodes[0].x(), 10.0, 1e-9);
  EXPECT_NEAR(g.nodes[0].y(), 10.0, 1e-9);
  EXPECT_EQ(g.start, 1);
  EXPECT_EQ(g.goal, 2);
  // The start reaches the vertex of its cell (gap 10); the vertex is on no finite edge, so
  // (as in the team's vertex-keyed map) it does not lead to the goal.
  ASSERT_NE(edge(g, g.start, 0), nullptr);
  EXPECT_EQ(edge(g, g.start, 0)->gap, 10.0);
  EXPECT_EQ(edge(g, 0, g.goal), nullptr);
  EXPECT_FALSE(searchWidest(g, VoronoiPlannerConfig{}).has_value());
}

TEST(VoronoiGraph, AGridOfNineHasOneSquareCellWhoseEdgesSeparateNeighboursOneSideApart) {
  // Sites on a 3 x 3 grid, 20 dm apart. The centre site's cell is the square with corners
  // (10 | 30, 10 | 30); its four sides are the finite edges, each the bisector of the centre
  // and one neighbour, so each gap is the grid side, 20. Everything else runs to infinity.
  std::vector<V> sites;
  for (int i = 0; i < 3; ++i)
    for (int j = 0; j < 3; ++j) sites.emplace_back(20.0 * i, 20.0 * j);
  const int centre = 4, corner = 8;  // (20, 20) and (40, 40)
  const VoronoiGraph g = buildVoronoiGraph(sites, centre, corner, 10.0);
  ASSERT_EQ(g.nodes.size(), 4u + 2u);
  const int a = nodeAt(g, {10, 10}), b = nodeAt(g, {30, 10}), c = nodeAt(g, {30, 30}), d = nodeAt(g, {10, 30});
  ASSERT_TRUE(a >= 0 && b >= 0 && c >= 0 && d >= 0);
  for (auto [p, q] : std::vector<std::pair<int, int>>{{a, b}, {b, c}, {c, d}, {d, a}}) {
    ASSERT_NE(edge(g, p, q), nullptr);
    ASSERT_NE(edge(g, q, p), nullptr);
    EXPECT_NEAR(edge(g, p, q)->gap, 20.0, 1e-9);
  }
  EXPECT_EQ(edge(g, a, c), nullptr);  // no diagonals
  // The start (the centre site) reaches all four corners of its cell; the goal (40, 40) owns
  // only the vertex (30, 30).
  for (int v : {a, b, c, d}) EXPECT_NE(edge(g, g.start, v), nullptr);
  EXPECT_NE(edge(g, c, g.goal), nullptr);
  EXPECT_EQ(edge(g, a, g.goal), nullptr);
  // Start -> (30, 30) -> goal: f of (30, 30) = 14.1 + 20 + 80 is the least.
  const auto path = searchWidest(g, VoronoiPlannerConfig{});
  ASSERT_TRUE(path.has_value());
  ASSERT_EQ(path->points.size(), 3u);
  EXPECT_NEAR((path->points[1] - V(30, 30)).norm(), 0.0, 1e-9);
  EXPECT_EQ(path->average_gap, 10.0);  // both edges are the start's and the goal's, gap 10
}

// ---- The searches ----

/// start (0, 0), goal (100, 0); a short narrow route over A (50, 10), gap 6, and a longer wide
/// one over B (50, -20), gap 40; both reach the goal with gap 10.
VoronoiGraph twoRoutes(double narrow_gap) {
  VoronoiGraph g;
  g.nodes = {{50, 10}, {50, -20}, {0, 0}, {100, 0}};
  g.start = 2;
  g.goal = 3;
  g.adjacency.resize(4);
  g.adjacency[2] = {{0, narrow_gap}, {1, 40.0}};
  g.adjacency[0] = {{3, 10.0}};
  g.adjacency[1] = {{3, 10.0}};
  return g;
}

TEST(VoronoiSearch, TheGapPenaltyTakesTheWiderRoute) {
  // f(A) = 50.99 + (50 + 10) + 800 / 6 = 244.3, f(B) = 53.85 + (50 + 20) + 800 / 40 = 143.9:
  // B is expanded first and reaches the goal with f = 107.7 + 0 + 800 / 10 = 187.7 < 244.3.
  const VoronoiPlannerConfig c;
  const auto path = searchWidest(twoRoutes(6.0), c);
  ASSERT_TRUE(path.has_value());
  ASSERT_EQ(path->points.size(), 3u);
  EXPECT_EQ(path->points[1], V(50, -20));
  EXPECT_DOUBLE_EQ(path->average_gap, (40.0 + 10.0) / 2.0);
  // Without it the shorter route wins: f(A) = 110.99 < f(B) = 123.85.
  VoronoiPlannerConfig plain;
  plain.gap_weight = 0.0;
  const auto short_path = searchWidest(twoRoutes(6.0), plain);
  ASSERT_TRUE(short_path.has_value());
  EXPECT_EQ(short_path->points[1], V(50, 10));
  EXPECT_DOUBLE_EQ(short_path->average_gap, (6.0 + 10.0) / 2.0);
}

TEST(VoronoiSearch, EdgesNarrowerThanFiveDecimetresAreNeverTaken) {
  // The narrow route with gap 4.9 is closed even without the penalty; the wide one remains.
  VoronoiPlannerConfig plain;
  plain.gap_weight = 0.0;
  const auto path = searchWidest(twoRoutes(4.9), plain);
  ASSERT_TRUE(path.has_value());
  EXPECT_EQ(path->points[1], V(50, -20));
  // Both closed: no path.
  VoronoiGraph g = twoRoutes(4.9);
  g.adjacency[2][1].gap = 4.0;
  EXPECT_FALSE(searchWidest(g, plain).has_value());
}

TEST(VoronoiSearch, TheAverageGapLeavesOutGapsOfFiftyAndMore) {
  // Gaps 40 and 10 count; a 60 on the way would not: (40 + 10) / 2 either way.
  VoronoiGraph g = twoRoutes(6.0);
  g.adjacency[2][1].gap = 60.0;
  const auto path = searchWidest(g, VoronoiPlannerConfig{});
  ASSERT_TRUE(path.has_value());
  EXPECT_EQ(path->points[1], V(50, -20));
  EXPECT_DOUBLE_EQ(path->average_gap, 10.0);
}

TEST(VoronoiSearch, TheRePlanFollowsTheOldPath) {
  // Without a gap term the re-plan ranks by g + h + 50 x (L1 distance to the old path). Old
  // path over B: f(B) = 70 + 70 + 0 = 140 against f(A) = 60 + 60 + 50 x 30 = 1620.
  const std::vector<V> old_path = {{0, 0}, {50, -20}, {100, 0}};
  const auto path = searchNearOldPath(twoRoutes(6.0), old_path, VoronoiPlannerConfig{});
  ASSERT_TRUE(path.has_value());
  EXPECT_EQ(path->points[1], V(50, -20));
  // Over A it keeps A, though B is wider.
  const std::vector<V> old_over_a = {{0, 0}, {50, 10}, {100, 0}};
  const auto kept = searchNearOldPath(twoRoutes(6.0), old_over_a, VoronoiPlannerConfig{});
  ASSERT_TRUE(kept.has_value());
  EXPECT_EQ(kept->points[1], V(50, 10));
}

TEST(VoronoiSearch, EqualCostsFallToTheSmallerCoordinates) {
  // A and B mirrored about the x axis with equal gaps: equal f, so (as Python's heap of
  // (f, (x, y)) tuples) the smaller y goes first when x ties.
  VoronoiGraph g = twoRoutes(40.0);
  g.nodes[0] = {50, 20};
  const auto path = searchWidest(g, VoronoiPlannerConfig{});
  ASSERT_TRUE(path.has_value());
  EXPECT_EQ(path->points[1], V(50, -20));
}

// ---- Hausdorff and the hysteresis ----

TEST(VoronoiHysteresis, HausdorffOfParallelPathsIsTheirOffset) {
  // Two 30 dm segments 6 dm apart, sampled 10 points each: every sample has its twin 6 away.
  EXPECT_NEAR(pathHausdorff(std::vector<V>{{0, 0}, {30, 0}}, std::vector<V>{{0, 6}, {30, 6}}, 10), 6.0, 1e-12);
  // A detour 8 dm out at the middle: its tip (15, 8) is 8 from the straight path's sample
  // (15, 0) and farther from the others; every straight sample is nearer than 8 to the detour.
  EXPECT_NEAR(pathHausdorff(std::vector<V>{{0, 0}, {15, 0}, {30, 0}}, std::vector<V>{{0, 0}, {15, 8}, {30, 0}}, 10), 8.0,
              1e-12);
  EXPECT_NEAR(pathLength(std::vector<V>{{0, 0}, {15, 8}, {30, 0}}), 34.0, 1e-12);  // 2 x 17
}

/// A straight path along y = offset from x = 0 to x = length, with `points` vertices.
GraphPath straight(double offset, double length, int points, double gap) {
  GraphPath p;
  for (int i = 0; i < points; ++i) p.points.emplace_back(length * i / (points - 1), offset);
  p.average_gap = gap;
  return p;
}

TEST(VoronoiHysteresis, AWiderFreshPathReplacesALongOldOne) {
  const VoronoiPlannerConfig c;
  const GraphPath replanned = straight(0, 100, 9, 10.0);
  // 10.6 > 1.05 x 10 and the old path has 9 > 8 points.
  EXPECT_EQ(choosePath(straight(3, 100, 5, 10.6), replanned, straight(0, 100, 9, 10.0).points, c), PathSwitch::WiderGap);
  // 10.5 is not more than 1.05 x 10.
  EXPECT_EQ(choosePath(straight(3, 100, 5, 10.5), replanned, straight(0, 100, 9, 10.0).points, c), PathSwitch::Kept);
  // A short old path (8 points) is not switched for its gap.
  EXPECT_EQ(choosePath(straight(3, 100, 5, 12.0), straight(0, 100, 8, 10.0), straight(0, 100, 8, 10.0).points, c),
            PathSwitch::Kept);
}

TEST(VoronoiHysteresis, ARePlanThatLeftTheOldPathGivesWayToTheFreshOne) {
  const VoronoiPlannerConfig c;
  const GraphPath fresh = straight(20, 100, 5, 10.0);
  // The re-planned route runs 6 dm from the old one (> 5): Diverged; 4 dm: Kept.
  EXPECT_EQ(choosePath(fresh, straight(6, 100, 5, 10.0), straight(0, 100, 5, 10.0).points, c), PathSwitch::Diverged);
  EXPECT_EQ(choosePath(fresh, straight(4, 100, 5, 10.0), straight(0, 100, 5, 10.0).points, c), PathSwitch::Kept);
}

TEST(VoronoiHysteresis, AMuchShorterFreshPathOfNearlyTheSameGapReplacesTheOldOne) {
  const VoronoiPlannerConfig c;
  const GraphPath replanned = straight(0, 100, 5, 10.0);
  const std::vector<V> old_path = replanned.points;
  // 79 < 0.8 x 100 and 9.5 >= 0.95 x 10: Shorter. 81 dm is not short enough; gap 9.4 too narrow.
  EXPECT_EQ(choosePath(straight(0, 79, 5, 9.5), replanned, old_path, c), PathSwitch::Shorter);
  EXPECT_EQ(choosePath(straight(0, 81, 5, 9.5), replanned, old_path, c), PathSwitch::Kept);
  EXPECT_EQ(choosePath(straight(0, 79, 5, 9.4), replanned, old_path, c), PathSwitch::Kept);
}

// ---- The clearing polygon ----

TEST(ScanPolygon, CountsCrossingsSoANotchIsOutside) {
  // A U: the square 0..10 with the notch x 4..6, y 3..10 cut from its top.
  const std::vector<V> u = {{0, 0}, {10, 0}, {10, 10}, {6, 10}, {6, 3}, {4, 3}, {4, 10}, {0, 10}};
  const ScanPolygon polygon(u);
  EXPECT_TRUE(polygon.contains({2, 5}));
  EXPECT_TRUE(polygon.contains({8, 9}));
  EXPECT_TRUE(polygon.contains({5, 1}));
  EXPECT_FALSE(polygon.contains({5, 5}));   // in the notch
  EXPECT_FALSE(polygon.contains({11, 5}));  // outside the box
  EXPECT_FALSE(polygon.contains({5, -1}));
}

// ---- The planner ----

/// The default LiDAR at the robot centre, every beam empty but the one nearest `bearing`.
core::LaserScan oneReturn(double bearing, double range) {
  core::LaserScan scan = uniformScan(centredLidar(), kInf);
  const auto i = static_cast<std::size_t>(std::lround((bearing - scan.angle_min) / scan.angle_increment));
  scan.ranges[i] = range;
  return scan;
}

TEST(VoronoiPlanner, RoundsReturnsToEvenDecimetresHalvesToEven) {
  // Three returns straight along +x from the origin, 0.5, 1.5 and 2.5 m: 5, 15 and 25 dm,
  // halved 2.5, 7.5 and 12.5, rounded as Python's round() (halves to even) 2, 8 and 12, doubled.
  VoronoiPlanner planner{VoronoiPlannerConfig{}};
  core::LaserScan scan;
  scan.angle_min = 0.0;
  scan.angle_increment = 0.0;
  scan.ranges = {0.5, 1.5, 2.5};
  const core::Pose2 robot{0.0, 0.0, 0.0};
  planner.plan(scan, robot, robot);
  const std::vector<GridPoint> expected = {{4, 0}, {16, 0}, {24, 0}};
  EXPECT_EQ(planner.memory(), expected);
}

TEST(VoronoiPlanner, AScanClearsTheRememberedPointsItSeesThrough) {
  // Only finite Voronoi edges join the graph, so a lone wall across open ground cannot be gone
  // round (the ways past its ends run to infinity) and the cycle would fail and clear the
  // memory; with no gap limit the path simply crosses it.
  VoronoiPlannerConfig crossing;
  crossing.min_gap = 0.0;
  VoronoiPlanner planner{crossing};
  const core::Pose2 robot{0.0, 0.0, 0.0};
  // A wall 1 m ahead, then the same bearings open: the wall's points fall inside the new
  // polygon (inf beams reach 5 m) and go; a point seen once behind-left stays, outside it.
  core::LaserScan wall_scan = wallScan(centredLidar(), 1.0);
  for (double& r : wall_scan.ranges)
    if (r > 3.0) r = kInf;  // the wall within 3 m: |y| <= 2.83, all inside 5 m
  planner.plan(wall_scan, robot, robot);
  const std::size_t wall = planner.memory().size();
  EXPECT_GT(wall, 10u);
  for (const GridPoint& p : planner.memory()) EXPECT_EQ(p.x, 10);
  planner.plan(oneReturn(2.3, 1.0), robot, robot);  // one return 1 m away at 132 degrees
  // (-0.666, 0.746) m: (-3.33, 3.73) half-decimetres round to (-3, 4), so (-6, 8) dm.
  ASSERT_EQ(planner.memory(), (std::vector<GridPoint>{{-6, 8}}));
  // A later scan facing -y sees all but the wedge from 45 to 135 degrees; the point, at 127
  // degrees, is in that wedge, outside the polygon, and is kept.
  planner.plan(uniformScan(centredLidar(), kInf), robot, {0.0, 0.0, -std::numbers::pi / 2.0});
  EXPECT_EQ(planner.memory().size(), 1u);
}

TEST(VoronoiPlanner, InTheOpenThePathRunsThroughACornerOfTheStartsCell) {
  // Nothing seen, facing +y: the sites are the goal (0, 100) dm, the start and the half
  // ellipse whose ends (+-20, 0) are level with the start. Their bisectors with the start
  // (x = +-10) and the start-goal bisector (y = 50) meet at (+-10, 50): the start's cell's
  // corners, the only ways to the goal. Both have f = 50.99 + 60 + 80; x decides: (-10, 50).
  VoronoiPlanner planner{VoronoiPlannerConfig{}};
  const core::Pose2 robot{0.0, 0.0, std::numbers::pi / 2.0};
  ASSERT_TRUE(planner.plan(uniformScan(centredLidar(), kInf), robot, robot));
  const std::vector<V> path = planner.pathMetres();
  ASSERT_EQ(path.size(), 3u);
  EXPECT_NEAR((path[0] - V(0, 0)).norm(), 0.0, 1e-9);
  EXPECT_NEAR((path[1] - V(-1, 5)).norm(), 0.0, 1e-6);
  EXPECT_NEAR((path[2] - V(0, 10)).norm(), 0.0, 1e-9);
  EXPECT_EQ(planner.lastSwitch(), PathSwitch::First);
  // The same again: the re-plan along the old path is the same path; nothing switches.
  ASSERT_TRUE(planner.plan(uniformScan(centredLidar(), kInf), robot, robot));
  EXPECT_EQ(planner.lastSwitch(), PathSwitch::Kept);
  EXPECT_NEAR((planner.pathMetres()[1] - V(-1, 5)).norm(), 0.0, 1e-6);
}

TEST(VoronoiPlanner, NoPathClearsTheMemory) {
  // With every edge ruled too narrow (even the start's and the goal's, gap 10) nothing reaches
  // the goal: the cycle fails and forgets what it saw.
  VoronoiPlannerConfig closed;
  closed.min_gap = 20.0;
  VoronoiPlanner planner{closed};
  const core::Pose2 robot{0.0, 0.0, 0.0};
  EXPECT_FALSE(planner.plan(wallScan(centredLidar(), 1.0), robot, robot));
  EXPECT_TRUE(planner.memory().empty());
  EXPECT_TRUE(planner.path().empty());
}

TEST(VoronoiPlanner, TheArcBehindIsTheTeamsHalfEllipse) {
  // Heading +y: from 90 + 90 = 180 to 360 degrees, (2 cos a, 1.5 sin a) around the centre.
  const std::vector<V> arc = ellipseArc({1.0, 2.0}, std::numbers::pi / 2.0, 2.0, 1.5, 20);
  ASSERT_EQ(arc.size(), 20u);
  EXPECT_NEAR((arc.front() - V(-1.0, 2.0)).norm(), 0.0, 1e-12);
  EXPECT_NEAR((arc.back() - V(3.0, 2.0)).norm(), 0.0, 1e-12);
  for (const V& p : arc) EXPECT_LE(p.y(), 2.0 + 1e-12);  // all behind
}

}  // namespace
}  // namespace barn::controllers
