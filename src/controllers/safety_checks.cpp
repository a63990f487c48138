#include "barn/controllers/safety_checks.hpp"

#include <algorithm>
#include <cmath>

namespace barn::controllers {

Box footprintBox(double length, double width, double offset) {
  return {-length / 2 - offset, length / 2 + offset, -width / 2 - offset, width / 2 + offset};
}

std::vector<Eigen::Vector2d> scanPoints(const core::LaserScan& scan, const core::LidarConfig& lidar) {
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
                double dt, int steps, RolloutPoses poses) {
  double x = 0.0, y = 0.0, psi = 0.0;
  for (int k = 0; k < steps; ++k) {
    x += command.linear * std::cos(psi) * dt;
    y += command.linear * std::sin(psi) * dt;
    psi += command.angular * dt;
    if (poses == RolloutPoses::Final && k + 1 < steps) continue;
    // The points in the frame of the rolled-out pose.
    const core::Pose2 pose{x, y, psi};
    for (const auto& p : points)
      if (footprint.contains(pose.inverseTransform(p))) return true;
  }
  return false;
}

bool frontCheckHit(const core::LaserScan& scan, const core::LidarConfig& lidar, const core::Twist& command,
                   const FrontCheck& check) {
  const Box region{-check.half_length, check.half_length + std::max(check.pad_front, check.speed_gain * command.linear),
                   -check.half_width - check.pad_x, check.half_width + check.pad_x};
  // The region is turned by rotate_gain * w about the robot centre; a point is inside if, turned
  // back by the same angle, it lies in the axis-aligned rectangle. (The code rotated a polygon
  // and asked matplotlib; for a rectangle this is the same test.)
  const core::Pose2 turned{0.0, 0.0, check.rotate_gain * command.angular};
  for (std::size_t i = 0; i < scan.ranges.size(); ++i) {
    const double r = scan.ranges[i];
    const double a = scan.angle(i);
    if (!std::isfinite(r) || std::abs(a) > check.front_angle) continue;
    const Eigen::Vector2d p(lidar.mount_x + r * std::cos(a), lidar.mount_y + r * std::sin(a));
    if (region.contains(turned.inverseTransform(p))) return true;
  }
  return false;
}

bool ringHit(const core::LaserScan& scan, double front, double edge) {
  if (scan.ranges.empty()) return false;
  const double widest = std::max(std::abs(scan.angle(0)), std::abs(scan.angle(scan.ranges.size() - 1)));
  for (std::size_t i = 0; i < scan.ranges.size(); ++i) {
    const double r = scan.ranges[i];
    if (!std::isfinite(r)) continue;
    const double t = widest > 0.0 ? std::min(1.0, std::abs(scan.angle(i)) / widest) : 0.0;
    if (r <= front + (edge - front) * t) return true;
  }
  return false;
}

bool frontClear(const core::LaserScan& scan, double angle, double distance) {
  for (std::size_t i = 0; i < scan.ranges.size(); ++i)
    if (std::abs(scan.angle(i)) <= angle && scan.ranges[i] <= distance) return false;
  return true;
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
