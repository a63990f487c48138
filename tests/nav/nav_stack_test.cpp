#include "barn/nav/nav_stack.hpp"

#include <algorithm>
#include <array>

#include <cmath>
#include <limits>
#include <numbers>
#include <stdexcept>
#include <string>

#include <gmock/gmock.h>
#include <gtest/gtest.h>

#include "barn/nav/footprint.hpp"

namespace barn::nav {
namespace {

// A scan straight ahead (+-0.45 rad, 0.01 rad apart) with returns at `range` on the beams
// between `from` and `to` [rad] and none elsewhere.
core::LaserScan wallScan(double from, double to, double range) {
  core::LaserScan scan;
  scan.angle_min = -0.45;
  scan.angle_increment = 0.01;
  scan.range_min = 0.1;
  scan.range_max = 30.0;
  for (int i = 0; i <= 90; ++i) {
    const double angle = scan.angle(static_cast<std::size_t>(i));
    scan.ranges.push_back(angle >= from && angle <= to ? range : std::numeric_limits<double>::infinity());
  }
  return scan;
}

// The path after one scan from the start, the goal 5 m ahead.
Path pathAfter(NavStack& nav, const core::LaserScan& scan) {
  const core::Pose2 robot{0.0, 0.0, std::numbers::pi / 2};
  nav.reset({0.0, 5.0});
  nav.update(0.0, scan, robot, robot);
  return nav.path();
}

TEST(FootprintRadii, InscribedIsTheNearestEdgeAndCircumscribedTheFarthestVertex) {
  // BARN's 0.42 x 0.33 footprint padded by 0.1: corners (+-0.31, +-0.265). The nearest edges
  // are the sides at y = +-0.265; the corners are sqrt(0.31^2 + 0.265^2) = 0.4078 away.
  const auto corners = core::Rect::centred(0.42, 0.33).grownBy(0.1).corners();
  const FootprintRadii barn = footprintRadii(corners);
  EXPECT_DOUBLE_EQ(barn.inscribed, 0.265);
  EXPECT_NEAR(barn.circumscribed, 0.40783, 1e-5);
  // A triangle (1, 0), (-1, 1), (-1, -1): the edge from (1, 0) to (-1, 1) passes the centre at
  // |1 * 1 - 0 * (-2)| / sqrt(2^2 + 1^2) = 1 / sqrt(5) = 0.4472, nearer than the back edge
  // (x = -1, 1 away); the far vertices are sqrt(2) away.
  const std::array<Eigen::Vector2d, 3> triangle = {Eigen::Vector2d(1.0, 0.0), Eigen::Vector2d(-1.0, 1.0),
                                                   Eigen::Vector2d(-1.0, -1.0)};
  const FootprintRadii tri = footprintRadii(triangle);
  EXPECT_NEAR(tri.inscribed, 1.0 / std::sqrt(5.0), 1e-12);
  EXPECT_NEAR(tri.circumscribed, std::sqrt(2.0), 1e-12);
  // An edge whose nearest point to the centre is its end: the segment (1, 1) - (2, 1) alone
  // (a degenerate two-vertex polygon) is sqrt(2) away at (1, 1).
  const std::array<Eigen::Vector2d, 2> segment = {Eigen::Vector2d(1.0, 1.0), Eigen::Vector2d(2.0, 1.0)};
  EXPECT_NEAR(footprintRadii(segment).inscribed, std::sqrt(2.0), 1e-12);
}

TEST(NavStack, ChangingThePaddingChangesEveryNumberDerivedFromTheFootprint) {
  // The 0.42 x 0.33 footprint padded by p: the costmaps' inscribed radius 0.165 + p, the
  // padded corners (+-(0.21 + p), +-(0.165 + p)), the circumscribed radius
  // hypot(0.21 + p, 0.165 + p); and each costmap costs 253 out to its inscribed radius.
  // p = 0.1: 0.265, hypot(0.31, 0.265) = 0.4078; p = 0.2: 0.365, hypot(0.41, 0.365) = 0.5489.
  for (const auto& [padding, inscribed, circumscribed] :
       {std::array{0.1, 0.265, 0.40783}, std::array{0.2, 0.365, 0.54893}}) {
    NavStackConfig config;
    config.footprint_padding = padding;
    config.global_costmap.inflation_radius = config.local_costmap.inflation_radius = 1.0;
    const NavStack nav(config);
    for (const Costmap* map : {&nav.globalCostmap(), &nav.localCostmap()}) {
      EXPECT_NEAR(map->inscribedRadius(), inscribed, 1e-12) << "padding " << padding;
      // Cell distances: 0.05 m cells, so 0.25 m (5 cells) and 0.35 m (7) are inside, and the
      // next cell beyond the radius costs 252 exp(-10 (d - r)) < 253.
      EXPECT_EQ(map->inflationCost(inscribed - 0.01), kInscribedCost) << "padding " << padding;
      EXPECT_LT(map->inflationCost(inscribed + 0.01), kInscribedCost) << "padding " << padding;
      EXPECT_GT(map->inflationCost(inscribed + 0.01), kFreeCost) << "padding " << padding;
    }
    EXPECT_NEAR(config.circumscribedRadius(), circumscribed, 1e-5);
    const std::vector<Eigen::Vector2d> corners = nav.paddedFootprint();
    ASSERT_EQ(corners.size(), 4u);
    EXPECT_NEAR(corners[0].x(), 0.21 + padding, 1e-12);  // front left
    EXPECT_NEAR(corners[0].y(), 0.165 + padding, 1e-12);
  }
}

TEST(NavStack, AnInscribedPaddingOffsetMovesOnlyItsOwnCostmapsRadius) {
  // Inventec's local costmap: the stack padded by 0.075, the local map's own padding -0.08,
  // so its inscribed radius is 0.165 - 0.08 = 0.085 while the global map keeps 0.165 + 0.075;
  // the footprint the stack clears stays padded by 0.075 (front left corner 0.285, 0.24).
  NavStackConfig config;
  config.footprint_padding = 0.075;
  config.local_costmap.inscribed_padding_offset = -0.08 - 0.075;
  const NavStack nav(config);
  EXPECT_NEAR(nav.globalCostmap().inscribedRadius(), 0.24, 1e-12);
  EXPECT_NEAR(nav.localCostmap().inscribedRadius(), 0.085, 1e-12);
  EXPECT_NEAR(nav.paddedFootprint()[0].x(), 0.285, 1e-12);
  EXPECT_NEAR(nav.paddedFootprint()[0].y(), 0.24, 1e-12);
  // An offset that would shrink the footprint to nothing (0.075 - 0.3 < -0.165) is refused.
  config.local_costmap.inscribed_padding_offset = -0.3;
  core::Errors errors;
  validate(config, errors, "nav");
  ASSERT_EQ(errors.messages().size(), 1u);
  EXPECT_NE(errors.messages().front().find("nav.local_costmap.inscribed_padding_offset"), std::string::npos);
}

TEST(NavStack, ResetForgetsThePreviousEpisodesPlans) {
  // Episode 1 sees a wall ahead-left, episode 2 one ahead-right: the same goal, and costmaps
  // changed the same number of times. Episode 2's path must be what a fresh stack plans, not
  // the first episode's (whose route now runs through the wall).
  const core::LaserScan left = wallScan(0.0, 0.45, 1.0), right = wallScan(-0.45, 0.0, 1.0);
  NavStack fresh({});
  const Path expected = pathAfter(fresh, right);
  NavStack reused({});
  const Path first = pathAfter(reused, left);
  const Path second = pathAfter(reused, right);
  ASSERT_FALSE(expected.empty());
  ASSERT_EQ(second.size(), expected.size());
  for (std::size_t i = 0; i < expected.size(); ++i) EXPECT_EQ(second[i], expected[i]) << i;
  // The two walls really ask for different routes.
  EXPECT_NE(first.size() == expected.size() && std::equal(first.begin(), first.end(), expected.begin()), true);
}

// The wall's returns as odom points: the robot at the origin heading +y, the sensor there too.
std::vector<Eigen::Vector2d> wallPoints(const core::LaserScan& scan, const core::Pose2& sensor) {
  std::vector<Eigen::Vector2d> points;
  for (std::size_t i = 0; i < scan.ranges.size(); ++i)
    if (std::isfinite(scan.ranges[i]))
      points.push_back(sensor.transform(scan.ranges[i] * Eigen::Vector2d(std::cos(scan.angle(i)), std::sin(scan.angle(i)))));
  return points;
}

TEST(NavStack, ThePathRunsFromTheRobotToTheGoalAroundTheWallItSaw) {
  const core::LaserScan wall = wallScan(-0.45, 0.45, 1.0);  // 0.87 m wide, 1 m ahead
  NavStack nav({});
  const Path path = pathAfter(nav, wall);
  ASSERT_TRUE(nav.hasPath());
  // From the robot's cell to the goal's (cell centres: within half a cell diagonal).
  const double half_diagonal = 0.05 * std::sqrt(0.5) + 1e-9;
  EXPECT_LE(path.front().norm(), half_diagonal);
  EXPECT_LE((path.back() - Eigen::Vector2d(0.0, 5.0)).norm(), half_diagonal);
  // No point of the path is within the padded footprint's inscribed radius of the wall.
  const double inscribed = NavStack({}).globalCostmap().inscribedRadius();
  const core::Pose2 robot{0.0, 0.0, std::numbers::pi / 2};
  double closest = std::numeric_limits<double>::infinity();
  for (const Eigen::Vector2d& p : path)
    for (const Eigen::Vector2d& w : wallPoints(wall, robot)) closest = std::min(closest, (p - w).norm());
  EXPECT_GT(closest, inscribed);
  // Without the wall the path is the straight line.
  NavStack open({});
  for (const Eigen::Vector2d& p : pathAfter(open, wallScan(1.0, 1.0, 1.0))) EXPECT_LT(std::abs(p.x()), 0.05);
}

TEST(NavStack, ClearingOutsideARadiusForgetsOnlyTheFarObstacles) {
  const core::LaserScan wall = wallScan(-0.45, 0.45, 1.0);
  const core::Pose2 robot{0.0, 0.0, std::numbers::pi / 2};
  const auto wallRemembered = [&](const NavStack& nav) {
    int marked = 0;
    for (const Eigen::Vector2d& w : wallPoints(wall, robot)) {
      CellIndex cell;
      if (nav.localCostmap().toCell(w, cell) && nav.localCostmap().isObstacle(cell.x, cell.y)) ++marked;
    }
    return marked;
  };
  NavStack nav({});
  pathAfter(nav, wall);
  EXPECT_GT(wallRemembered(nav), 0);
  nav.clearCostmapsOutside(robot.position(), 2.0);  // the wall is 1 m away: kept
  EXPECT_GT(wallRemembered(nav), 0);
  nav.clearCostmapsOutside(robot.position(), 0.5);  // now beyond the radius: forgotten
  EXPECT_EQ(wallRemembered(nav), 0);
}

TEST(NavStack, ThePublishedLocalCostmapIsTheMapOfTheWindowsLastMove) {
  // costmap_2d publishes the rolling map whole only when the window has moved: a node reading
  // that topic alone keeps the last such map while the robot turns on the spot.
  NavStackConfig published_config;
  published_config.local_costmap_view = CostmapView::Published;
  NavStack published(published_config), live({});
  const core::LaserScan wall = wallScan(-0.45, 0.45, 1.0);
  const auto wallMarked = [&](const NavStack& nav, const core::Pose2& sensor) {
    int marked = 0;
    for (const Eigen::Vector2d& w : wallPoints(wall, sensor)) {
      CellIndex cell;
      if (nav.localCostmap().toCell(w, cell) && nav.localCostmap().isObstacle(cell.x, cell.y)) ++marked;
    }
    return marked;
  };
  const auto step = [&](double time, const core::Pose2& robot) {
    core::LaserScan scan = wall;
    scan.stamp = time;
    for (NavStack* nav : {&published, &live}) nav->update(time, scan, robot, robot);
  };
  for (NavStack* nav : {&published, &live}) nav->reset({0.0, 5.0});
  // The first map is published: the wall ahead (+y) is in both views.
  const core::Pose2 facing_y{0.0, 0.0, std::numbers::pi / 2};
  step(0.0, facing_y);
  EXPECT_GT(wallMarked(published, facing_y), 20);
  // The robot turns to +x, 2 cm off the centre: the window stays, so the published map does not
  // hold the wall it sees now.
  const core::Pose2 facing_x{0.02, 0.0, 0.0};
  step(0.05, facing_x);
  EXPECT_GT(wallMarked(live, facing_x), 20);
  EXPECT_EQ(wallMarked(published, facing_x), 0);
  EXPECT_GT(wallMarked(published, facing_y), 20);
  // A full cell from the centre the window moves, and the next map holds the wall.
  const core::Pose2 moved{0.08, 0.0, 0.0};
  step(0.10, moved);
  EXPECT_GT(wallMarked(published, moved), 20);
  EXPECT_EQ(wallMarked(published, moved), wallMarked(live, moved));
}

TEST(NavStack, TheObstacleLayerShowsTheLocalMapsObstaclesWithoutFoldingItsInflation) {
  // Two stacks see the same wall 1 m ahead; one is read through the obstacle layer first.
  NavStack layer_first({}), costs_only({});
  const core::Pose2 robot{0.0, 0.0, std::numbers::pi / 2};
  core::LaserScan wall = wallScan(-0.45, 0.45, 1.0);
  for (NavStack* nav : {&layer_first, &costs_only}) {
    nav->reset({0.0, 5.0});
    nav->update(0.0, wall, robot, robot);
  }
  const Costmap& layer = layer_first.localObstacleLayer();
  int marked = 0;
  for (const Eigen::Vector2d& w : wallPoints(wall, robot)) {
    CellIndex cell;
    ASSERT_TRUE(layer.toCell(w, cell));
    EXPECT_EQ(layer.isObstacle(cell.x, cell.y), costs_only.localCostmap().isObstacle(cell.x, cell.y));
    marked += layer.isObstacle(cell.x, cell.y);
  }
  EXPECT_GT(marked, 20);
  // The wall's inflation is not folded in: its costs may not be read...
  EXPECT_THROW(static_cast<void>(layer.costs()), std::logic_error);
  // ...until the map is read as a costmap, which folds it in: the same costs as the other's.
  const Costmap& folded = layer_first.localCostmap();
  const std::size_t cells = static_cast<std::size_t>(folded.widthCells()) * static_cast<std::size_t>(folded.heightCells());
  const std::uint8_t* a = folded.costs();
  const std::uint8_t* b = costs_only.localCostmap().costs();
  EXPECT_TRUE(std::equal(a, a + cells, b));
}

TEST(NavStack, RejectsAnUnknownLocalCostmapView) {
  try {
    core::readConfig<NavStackConfig>(core::ConfigNode::parseString("local_costmap_view: stale\n", "nav.yaml"));
    FAIL() << "stale is not a view";
  } catch (const core::InputError& e) {
    EXPECT_THAT(e.what(), ::testing::HasSubstr("nav.yaml: local_costmap_view: expected one of live, published"));
  }
}

TEST(NavStack, AnOutOfRangeFieldNamesItsPathAndUnit) {
  NavStackConfig config;
  config.local_update_rate = 0.0;
  core::Errors errors;
  validate(config, errors, "dwa.yaml: dwa.nav");
  ASSERT_EQ(errors.messages().size(), 1u);
  EXPECT_EQ(errors.messages()[0], "dwa.yaml: dwa.nav.local_update_rate: must be > 0 Hz, got 0 Hz");
}

TEST(NavStack, AnInflationRadiusSetWhileRunningTakesEffectAtTheMapsNextUpdate) {
  // The wall is 1 m ahead; the robot's cell is 1 m from it. The default global inflation
  // (0.3 m) leaves that cell free; 1.2 m at cost scaling 1 reaches it (252 exp(-(1 - 0.265))
  // = 120), but only once the global costmap (10 Hz) next takes a scan, as costmap_2d applies
  // a reconfigure in its update loop.
  const core::LaserScan wall = wallScan(-0.45, 0.45, 1.0);
  const core::Pose2 robot{0.0, 0.0, std::numbers::pi / 2};
  NavStack nav({});
  nav.reset({0.0, 5.0});
  nav.update(0.0, wall, robot, robot);
  const auto robotCost = [&] { return nav.globalCostmap().costAt({0.0, 0.0}); };
  EXPECT_EQ(robotCost(), kFreeCost);
  nav.setParameter("global_costmap.inflation_radius", 1.2);
  nav.setParameter("global_costmap.cost_scaling_factor", 1.0);
  EXPECT_EQ(robotCost(), kFreeCost);  // not before the next update
  core::LaserScan next = wall;
  next.stamp = 0.05;
  nav.update(0.05, next, robot, robot);  // 0.05 s: the 10 Hz map does not update yet
  EXPECT_EQ(robotCost(), kFreeCost);
  next.stamp = 0.1;
  nav.update(0.1, next, robot, robot);
  EXPECT_GT(robotCost(), kFreeCost);
  // The next episode starts with the configured radius again.
  nav.reset({0.0, 5.0});
  nav.update(0.0, wall, robot, robot);
  EXPECT_EQ(robotCost(), kFreeCost);
}

TEST(NavStack, APlannerRateSetWhileRunningSpacesThePlans) {
  const core::LaserScan scan = wallScan(1.0, 1.0, 1.0);
  const core::Pose2 robot{0.0, 0.0, std::numbers::pi / 2};
  NavStack nav({});
  nav.reset({0.0, 5.0});
  nav.setParameter("planner.rate", 2.0);
  // 0.05 s ticks for 1 s at 2 Hz: plans at 0 and 0.5 s only.
  for (int tick = 0; tick < 20; ++tick) nav.update(0.05 * tick, scan, robot, robot);
  EXPECT_EQ(nav.plansMade(), 2);
}

TEST(NavStack, SettingAnUnknownKeyOrABadValueNamesTheKey) {
  NavStack nav({});
  nav.reset({0.0, 5.0});
  const auto message = [&](const char* key, double value) {
    try {
      nav.setParameter(key, value);
    } catch (const std::invalid_argument& e) {
      return std::string(e.what());
    }
    return std::string();
  };
  EXPECT_NE(message("global_costmap.inflation_radius_", 0.5).find("global_costmap.inflation_radius_: not a settable parameter (settable: global_costmap.inflation_radius,"),
            std::string::npos);
  EXPECT_NE(message("global_costmap.inflation_radius", -1.0).find("global_costmap.inflation_radius: must be >= 0"),
            std::string::npos);
  EXPECT_NE(message("planner.rate", 0.0).find("planner.rate: must be > 0"), std::string::npos);
  EXPECT_NE(message("local_update_rate", std::nan("")).find("local_update_rate"), std::string::npos);
  EXPECT_EQ(message("local_costmap.raytrace_range", 4.0), "");
  // Every listed key is settable.
  for (const std::string& key : NavStack::settableParameters()) EXPECT_EQ(message(key.c_str(), 1.0), "") << key;
}

}  // namespace
}  // namespace barn::nav
