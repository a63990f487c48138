#pragma once
/// What controllers need from a global path: the closest point, a local goal at a look-ahead
/// distance along it, the heading error to it, and the path in the robot frame.

#include <vector>

#include <Eigen/Core>

#include "barn/core/types.hpp"

namespace barn::nav {

using Path = std::vector<Eigen::Vector2d>;  // [m] odom frame

/// Index of the path point closest to `position` (0 for an empty path).
std::size_t closestIndex(const Path& path, const Eigen::Vector2d& position);

/// The point `lookahead` metres along the path from its point closest to `position` (the
/// path's end if it is shorter). The path must not be empty.
Eigen::Vector2d pointAlongPath(const Path& path, const Eigen::Vector2d& position, double lookahead);

/// Angle from the robot's heading to the direction of pointAlongPath(lookahead). [rad] in
/// [-pi, pi), positive to the left.
double headingError(const Path& path, const core::Pose2& pose, double lookahead);

/// The path expressed in the robot frame (x forward, y left).
Path pathInRobotFrame(const Path& path, const core::Pose2& pose);

}  // namespace barn::nav
