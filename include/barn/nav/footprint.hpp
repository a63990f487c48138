#pragma once
/// The radii costmap_2d derives from a robot footprint (footprint.cpp,
/// calculateMinAndMaxDistances; Nav2's nav2_costmap_2d computes them the same way): the
/// inscribed radius, the least distance from the robot centre to an edge of the (padded)
/// footprint polygon, and the circumscribed radius, the greatest distance to a vertex.
///
/// The costmaps' inscribed cost (253), E-Band's yaw scaling and anything else that needs a
/// radius take it from here, never typed by hand: another robot or another padding then
/// changes every derived number with it.

#include <span>

#include <Eigen/Core>

namespace barn::nav {

struct FootprintRadii {
  double inscribed = 0.0;      // [m] least distance from the centre to an edge
  double circumscribed = 0.0;  // [m] greatest distance from the centre to a vertex
};

/// The radii of a polygon in the robot frame (vertices in order, the last joined to the
/// first). A polygon of one vertex is a point (both radii its distance); none gives zeros.
FootprintRadii footprintRadii(std::span<const Eigen::Vector2d> polygon);

}  // namespace barn::nav
