#include "barn/controllers/safety_checks.hpp"

#include <algorithm>
#include <cmath>
#include <limits>

namespace barn::controllers {

std::vector<Eigen::Vector2d> scanPoints(const core::LaserScan& scan, const core::LidarConfig& lidar, core::BeamDirections& beams) {
  beams.update(scan);
  std::vector<Eigen::Vector2d> points;
  points.reserve(scan.ranges.size());
  for (std::size_t i = 0; i < scan.ranges.size(); ++i) {
    const double r = scan.ranges[i];
    if (!std::isfinite(r)) continue;
    points.emplace_back(lidar.mount_x + r * beams.cos(i), lidar.mount_y + r * beams.sin(i));
  }
  return points;
}

bool footprintInflationHit(const std::vector<Eigen::Vector2d>& points, const core::Rect& inflated) {
  for (const auto& p : points)
    if (inflated.contains(p)) return true;
  return false;
}

namespace {

// One Euler step of the unicycle model the rollouts share.
core::Pose2 unicycleStep(const core::Pose2& pose, const core::Twist& command, double dt) {
  return {pose.x + command.linear * std::cos(pose.yaw) * dt, pose.y + command.linear * std::sin(pose.yaw) * dt,
          pose.yaw + command.angular * dt};
}

}  // namespace

bool rolloutHit(const std::vector<Eigen::Vector2d>& points, const core::Rect& footprint, const core::Twist& command,
                double dt, int steps) {
  core::Pose2 pose{0.0, 0.0, 0.0};
  for (int k = 0; k < steps; ++k) {
    pose = unicycleStep(pose, command, dt);
    // The points in the frame of the rolled-out pose.
    const core::PoseFrame rolledOut(pose);
    for (const auto& p : points)
      if (footprint.contains(rolledOut.toLocal(p))) return true;
  }
  return false;
}

bool beamRolloutHit(const core::LaserScan& scan, const core::Twist& command, const BeamRollout& check) {
  core::Pose2 final_pose{0.0, 0.0, 0.0};
  for (int k = 0; k < check.steps; ++k) final_pose = unicycleStep(final_pose, command, check.dt);
  const core::Rect& r = check.rectangle;
  const int n = check.points_per_side;
  const core::PoseFrame finalFrame(final_pose);
  const auto hit = [&](double local_x, double local_y) {
    const Eigen::Vector2d p = finalFrame.toParent({local_x, local_y});
    const double index = std::floor((std::atan2(p.y(), p.x()) - scan.angle_min) / scan.angle_increment);
    if (!(index >= 0.0 && index < static_cast<double>(scan.ranges.size()))) return false;  // outside the field of view
    return scan.ranges[static_cast<std::size_t>(index)] < std::abs(p.x()) + std::abs(p.y()) + check.tolerance;
  };
  for (int i = 0; i < n; ++i) {
    const double s = n == 1 ? 0.5 : static_cast<double>(i) / (n - 1);
    const double along_x = r.min_x + s * (r.max_x - r.min_x);
    const double along_y = r.min_y + s * (r.max_y - r.min_y);
    if (hit(along_x, r.min_y) || hit(along_x, r.max_y) || hit(r.min_x, along_y) || hit(r.max_x, along_y)) return true;
  }
  return false;
}

bool frontCheckHit(const core::LaserScan& scan, const core::LidarConfig& lidar, core::BeamDirections& beams,
                   const core::Twist& command, const FrontCheck& check) {
  const core::Rect region{-check.half_length, check.half_length + std::max(check.pad_front, check.speed_gain * command.linear),
                   -check.half_width - check.pad_x, check.half_width + check.pad_x};
  // The region is turned by rotate_gain * w about the robot centre; a point is inside if, turned
  // back by the same angle, it lies in the axis-aligned rectangle. (The code rotated a polygon
  // and asked matplotlib; for a rectangle this is the same test.)
  const core::PoseFrame turned(core::Pose2{0.0, 0.0, check.rotate_gain * command.angular});
  beams.update(scan);
  for (std::size_t i = 0; i < scan.ranges.size(); ++i) {
    const double r = scan.ranges[i];
    if (!std::isfinite(r) || std::abs(scan.angle(i)) > check.front_angle) continue;
    const Eigen::Vector2d p(lidar.mount_x + r * beams.cos(i), lidar.mount_y + r * beams.sin(i));
    if (region.contains(turned.toLocal(p))) return true;
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

int publishedCost(std::uint8_t cost) {
  if (cost == nav::kFreeCost) return 0;
  if (cost == nav::kInscribedCost) return 99;
  if (cost == nav::kLethalCost) return 100;
  if (cost == nav::kUnknownCost) return -1;
  return 1 + (97 * (cost - 1)) / 251;
}

core::Rect rearStrip(const core::Rect& footprint, double depth) {
  return {footprint.min_x - depth, footprint.min_x, footprint.min_y, footprint.max_y};
}

namespace {

/// The distance in cells from `cell` to the nearest obstacle cell, or +inf beyond `max_cells`:
/// square rings outward until one holds an obstacle, then on to the radius that can still hold
/// a nearer one.
double cellsToNearestObstacle(const nav::Costmap& costmap, nav::CellIndex cell, double max_cells) {
  double best_sq = std::numeric_limits<double>::infinity();
  int last_ring = static_cast<int>(std::ceil(max_cells));
  for (int ring = 0; ring <= last_ring; ++ring) {
    for (int dy = -ring; dy <= ring; ++dy) {
      const bool edge_row = dy == -ring || dy == ring;
      for (int dx = -ring; dx <= ring; dx += edge_row ? 1 : 2 * ring) {
        if (costmap.isObstacle(cell.x + dx, cell.y + dy)) best_sq = std::min(best_sq, static_cast<double>(dx * dx + dy * dy));
        if (ring == 0) break;
      }
    }
    if (std::isfinite(best_sq)) last_ring = std::min(last_ring, static_cast<int>(std::ceil(std::sqrt(best_sq))));
  }
  const double cells = std::sqrt(best_sq);
  return cells <= max_cells ? cells : std::numeric_limits<double>::infinity();
}

}  // namespace

std::vector<Eigen::Vector2d> inscribedCellPoints(const nav::Costmap& costmap, const core::Pose2& pose, double reach) {
  std::vector<Eigen::Vector2d> points;
  nav::CellIndex centre;
  if (!costmap.toCell(pose.position(), centre)) return points;
  const double inscribed_cells = costmap.inscribedRadius() / costmap.resolution();
  const int span = static_cast<int>(std::ceil(reach / costmap.resolution())) + 1;
  const core::PoseFrame robot(pose);
  for (int dy = -span; dy <= span; ++dy) {
    for (int dx = -span; dx <= span; ++dx) {
      const nav::CellIndex cell{centre.x + dx, centre.y + dy};
      if (!costmap.inBounds(cell.x, cell.y)) continue;
      const Eigen::Vector2d at = costmap.cellCentre(cell);
      if ((at - pose.position()).norm() > reach) continue;
      const double distance = cellsToNearestObstacle(costmap, cell, inscribed_cells + 1.0);
      if (std::isfinite(distance) && costmap.inflationCostAtCells(distance) >= nav::kInscribedCost)
        points.push_back(robot.toLocal(at));
    }
  }
  return points;
}

bool rearRegionBlocked(const nav::Costmap& costmap, const core::Pose2& pose, const core::Rect& region, double weight) {
  // The cells under the region: sampled at half the cell size so every cell it covers is seen.
  std::vector<nav::CellIndex> cells;
  const core::PoseFrame robot(pose);
  const double step = costmap.resolution() / 2;
  for (double x = region.min_x; x <= region.max_x + 1e-9; x += step) {
    for (double y = region.min_y; y <= region.max_y + 1e-9; y += step) {
      nav::CellIndex cell;
      if (!costmap.toCell(robot.toParent({x, y}), cell)) continue;
      if (costmap.isObstacle(cell.x, cell.y)) return true;
      if (std::find_if(cells.begin(), cells.end(), [&](const nav::CellIndex& c) { return c.x == cell.x && c.y == cell.y; }) ==
          cells.end())
        cells.push_back(cell);
    }
  }
  if (weight <= 0.0 || cells.empty()) return false;
  // The distance (in cells) beyond which a cell's published cost is at most the threshold.
  const double threshold = weight * 100.0;
  const double max_cells = costmap.config().inflation_radius / costmap.resolution();
  double cheap_beyond = 0.0;
  while (cheap_beyond < max_cells && publishedCost(costmap.inflationCostAtCells(cheap_beyond)) > threshold)
    cheap_beyond += 0.05;
  // If one cell of the region is farther than span + cheap_beyond from every obstacle, every
  // cell is farther than cheap_beyond, so the mean cannot exceed the threshold: no cell needs a
  // longer search than that, which keeps the search short in the open.
  int min_x = cells.front().x, max_x = min_x, min_y = cells.front().y, max_y = min_y;
  for (const nav::CellIndex& cell : cells) {
    min_x = std::min(min_x, cell.x), max_x = std::max(max_x, cell.x);
    min_y = std::min(min_y, cell.y), max_y = std::max(max_y, cell.y);
  }
  const double span = std::hypot(max_x - min_x, max_y - min_y);
  const double search_cells = std::min(max_cells, span + cheap_beyond);
  int sum = 0, nonzero = 0;
  for (const nav::CellIndex& cell : cells) {
    const double distance = cellsToNearestObstacle(costmap, cell, search_cells);
    if (!std::isfinite(distance)) {
      if (search_cells < max_cells) return false;  // the bound above
      continue;                                    // beyond the inflation: cost 0, not counted
    }
    const int value = publishedCost(costmap.inflationCostAtCells(distance));
    if (value <= 0) continue;
    sum += value;
    ++nonzero;
  }
  return nonzero > 0 && sum > threshold * nonzero;
}

bool rotateCheckHit(const std::vector<Eigen::Vector2d>& points, const nav::Costmap& costmap, const core::Pose2& pose,
                    double turn_rate, const RotateCheck& check) {
  const core::PoseFrame turned(core::Pose2{0.0, 0.0, check.rotate_gain * turn_rate});
  for (const auto& p : points)
    if (check.body.contains(turned.toLocal(p))) return true;
  // Turning left (w > 0) swings the tail to the right (-y), and the other way round.
  const double half = check.rear_width / 2;
  const core::Rect rear{-check.rear_centre - check.rear_depth / 2, -check.rear_centre + check.rear_depth / 2,
                        turn_rate > 0.0 ? -half : 0.0, turn_rate > 0.0 ? 0.0 : half};
  return rearRegionBlocked(costmap, pose, rear, check.rear_weight);
}

}  // namespace barn::controllers
