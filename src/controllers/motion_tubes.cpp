#include "barn/controllers/motion_tubes.hpp"

#include <algorithm>
#include <cmath>
#include <numbers>

namespace barn::controllers {

namespace {

constexpr double kDeg = std::numbers::pi / 180.0;

Eigen::Vector2d rotateAbout(const Eigen::Vector2d& p, const Eigen::Vector2d& centre, double angle) {
  const double c = std::cos(angle), s = std::sin(angle);
  const Eigen::Vector2d d = p - centre;
  return centre + Eigen::Vector2d(c * d.x() - s * d.y(), s * d.x() + c * d.y());
}

/// Appends the arc `p` travels turning by `angle` about `centre`: ceil(arc length / step) + 1
/// points, both ends included.
void sampleArc(std::vector<Eigen::Vector2d>& out, const Eigen::Vector2d& p, const Eigen::Vector2d& centre, double angle,
               double step) {
  const double arc = (p - centre).norm() * std::abs(angle);
  const int n = std::max(1, static_cast<int>(std::ceil(arc / step - 1e-9)));
  for (int k = 0; k <= n; ++k) out.push_back(rotateAbout(p, centre, angle * k / n));
}

/// Appends the segment a -> b: ceil(length / step) + 1 points, both ends included.
void sampleSegment(std::vector<Eigen::Vector2d>& out, const Eigen::Vector2d& a, const Eigen::Vector2d& b, double step) {
  const int n = std::max(1, static_cast<int>(std::ceil((b - a).norm() / step - 1e-9)));
  for (int k = 0; k <= n; ++k) out.push_back(a + (b - a) * (static_cast<double>(k) / n));
}

}  // namespace

void validate(const MotionTubeConfig& c, core::Errors& errors, const std::string& prefix) {
  core::validateFields(c, errors, prefix);
  errors.check(c.angle_step_deg > 0.0 && c.max_angle_deg / std::max(c.angle_step_deg, 1e-9) <= 10000.0,
               prefix + ".angle_step_deg", "must be > 0 and give at most 10000 angles");
  // The tightest tube turns about a centre at radius_factor / (max angle / length) from the robot
  // centre; the inner whisker must stay on the robot's side of it.
  if (c.length > 0.0 && c.backward_length > 0.0 && c.max_angle_deg > 0.0 && c.radius_factor > 0.0) {
    const double tightest =
        c.radius_factor / std::max(c.max_angle_deg * kDeg / std::min(c.length, c.backward_length), c.min_curvature);
    errors.check(tightest - c.vehicle_width / 2 - c.side_whisker_offset > 0.0, prefix + ".max_angle_deg",
                 "the tightest tube (radius " + std::to_string(tightest) +
                     " m) must turn about a point beyond the inner whisker (vehicle_width / 2 + side_whisker_offset)");
  }
}

bool toSensorSample(const Eigen::Vector2d& p, const core::LidarConfig& lidar, SensorSample& sample) {
  const double x = p.x() - lidar.mount_x, y = p.y() - lidar.mount_y;
  const double bearing = std::atan2(y, x);
  const double range = std::hypot(x, y);
  if (bearing < lidar.angle_min || bearing > lidar.angle_max) return false;
  if (range < lidar.range_min || range > lidar.range_max) return false;
  const long beam = std::lround((bearing - lidar.angle_min) / lidar.angleIncrement());
  sample.beam = static_cast<int>(std::clamp<long>(beam, 0, lidar.beams - 1));
  sample.range = range;
  return true;
}

SampleSet toSampleSet(const std::vector<Eigen::Vector2d>& points, const core::LidarConfig& lidar) {
  SampleSet set;
  SensorSample sample;
  for (const auto& p : points)
    if (toSensorSample(p, lidar, sample)) set.push_back(sample);
  return set;
}

bool isFree(const SampleSet& samples, const core::LaserScan& scan) {
  for (const SensorSample& s : samples) {
    const double r = scan.ranges[static_cast<std::size_t>(s.beam)];
    if (r > scan.range_min && r < scan.range_max && r < s.range) return false;
  }
  return true;
}

core::Pose2 arcEnd(double length, double radius) {
  const double theta = length / radius;
  return {radius * std::sin(theta), radius * (1.0 - std::cos(theta)), theta};
}

TubeShape tubeShape(double length, double radius, const MotionTubeConfig& c) {
  const double side = radius > 0.0 ? 1.0 : -1.0;       // +1: turning left
  const double travel = length > 0.0 ? 1.0 : -1.0;     // +1: driving forward
  const double theta = length / radius;
  const double half = c.vehicle_width / 2;
  const double lead_x = travel > 0.0 ? c.axle_to_front : -c.axle_to_rear;
  const Eigen::Vector2d centre(0.0, radius);
  const Eigen::Vector2d outer_corner(lead_x, -side * half);  // leads on the far side of the centre
  const Eigen::Vector2d inner_point(0.0, side * half);      // the body point nearest the centre
  const core::PoseFrame end(arcEnd(length, radius));

  TubeShape shape;
  sampleArc(shape.edge, outer_corner, centre, theta, c.edge_step);
  sampleArc(shape.edge, inner_point, centre, theta, c.edge_step);
  const Eigen::Vector2d end_inner_point = end.toParent(inner_point);
  const Eigen::Vector2d end_inner_corner = end.toParent({lead_x, side * half});
  const Eigen::Vector2d end_outer_corner = end.toParent(outer_corner);
  sampleSegment(shape.edge, end_inner_point, end_inner_corner, c.edge_step);
  sampleSegment(shape.edge, end_outer_corner, end_inner_corner, c.edge_step);

  const double outer_r = (outer_corner - centre).norm();
  const double inner_r = (inner_point - centre).norm();
  sampleArc(shape.outer, centre + (outer_corner - centre) * ((outer_r + c.side_whisker_offset) / outer_r), centre, theta,
            c.whisker_step);
  sampleArc(shape.inner, centre + (inner_point - centre) * ((inner_r - c.side_whisker_offset) / inner_r), centre, theta,
            c.whisker_step);
  const double front_x = lead_x + travel * c.front_whisker_offset;
  sampleSegment(shape.front, end.toParent({front_x, -side * half}), end.toParent({front_x, side * half}), c.whisker_step);
  return shape;
}

std::vector<MotionTube> buildTubeLibrary(double length, const MotionTubeConfig& c, const core::LidarConfig& lidar) {
  const int angles = static_cast<int>(std::lround(c.max_angle_deg / c.angle_step_deg)) + 1;
  std::vector<MotionTube> tubes;
  tubes.reserve(2 * static_cast<std::size_t>(angles));
  for (int i = 0; i < angles; ++i) {
    const double curvature = std::max(i * c.angle_step_deg * kDeg / std::abs(length), c.min_curvature);
    for (const double side : {1.0, -1.0}) {
      MotionTube t;
      t.length = length;
      t.radius = side * c.radius_factor / curvature;
      t.heading_change = length / t.radius;
      t.end = arcEnd(length, t.radius);
      t.shape = tubeShape(length, t.radius, c);
      t.edge = toSampleSet(t.shape.edge, lidar);
      t.outer = toSampleSet(t.shape.outer, lidar);
      t.inner = toSampleSet(t.shape.inner, lidar);
      t.front = toSampleSet(t.shape.front, lidar);
      tubes.push_back(std::move(t));
    }
  }
  return tubes;
}

SampleSet rotationRing(double radius, const core::LidarConfig& lidar) {
  const Eigen::Vector2d mount(lidar.mount_x, lidar.mount_y);
  SampleSet ring;
  for (int i = 0; i < lidar.beams; ++i) {
    const double a = lidar.angle_min + i * lidar.angleIncrement();
    const Eigen::Vector2d u(std::cos(a), std::sin(a));
    // |mount + t u| = radius, the root ahead of the sensor (inside the circle: one of each sign).
    const double along = mount.dot(u);
    const double disc = along * along - (mount.squaredNorm() - radius * radius);
    if (disc < 0.0) continue;  // the sensor outside a circle this beam misses
    const double t = -along + std::sqrt(disc);
    if (t <= 0.0) continue;
    ring.push_back({i, t});
  }
  return ring;
}

}  // namespace barn::controllers
