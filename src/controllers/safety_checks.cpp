#include "barn/controllers/safety_checks.hpp"

#include <cmath>

namespace barn::controllers {

Box footprintBox(double length, double width, double offset) {
  return {-length / 2 - offset, length / 2 + offset, -width / 2 - offset, width / 2 + offset};
}

std::vector<Eigen::Vector2d> scanPoints(const core::LaserScan& scan, const sim::LidarConfig& lidar) {
  std::vector<Eigen::Vector2d> points;
  points.reserve(scan.ranges.size());
  for (std::size_t i = 0; i < scan.ranges.size(); ++i) {
    const double r = scan.ranges[i];
    if (!std::isfinite(r)) continue;
    const double a = scan.angle(i);
    points.emplace_back(lidar.mount_x + r * std::cos(a), lidar.mount_y + r * std::sin(a));
  }
  return points;
}

bool footprintInflationHit(const std::vector<Eigen::Vector2d>& points, const Box& inflated) {
  for (const auto& p : points)
    if (inflated.contains(p)) return true;
  return false;
}

bool rolloutHit(const std::vector<Eigen::Vector2d>& points, const Box& footprint, const core::Twist& command,
                double dt, int steps) {
  double x = 0.0, y = 0.0, psi = 0.0;
  for (int k = 0; k < steps; ++k) {
    x += command.linear * std::cos(psi) * dt;
    y += command.linear * std::sin(psi) * dt;
    psi += command.angular * dt;
    // The points in the frame of the rolled-out pose.
    const core::Pose2 pose{x, y, psi};
    for (const auto& p : points)
      if (footprint.contains(pose.inverseTransform(p))) return true;
  }
  return false;
}

bool rearRegionBlocked(const nav::Costmap& costmap, const core::Pose2& pose, const Box& footprint, double depth) {
  const Box strip{footprint.min_x - depth, footprint.min_x, footprint.min_y, footprint.max_y};
  // Sample the strip at half the cell size so every cell it covers is looked at.
  const double step = costmap.resolution() / 2;
  for (double x = strip.min_x; x <= strip.max_x + 1e-9; x += step) {
    for (double y = strip.min_y; y <= strip.max_y + 1e-9; y += step) {
      nav::CellIndex cell;
      if (!costmap.toCell(pose.transform({x, y}), cell)) continue;
      if (costmap.isObstacle(cell.x, cell.y)) return true;
    }
  }
  return false;
}

}  // namespace barn::controllers
