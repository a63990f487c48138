#include "barn/controllers/meco_fitter.hpp"

#include <algorithm>
#include <cmath>
#include <numbers>
#include <numeric>

namespace barn::controllers {

namespace {
constexpr double kDeg = std::numbers::pi / 180.0;
constexpr double kTwoPi = 2.0 * std::numbers::pi;
}  // namespace

void validate(const MecoFitterConfig& c, core::Errors& errors, const std::string& prefix) {
  core::validateFields(c, errors, prefix);
  errors.check(c.sectors <= 0 || c.beams / std::max(c.sectors, 1) >= 2, prefix + ".sectors",
               "must leave at least 2 beams per sector");
  errors.check(std::isfinite(c.forward_limit_y), prefix + ".forward_limit_y", "must be finite");
  errors.check(std::isfinite(c.fallback_tilt_deg), prefix + ".fallback_tilt_deg", "must be finite");
}

std::optional<double> openingInSector(std::span<const double> ranges, double increment, const MecoFitterConfig& c) {
  const std::size_t n = ranges.size();
  std::vector<std::size_t> order(n);
  std::iota(order.begin(), order.end(), std::size_t{0});
  std::stable_sort(order.begin(), order.end(), [&](std::size_t a, std::size_t b) { return ranges[a] < ranges[b]; });
  const double wide = 2.0 * (c.robot_radius + c.safety_radius);  // beams at least as far as the candidate
  const double narrow = 2.0 * c.robot_radius + c.safety_radius;  // after a nearer beam
  for (const std::size_t candidate : order) {
    const double r = ranges[candidate];
    if (r < c.min_range) continue;
    const double arc = increment * r;
    double opening = 0.5 * arc;
    for (std::size_t k = 0; k < n; ++k) {
      if (ranges[k] >= r) {
        opening += arc;
        if (opening > wide) return 0.5 * static_cast<double>(k + candidate);
      } else {
        opening += 0.5 * arc;
        if (opening > narrow) return 0.5 * static_cast<double>(k + candidate);
        opening = 0.0;
      }
    }
  }
  return std::nullopt;
}

std::vector<double> openingDirections(const core::LaserScan& scan, const MecoFitterConfig& c) {
  const int total = static_cast<int>(scan.ranges.size());
  const int used = std::min(c.beams, total);
  const int first = (total - used) / 2;
  std::vector<double> central(static_cast<std::size_t>(used));
  for (int j = 0; j < used; ++j) {
    const double r = scan.ranges[static_cast<std::size_t>(first + j)];
    central[static_cast<std::size_t>(j)] = std::isfinite(r) ? r : c.inf_range;
  }
  const int size = used / c.sectors;
  const int half = size / 2;
  std::vector<double> directions;
  // `offset` is where the team's code puts the sector's first beam, relative to where it is.
  const auto search = [&](int begin, int count, double offset) {
    if (count <= 0) return;
    const auto found = openingInSector(std::span<const double>(central).subspan(static_cast<std::size_t>(begin),
                                                                                static_cast<std::size_t>(count)),
                                       scan.angle_increment, c);
    if (!found) return;
    const double index = static_cast<double>(first + begin) + (c.team_sector_angles ? offset : 0.0) + *found;
    directions.push_back(scan.angle_min + index * scan.angle_increment);
  };
  for (int i = 0; i < c.sectors; ++i) search(i * size, size, i == 0 ? 0.0 : -0.5 * size);
  for (int i = 0; i <= c.sectors; ++i) {
    if (i == 0)
      search(0, half, 0.0);
    else
      search(i * size - half, i == c.sectors ? half : size, static_cast<double>(half));
  }
  return directions;
}

std::vector<Eigen::Vector2d> scanPoints(const core::LaserScan& scan, const core::LidarConfig& lidar, int stride) {
  std::vector<Eigen::Vector2d> points;
  const Eigen::Vector2d mount(lidar.mount_x, lidar.mount_y);
  int valid = 0;
  for (std::size_t i = 0; i < scan.ranges.size(); ++i) {
    const double r = scan.ranges[i];
    if (!std::isfinite(r) || r < scan.range_min || r > scan.range_max) continue;
    if (++valid % stride != 0) continue;
    const double a = scan.angle(i);
    points.push_back(mount + r * Eigen::Vector2d(std::cos(a), std::sin(a)));
  }
  return points;
}

bool anyInside(const MecoCorridor& corridor, std::span<const Eigen::Vector2d> points) {
  return std::any_of(points.begin(), points.end(), [&](const Eigen::Vector2d& p) { return corridor.contains(p); });
}

void growCorridorEdge(MecoCorridor& corridor, MecoEdge edge, std::span<const Eigen::Vector2d> points,
                      const core::Pose2& pose, double step_multiplier, const MecoFitterConfig& c) {
  if (anyInside(corridor, points)) return;  // the team discards it: it keeps its seed size
  const double step = c.growth_step * step_multiplier;
  const double back = step / c.backoff_divisions;
  const core::PoseFrame frame(pose);
  const auto at_limit = [&] {
    for (const Eigen::Vector2d& corner : corridor.corners())
      if (frame.toParent(corner).y() >= c.forward_limit_y) return true;
    return false;
  };
  for (int s = 0; s < c.growth_steps; ++s) {
    corridor.moveEdge(edge, step);
    if (!anyInside(corridor, points) && !at_limit()) continue;
    // Back off until no point is inside; the step before held none, so divisions moves suffice
    // (one more for rounding).
    for (int b = 0; b <= c.backoff_divisions && anyInside(corridor, points); ++b) corridor.moveEdge(edge, -back);
    break;
  }
}

void growChild(MecoCorridor& corridor, std::span<const Eigen::Vector2d> points, const core::Pose2& pose,
               const MecoFitterConfig& c) {
  const double tilt = corridor.heading;
  growCorridorEdge(corridor, MecoEdge::Front, points, pose, 1.0, c);
  // The heading in the odom frame, in [0, 2 pi), picks the sides that may grow: those facing +y.
  double world = std::fmod(pose.yaw + tilt, kTwoPi);
  if (world < 0.0) world += kTwoPi;
  constexpr double kQuarter = std::numbers::pi / 4;
  if (world >= kQuarter && world <= 3 * kQuarter) {
    growCorridorEdge(corridor, MecoEdge::Right, points, pose, 1.0, c);
    growCorridorEdge(corridor, MecoEdge::Left, points, pose, 1.0, c);
  } else if (world > 3 * kQuarter && world <= 5 * kQuarter) {
    growCorridorEdge(corridor, MecoEdge::Right, points, pose, 1.0, c);
  } else if (world > 7 * kQuarter || world < kQuarter) {
    growCorridorEdge(corridor, MecoEdge::Left, points, pose, 1.0, c);
  }
  if (corridor.width > corridor.length) corridor.turnQuarter(tilt > 0.0);
}

std::vector<MecoCorridor> fitCorridors(const core::LaserScan& scan, const core::LidarConfig& lidar,
                                       const core::Pose2& pose, const Eigen::Vector2d& goal,
                                       const MecoFitterConfig& c) {
  std::vector<double> tilts = openingDirections(scan, c);
  if (tilts.size() == 1) {
    tilts.push_back(0.0);
  } else if (tilts.empty()) {
    tilts.push_back(0.0);
    tilts.push_back(c.fallback_tilt_deg * kDeg);
  }
  const std::vector<Eigen::Vector2d> points = scanPoints(scan, lidar, c.point_stride);
  std::vector<MecoCorridor> corridors;
  for (const double tilt : tilts) {
    MecoCorridor child{Eigen::Vector2d::Zero(), tilt, c.child_length, c.child_width, Eigen::Vector2d::Zero()};
    growChild(child, points, pose, c);
    corridors.push_back(child);
  }
  const Eigen::Vector2d to_goal = goal - pose.position();
  const double bearing = core::wrapAngle(std::atan2(to_goal.y(), to_goal.x()) - pose.yaw);
  if (std::abs(bearing) <= c.final_max_bearing_deg * kDeg) {
    MecoCorridor final{Eigen::Vector2d::Zero(), bearing, c.final_length, c.final_width, Eigen::Vector2d::Zero()};
    growCorridorEdge(final, MecoEdge::Front, points, pose, c.final_step_multiplier, c);
    corridors.push_back(final);
  }
  for (MecoCorridor& corridor : corridors) corridor = corridor.toParent(pose);
  std::stable_sort(corridors.begin(), corridors.end(),
                   [](const MecoCorridor& a, const MecoCorridor& b) { return a.maxCornerY() > b.maxCornerY(); });
  if (corridors.size() > static_cast<std::size_t>(c.published)) corridors.resize(static_cast<std::size_t>(c.published));
  return corridors;
}

}  // namespace barn::controllers
