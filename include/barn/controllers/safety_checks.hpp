#pragma once
/// The Inventec controller's safety checks, as pure functions of the scan, the command and the
/// costmap (so they are tested without a simulator).
///
/// Robot frame throughout: x forward, y left, origin at the robot centre. LiDAR points include
/// the sensor's mounting offset.

#include <vector>

#include <Eigen/Core>

#include "barn/core/types.hpp"
#include "barn/nav/costmap.hpp"
#include "barn/sim/lidar.hpp"

namespace barn::controllers {

/// An axis-aligned rectangle in the robot frame.
struct Box {
  double min_x = 0.0, max_x = 0.0;  // [m]
  double min_y = 0.0, max_y = 0.0;  // [m]
  bool contains(const Eigen::Vector2d& p) const {
    return p.x() >= min_x && p.x() <= max_x && p.y() >= min_y && p.y() <= max_y;
  }
};

/// The robot's planning rectangle (length along x, width along y) grown by `offset` per side.
Box footprintBox(double length, double width, double offset);

/// Every finite return of the scan as a point in the robot frame.
std::vector<Eigen::Vector2d> scanPoints(const core::LaserScan& scan, const sim::LidarConfig& lidar);

/// Footprint inflation (FI): true if any point lies inside the rectangle grown by the offset.
/// A direct rectangle test, the whole of what the original did with a polygon library.
bool footprintInflationHit(const std::vector<Eigen::Vector2d>& points, const Box& inflated);

/// MPC rollout: rolls (v, w) forward with the unicycle model (x += v cos(psi) dt,
/// y += v sin(psi) dt, psi += w dt, one consistent model) for `steps` steps and returns true
/// if the footprint at any step contains a point. (The published code measured distances as
/// |x| + |y| and mirrored the lateral drift against the rotation; neither is copied here.)
bool rolloutHit(const std::vector<Eigen::Vector2d>& points, const Box& footprint, const core::Twist& command,
                double dt, int steps);

/// The backtrack region of interest: a strip as wide as the footprint and `depth` deep directly
/// behind it. True if any cell of the (rolling, remembering) costmap there is lethal — the
/// LiDAR cannot see behind the robot, the costmap remembers what it saw before.
bool rearRegionBlocked(const nav::Costmap& costmap, const core::Pose2& pose, const Box& footprint, double depth);

}  // namespace barn::controllers
