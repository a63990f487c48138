#pragma once
/// Free-space motion tubes (Rodrigues, Tsiogkas, Huebel, Bruyninckx, ISRR 2022), the library
/// the `kulfm` controller selects from: the area a rectangular robot sweeps along one
/// constant-curvature manoeuvre, described by samples on its boundary, each sample mapped once
/// to the LiDAR beam that looks at it and its range from the sensor. A tube is free when no beam
/// sees a return nearer than its samples: a check of a few tens of numbers, independent of the
/// LiDAR's resolution.
///
/// Robot frame throughout: x forward, y left, origin at the robot centre (the team's "axle"
/// reference point, base_link).
///
/// One tube, for a manoeuvre of signed arc length L (negative: reversing) on a circle of signed
/// radius R (positive: turning left) about the centre of rotation c = (0, R), heading change
/// theta = L / R. With the side s = sign(R) and the leading edge at x_lead = axle_to_front (forward)
/// or -axle_to_rear (reversing):
///   edge     - the arc of the leading outer corner (x_lead, -s w/2) over theta, the arc of the
///              inner side's centre point (0, s w/2) over theta (the body point nearest c), and at
///              the final pose the inner side from that point to the inner leading corner and the
///              leading edge between the two leading corners;
///   outer    - the whisker arc side_whisker_offset outside the outer corner's arc (same angles);
///   inner    - the whisker arc side_whisker_offset inside the inner point's arc;
///   front    - the leading edge at the final pose pushed front_whisker_offset further along the
///              direction of travel.
/// Arcs and segments are sampled at most `edge_step` (whiskers: `whisker_step`) apart, both ends
/// included (the paper's rule). The 2025 code (romulortr/fsmt_ros@75febc5) drops an arc's last
/// sample and, reversing, takes the front outer corner's arc with a side segment of the whole
/// body length; here reversing mirrors driving forward.

#include <vector>

#include <Eigen/Core>

#include "barn/core/config.hpp"
#include "barn/core/errors.hpp"
#include "barn/core/lidar_config.hpp"
#include "barn/core/types.hpp"

namespace barn::controllers {

/// The geometry of the tube library. Defaults: the 2025 code's (romulortr/fsmt_ros@75febc5,
/// fsmt/src/navigation/navigation_with_global_wp_plan.c and src/fsmt_base_local_planner.cpp).
struct MotionTubeConfig {
  double length = 0.75;
  double backward_length = 0.75;
  double max_angle_deg = 90.0;
  double angle_step_deg = 0.5;
  double min_curvature = 0.001;
  double radius_factor = 0.9;
  double vehicle_width = 0.5;
  double axle_to_front = 0.2;
  double axle_to_rear = 0.2;
  double edge_step = 0.1;
  double whisker_step = 0.1;
  double side_whisker_offset = 0.1;
  double front_whisker_offset = 0.05;

  template <class V> void visit(V& v) {
    v("length", length, {.unit = "m", .range = core::kPositive, .doc = "2025 code: nominal tube arc length"});
    v("backward_length", backward_length,
      {.unit = "m", .range = core::kPositive, .doc = "2025 code: the recovery tubes run -0.75 m"});
    v("max_angle_deg", max_angle_deg,
      {.unit = "deg", .range = core::closed(0.0, 180.0), .doc = "2025 code: nominal heading change 0 ... 90 deg, both sides"});
    v("angle_step_deg", angle_step_deg, {.unit = "deg", .doc = "2025 code: 2 (90 / 0.5 + 1) = 362 tubes"});
    v("min_curvature", min_curvature,
      {.unit = "1/m", .range = core::kPositive, .doc = "2025 code: curvature alpha / L floored here (the straight tubes)"});
    v("radius_factor", radius_factor,
      {.range = core::kPositive, .doc = "2025 code: stored radius 0.9 / curvature (tighter than nominal)"});
    v("vehicle_width", vehicle_width,
      {.unit = "m", .range = core::kPositive, .doc = "2025 code: box width (Jackal: 0.43 with the wheels)"});
    v("axle_to_front", axle_to_front, {.unit = "m", .range = core::kNonNegative, .doc = "2025 code"});
    v("axle_to_rear", axle_to_rear, {.unit = "m", .range = core::kNonNegative, .doc = "2025 code"});
    v("edge_step", edge_step, {.unit = "m", .range = core::kPositive, .doc = "2025 code: sampling step of the edge"});
    v("whisker_step", whisker_step,
      {.unit = "m", .range = core::kPositive, .doc = "2025 code: sampling step of the whiskers"});
    v("side_whisker_offset", side_whisker_offset,
      {.unit = "m", .range = core::kNonNegative, .doc = "2025 code: whiskers_distance.side"});
    v("front_whisker_offset", front_whisker_offset,
      {.unit = "m", .range = core::kNonNegative, .doc = "2025 code: whiskers_distance.front"});
  }
};
void validate(const MotionTubeConfig& config, core::Errors& errors, const std::string& prefix);

/// A boundary sample as the LiDAR sees it: the beam pointing at it and its range from the sensor.
struct SensorSample {
  int beam = 0;        // [-] scan index
  double range = 0.0;  // [m] from the sensor origin
};
using SampleSet = std::vector<SensorSample>;

/// The beam looking at robot-frame point `p` and its range from the sensor (at the LiDAR's
/// mount offset, facing forward): beam = round((atan2(y, x) - angle_min) / increment) for
/// (x, y) = p - mount. False if the bearing is outside [angle_min, angle_max] or the range
/// outside [range_min, range_max]: the LiDAR cannot check that point, and it is left out.
bool toSensorSample(const Eigen::Vector2d& p, const core::LidarConfig& lidar, SensorSample& sample);

/// The points of `points` the LiDAR can check, in order.
SampleSet toSampleSet(const std::vector<Eigen::Vector2d>& points, const core::LidarConfig& lidar);

/// Availability: true unless some sample's beam reads a return strictly inside
/// (range_min, range_max) that is nearer than the sample. Readings outside those limits (no
/// return, or too close to trust) say nothing. An empty set is free.
bool isFree(const SampleSet& samples, const core::LaserScan& scan);

/// The boundary of one tube in the robot frame (see the header comment).
struct TubeShape {
  std::vector<Eigen::Vector2d> edge, outer, inner, front;  // [m] robot frame
};

/// One manoeuvre of the library with its boundary mapped to the LiDAR.
struct MotionTube {
  double length = 0.0;          // [m] signed arc length of the robot centre (negative: reversing)
  double radius = 0.0;          // [m] signed turning radius (positive: left)
  double heading_change = 0.0;  // [rad] length / radius
  core::Pose2 end;              // the robot's pose at the end, in the start frame
  TubeShape shape;              // robot frame (for plots and tests)
  SampleSet edge, outer, inner, front;
};

/// The pose reached after arc length `length` on a circle of signed radius `radius`:
/// (R sin(L/R), R (1 - cos(L/R)), L/R).
core::Pose2 arcEnd(double length, double radius);

/// The boundary of the tube of (length, radius) for the configured vehicle and sampling.
TubeShape tubeShape(double length, double radius, const MotionTubeConfig& config);

/// The library for arc length `length` (config.length or -config.backward_length), in the 2025
/// code's order: for alpha = 0, step, ..., max_angle, the left tube then the right one, each of
/// curvature max(alpha / |length|, min_curvature) and radius radius_factor / curvature.
std::vector<MotionTube> buildTubeLibrary(double length, const MotionTubeConfig& config, const core::LidarConfig& lidar);

/// The rotation check: for every beam, the range at which it leaves a circle of `radius` about
/// the robot centre (from the sensor, at its mount offset). Turning in place is taken as safe
/// when this set is free. (The 2025 code adds the mount offset a second time when it turns the
/// intersection into a range: 0.455 m instead of 0.345 m straight ahead, 0.367 m instead of
/// 0.437 m at the widest bearings; here the range is the geometric one.)
SampleSet rotationRing(double radius, const core::LidarConfig& lidar);

}  // namespace barn::controllers
