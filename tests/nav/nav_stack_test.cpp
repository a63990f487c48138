#include "barn/nav/nav_stack.hpp"

#include <cmath>
#include <limits>
#include <numbers>

#include <gtest/gtest.h>

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

}  // namespace
}  // namespace barn::nav
