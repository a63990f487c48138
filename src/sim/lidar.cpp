#include "barn/sim/lidar.hpp"

#include <algorithm>
#include <cmath>
#include <limits>
#include <numbers>

namespace barn::sim {

namespace {

// atan2 to within 2e-8 rad (Abramowitz & Stegun 4.4.49 on [-1, 1], then octant reduction).
// The caster only uses it to pick which beams to test, with a margin far above that error; the
// ranges themselves come from the exact ray-circle intersection.
double approxAtan2(double y, double x) {
  const double ax = std::abs(x);
  const double ay = std::abs(y);
  const bool steep = ay > ax;
  const double t = steep ? ax / ay : ay / ax;  // in [0, 1]
  const double t2 = t * t;
  double a = t * (1.0 + t2 * (-0.3333314528 + t2 * (0.1999355085 + t2 * (-0.1420889944 + t2 * (0.1065626393 +
                 t2 * (-0.0752896400 + t2 * (0.0429096138 + t2 * (-0.0161657367 + t2 * 0.0028662257))))))));
  if (steep) a = 0.5 * std::numbers::pi - a;
  if (x < 0.0) a = std::numbers::pi - a;
  return y < 0.0 ? -a : a;
}

}  // namespace

LidarCaster::LidarCaster(const core::LidarConfig& config, const ObstacleField& field)
    : config_(config), field_(&field),
      bucket_start_(static_cast<std::size_t>(std::ceil((config.range_max + field.maxRadius()) * 4.0)) + 2, 0) {
  beam_cos_.resize(static_cast<std::size_t>(config.beams));
  beam_sin_.resize(static_cast<std::size_t>(config.beams));
  const double increment = config.angleIncrement();
  for (int i = 0; i < config.beams; ++i) {
    const double angle = config.angle_min + i * increment;
    beam_cos_[static_cast<std::size_t>(i)] = std::cos(angle);
    beam_sin_[static_cast<std::size_t>(i)] = std::sin(angle);
  }
}

void LidarCaster::cast(const core::Pose2& sensor_pose, std::vector<double>& ranges) {
  // Two instantiations: BARN's cylinders all share one radius, and that loop stays exactly as
  // it was (the radius is a loop constant); hallucinated LfLH obstacles have one radius each.
  if (field_->hasRadii()) castCircles<true>(sensor_pose, ranges);
  else castCircles<false>(sensor_pose, ranges);
}

template <bool kVariedRadii>
void LidarCaster::castCircles(const core::Pose2& sensor_pose, std::vector<double>& ranges) {
  constexpr double kInf = std::numeric_limits<double>::infinity();
  constexpr double kTwoPi = 2.0 * std::numbers::pi;
  // Beams whose angle lies within this margin outside a circle's angular interval are tested
  // too; the exact ray-circle test then decides. It covers approxAtan2's error and rounding.
  constexpr double kAngleMargin = 1e-6;
  constexpr double kBucketsPerMetre = 4.0;  // near-first order at 0.25 m resolution

  const int beams = config_.beams;
  ranges.assign(static_cast<std::size_t>(beams), kInf);
  const double uniform_r = field_->radius;
  const double max_r = kVariedRadii ? field_->maxRadius() : uniform_r;
  const double reach2 = (config_.range_max + max_r) * (config_.range_max + max_r);
  const double increment = config_.angleIncrement();
  const double inverse_increment = 1.0 / increment;
  const double c = std::cos(sensor_pose.yaw);
  const double s = std::sin(sensor_pose.yaw);
  // Circles entirely inside the blind wedge behind the sensor are skipped before any square
  // root. The wedge is the intersection of two half-planes bounded by the edge rays at
  // +-fov_edge; a circle is blind if its centre lies more than r inside both.
  const double fov_edge = std::max(std::abs(config_.angle_min), std::abs(config_.angle_max));
  const bool has_blind_wedge = fov_edge < std::numbers::pi - 1e-3;
  const double edge_c = std::cos(fov_edge);
  const double edge_s = std::sin(fov_edge);

  // Pass 1: every circle in range, in the sensor frame, counted into distance buckets.
  candidates_.clear();
  if constexpr (kVariedRadii) candidate_radius_.clear();
  std::fill(bucket_start_.begin(), bucket_start_.end(), 0);
  const int last_bucket = static_cast<int>(bucket_start_.size()) - 2;
  // Plain pointers: push_back below could alias a vector's members, forcing reloads each turn.
  const Eigen::Vector2d* const centres = field_->centres.data();
  const double* const radii = field_->radii.data();
  const std::size_t count = field_->centres.size();
  for (std::size_t n = 0; n < count; ++n) {
    const Eigen::Vector2d& centre = centres[n];
    const double r = kVariedRadii ? radii[n] : uniform_r;
    const double r2 = r * r;
    const double wx = centre.x() - sensor_pose.x;
    const double wy = centre.y() - sensor_pose.y;
    const double dx = c * wx + s * wy;
    const double dy = -s * wx + c * wy;
    // cross(e1, d) = |d| sin(bearing - fov_edge) > 0 beyond the left edge e1 = (c, s);
    // cross(e2, d) = |d| sin(bearing + fov_edge) < 0 beyond the right edge e2 = (c, -s).
    if (has_blind_wedge && edge_c * dy - edge_s * dx > r && edge_s * dx + edge_c * dy < -r) continue;
    const double dist2 = dx * dx + dy * dy;
    if (dist2 > reach2 || dist2 <= r2) continue;  // out of range, or the sensor is inside it
    const double dist = std::sqrt(dist2);
    const int bucket = std::min(last_bucket, static_cast<int>(dist * kBucketsPerMetre));
    candidates_.push_back({dx, dy, dist2 - r2, dist - r, bucket});
    if constexpr (kVariedRadii) candidate_radius_.push_back(r);
    ++bucket_start_[static_cast<std::size_t>(bucket) + 1];
  }
  for (std::size_t b = 1; b < bucket_start_.size(); ++b) bucket_start_[b] += bucket_start_[b - 1];
  order_.resize(candidates_.size());
  for (std::size_t k = 0; k < candidates_.size(); ++k)
    order_[static_cast<std::size_t>(bucket_start_[static_cast<std::size_t>(candidates_[k].bucket)]++)] = static_cast<int>(k);

  // Pass 2: near circles first, so beams they block skip the farther ones at one comparison.
  const auto castInterval = [&](const Candidate& circle, double lo, double hi) {
    if (hi < config_.angle_min || lo > config_.angle_max) return;
    const int first = std::max(0, static_cast<int>(std::ceil((lo - config_.angle_min) * inverse_increment)));
    const int last = std::min(beams - 1, static_cast<int>(std::floor((hi - config_.angle_min) * inverse_increment)));
    const double nearest = circle.nearest;
    for (int i = first; i <= last; ++i) {
      double& range = ranges[static_cast<std::size_t>(i)];
      if (nearest >= range) continue;  // something closer already blocks this beam
      // Ray p(t) = t u, |u| = 1: |t u - d|^2 = r^2 -> t = u.d - sqrt((u.d)^2 - (|d|^2 - r^2)).
      const double along = beam_cos_[static_cast<std::size_t>(i)] * circle.dx + beam_sin_[static_cast<std::size_t>(i)] * circle.dy;
      const double disc = along * along - circle.power;
      if (disc < 0.0 || along <= 0.0) continue;
      const double t = along - std::sqrt(disc);
      if (t < range) range = t;
    }
  };
  for (int k : order_) {
    const Candidate& circle = candidates_[static_cast<std::size_t>(k)];
    const double r = kVariedRadii ? candidate_radius_[static_cast<std::size_t>(k)] : uniform_r;
    const double bearing = approxAtan2(circle.dy, circle.dx);
    // Half the angle the circle subtends is asin(r / d) <= r / sqrt(d^2 - r^2) (its tangent):
    // a slight over-estimate, cheaper than asin; the exact test rejects the extra beams.
    const double half = r / std::sqrt(circle.power) + kAngleMargin;
    castInterval(circle, bearing - half, bearing + half);
    // An interval reaching past +-pi (behind the sensor) continues on the other side.
    if (bearing + half > std::numbers::pi) castInterval(circle, bearing - half - kTwoPi, bearing + half - kTwoPi);
    if (bearing - half < -std::numbers::pi) castInterval(circle, bearing - half + kTwoPi, bearing + half + kTwoPi);
  }
  for (double& range : ranges) {
    if (range > config_.range_max) range = kInf;
    else if (range < config_.range_min) range = config_.range_min;
  }
}

core::LaserScan LidarCaster::scan(const core::Pose2& robot_pose, double stamp, core::FastNoise* noise) {
  core::LaserScan scan;
  scan.stamp = stamp;
  scan.angle_min = config_.angle_min;
  scan.angle_increment = config_.angleIncrement();
  scan.range_min = config_.range_min;
  scan.range_max = config_.range_max;
  cast(config_.sensorPose(robot_pose), scan.ranges);
  if (noise) addRangeNoise(config_, *noise, scan.ranges);
  return scan;
}

void addRangeNoise(const core::LidarConfig& config, core::FastNoise& noise, std::vector<double>& ranges) {
  if (config.noise_stddev <= 0.0) return;
  for (double& range : ranges) {
    if (!std::isfinite(range)) continue;  // Gazebo's noise does not turn a miss into a hit
    range = std::clamp(range + config.noise_stddev * noise.normal(), config.range_min, config.range_max);
  }
}

}  // namespace barn::sim
