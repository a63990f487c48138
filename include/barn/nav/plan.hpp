#pragma once
/// A global planner's answer: the poses it would publish, robot -> goal, in the odom frame.

#include <cstdint>
#include <vector>

#include <Eigen/Core>

namespace barn::nav {

struct Plan {
  bool found = false;
  // [m] odom frame, robot -> goal. dijkstra: start cell centre ... goal cell centre. navfn: as
  // NavfnROS, the robot cell's corner (origin + index res, no half cell), the descent's points
  // likewise, then the requested goal itself. global_planner: see ros_global_planner.hpp.
  std::vector<Eigen::Vector2d> path;
  // [rad] one per path point, the yaw of the pose the planner publishes. navfn: 0 (identity
  // orientation) for every pose but the appended goal, which has the goal's yaw. dijkstra: 0
  // throughout (no ROS counterpart). global_planner: its orientation filter's.
  std::vector<double> yaw;
  // dijkstra: total edge cost of the cell path (integer units). navfn and global_planner: the
  // goal cell's potential, rounded.
  std::int64_t cost = 0;
};

}  // namespace barn::nav
