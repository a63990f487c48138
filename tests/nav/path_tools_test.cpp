#include "barn/nav/path_tools.hpp"

#include <cmath>
#include <numbers>

#include <gtest/gtest.h>

namespace barn::nav {
namespace {

// An L: 2 m along +x, then 2 m along +y, points every 0.5 m.
Path lPath() {
  Path path;
  for (int i = 0; i <= 4; ++i) path.emplace_back(0.5 * i, 0.0);
  for (int i = 1; i <= 4; ++i) path.emplace_back(2.0, 0.5 * i);
  return path;
}

TEST(PathTools, ClosestIndexIsTheNearestPoint) {
  const Path path = lPath();
  EXPECT_EQ(closestIndex(path, {0.7, 0.3}), 1u);  // (0.5, 0): 0.283 m; (1, 0): 0.424 m
  EXPECT_EQ(closestIndex(path, {2.4, 1.6}), 7u);  // (2, 1.5)
  EXPECT_EQ(closestIndex(path, {-5.0, 0.0}), 0u);
  EXPECT_EQ(closestIndex({}, {1.0, 1.0}), 0u);
}

TEST(PathTools, PointAlongPathWalksTheArcLengthRoundTheCorner) {
  const Path path = lPath();
  // From the point nearest (0.5, 0.1), i.e. (0.5, 0): 1.0 m reaches (1.5, 0); 2.0 m turns the
  // corner at (2, 0) and goes 0.5 m up.
  const Eigen::Vector2d straight = pointAlongPath(path, {0.5, 0.1}, 1.0);
  EXPECT_NEAR(straight.x(), 1.5, 1e-12);
  EXPECT_NEAR(straight.y(), 0.0, 1e-12);
  const Eigen::Vector2d round = pointAlongPath(path, {0.5, 0.1}, 2.0);
  EXPECT_NEAR(round.x(), 2.0, 1e-12);
  EXPECT_NEAR(round.y(), 0.5, 1e-12);
  // Within a segment: interpolated.
  const Eigen::Vector2d inside = pointAlongPath(path, {0.0, 0.0}, 0.2);
  EXPECT_NEAR(inside.x(), 0.2, 1e-12);
  // Longer than what is left: the end.
  EXPECT_EQ(pointAlongPath(path, {1.0, 0.0}, 100.0), path.back());
}

TEST(PathTools, HeadingErrorIsTheBearingOfTheLookAheadPoint) {
  const Path path = lPath();
  // At the origin facing +x, 2.5 m along is (2, 0.5): bearing atan2(0.5, 2), to the left.
  EXPECT_NEAR(headingError(path, {0.0, 0.0, 0.0}, 2.5), std::atan2(0.5, 2.0), 1e-12);
  // Facing +y the same point is to the right.
  EXPECT_NEAR(headingError(path, {0.0, 0.0, std::numbers::pi / 2}, 2.5), std::atan2(0.5, 2.0) - std::numbers::pi / 2,
              1e-12);
  // Facing away (-x): the error is wrapped into [-pi, pi).
  const double behind = headingError(path, {0.0, 0.0, std::numbers::pi}, 1.0);
  EXPECT_NEAR(std::abs(behind), std::numbers::pi, 1e-12);
  // Standing on the look-ahead point (the path's end): no error.
  EXPECT_EQ(headingError(path, {2.0, 2.0, 1.0}, 5.0), 0.0);
}

TEST(PathTools, PathInRobotFrameIsTheInverseTransform) {
  const Path path = lPath();
  const core::Pose2 pose{2.0, 0.0, std::numbers::pi / 2};  // at the corner, facing +y
  const Path local = pathInRobotFrame(path, pose);
  ASSERT_EQ(local.size(), path.size());
  // The leg ahead (world +y) lies along the robot's +x; the path's start, 2 m along world -x,
  // is on the robot's left (+y).
  EXPECT_NEAR(local.back().x(), 2.0, 1e-12);
  EXPECT_NEAR(local.back().y(), 0.0, 1e-12);
  EXPECT_NEAR(local.front().x(), 0.0, 1e-12);
  EXPECT_NEAR(local.front().y(), 2.0, 1e-12);
  for (std::size_t i = 0; i < path.size(); ++i) EXPECT_NEAR((pose.transform(local[i]) - path[i]).norm(), 0.0, 1e-12);
}

}  // namespace
}  // namespace barn::nav
