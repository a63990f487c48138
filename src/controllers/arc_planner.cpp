#include "barn/controllers/arc_planner.hpp"

#include <algorithm>
#include <cmath>
#include <limits>
#include <numbers>

namespace barn::controllers {

namespace {

constexpr double kInf = std::numeric_limits<double>::infinity();
// graph_navigation treats |curvature| below this as a straight line.
constexpr double kStraight = 1e-5;

double sq(double x) { return x * x; }

}  // namespace

void validate(const ArcPlannerConfig& c, core::Errors& errors, const std::string& prefix) {
  core::validateFields(c, errors, prefix);
}

double timeOptimalSpeed(const MotionLimits& limits, double speed, double distance, double dt) {
  const double v = std::abs(speed);
  const double dv_accel = dt * limits.max_accel;
  const double dv_decel = dt * limits.max_decel;
  // Where a stop would end after one more period of accelerating, or of holding this speed.
  const double accel_stop = (v + 0.5 * dv_accel) * dt + sq(v + dv_accel) / (2.0 * limits.max_decel);
  const double cruise_stop = v * dt + sq(v) / (2.0 * limits.max_decel);
  if (distance > 0.0) {
    if (v > limits.max_speed) return std::max(0.0, v - dv_decel);
    if (v < limits.max_speed && accel_stop < distance) return std::min(limits.max_speed, v + dv_accel);
    if (cruise_stop < distance) return v;
    return std::max(0.0, v - dv_decel);
  }
  return v > 0.0 ? std::max(0.0, v - dv_decel) : 0.0;
}

Arc evaluateArc(double curvature, const Eigen::Vector2d& target, std::span<const Eigen::Vector2d> points, double speed,
                double max_decel, const ArcPlannerConfig& c) {
  Arc arc;
  arc.curvature = curvature;
  const double stopping = sq(speed) / (2.0 * max_decel);
  // The robot's box plus margin: front and rear edge along x, half width.
  const double front = 0.5 * c.robot_length - c.base_link_offset + c.obstacle_margin;
  const double rear = -0.5 * c.robot_length + c.base_link_offset - c.obstacle_margin;
  const double half_width = 0.5 * c.robot_width + c.obstacle_margin;
  arc.clearance = c.max_clearance;

  if (std::abs(curvature) < kStraight) {
    // Straight: to abeam the target at most, then cut by the first point in the swept band.
    double length = std::max(std::min(c.max_free_path_length, target.x()), stopping);
    for (const Eigen::Vector2d& p : points)
      if (std::abs(p.y()) <= half_width && p.x() >= 0.0) length = std::min(length, p.x() - front);
    length = std::max(0.0, length);
    if (length < stopping) length = 0.0;
    arc.length = length;
    const double reach = c.clearance_clip * length + front;
    for (const Eigen::Vector2d& p : points)
      if (p.x() >= 0.0 && p.x() <= reach) arc.clearance = std::min(arc.clearance, std::abs(p.y()));
    arc.end = {length, 0.0};
    return arc;
  }

  // Curved: the turn centre is (0, R); every angle is measured around it from the robot.
  const double radius = 1.0 / curvature;
  const double abs_radius = std::abs(radius);
  const Eigen::Vector2d centre(0.0, radius);
  // At most to the arc's point nearest the target, and a quarter circle.
  const Eigen::Vector2d target_radial = target - centre;
  const double target_angle = std::atan2(std::abs(target_radial.x()), std::abs(target_radial.y()));
  double length = std::min({c.max_free_path_length, target_angle * abs_radius, abs_radius * std::numbers::pi / 2.0});
  length = std::max(length, stopping);

  const double side = radius > 0.0 ? 1.0 : -1.0;
  const Eigen::Vector2d inner_front(front, side * half_width);
  const Eigen::Vector2d outer_front(front, -side * half_width);
  const double r_inner = std::max(0.0, abs_radius - half_width);  // the inner side's radius
  const double r_inner_sq = sq(r_inner);
  const double r_corner_sq = (inner_front - centre).squaredNorm();  // inner front corner
  const double r_outer_sq = (outer_front - centre).squaredNorm();   // outer front corner
  auto angle_of = [&](const Eigen::Vector2d& p) {
    return curvature > 0.0 ? std::atan2(p.x(), radius - p.y()) : std::atan2(p.x(), p.y() - radius);
  };
  double obstruction_angle = std::numbers::pi;
  for (const Eigen::Vector2d& p : points) {
    if (!std::isfinite(p.x()) || !std::isfinite(p.y()) || p.x() < 0.0) continue;
    if (p.x() > rear && p.x() < front && std::abs(p.y()) < half_width) {
      // Already inside the box plus margin: not drivable at all.
      length = 0.0;
      obstruction_angle = 0.0;
      break;
    }
    const double r_sq = (p - centre).squaredNorm();
    if (r_sq < r_inner_sq || r_sq > r_outer_sq) continue;  // outside the swept annulus
    const double r = std::sqrt(r_sq);
    const double theta = angle_of(p);
    // How far ahead of the robot's radial the point is when the box first touches it: by the
    // inner side (inside the inner front corner's circle) or by the front.
    double alpha;
    if (r_sq < r_corner_sq) {
      const double x = abs_radius - half_width;
      alpha = x > 0.0 ? std::acos(std::min(1.0, x / r)) : std::numbers::pi / 2.0 + std::acos(std::min(1.0, -x / r));
    } else {
      alpha = std::asin(std::min(1.0, front / r));
    }
    const double cut = std::max(0.0, abs_radius * (theta - alpha));
    if (length > cut) {
      length = cut;
      obstruction_angle = theta;
    }
  }
  if (length < stopping) length = 0.0;
  length = std::max(0.0, length);
  arc.length = length;

  // Clearance: distance from the centre line of the points passed in the first part of the arc.
  const double sweep = std::min(obstruction_angle, length * std::abs(curvature));
  const double limit = c.clearance_clip * sweep;
  // 0 < angle < limit (< pi) as two cross products against the start radial u0 and the radial
  // at `limit` (no atan2 per point): in the turning sense, u0 x v > 0 and v x u_limit > 0.
  const Eigen::Vector2d u0(0.0, -side);
  const Eigen::Vector2d u_limit(std::sin(limit), -side * std::cos(limit));
  auto turn_cross = [&](const Eigen::Vector2d& a, const Eigen::Vector2d& b) { return side * (a.x() * b.y() - a.y() * b.x()); };
  for (const Eigen::Vector2d& p : points) {
    const Eigen::Vector2d v = p - centre;
    const double d = std::abs(v.norm() - abs_radius);
    if (d >= arc.clearance) continue;
    const bool within = limit < std::numbers::pi ? turn_cross(u0, v) > 0.0 && turn_cross(v, u_limit) > 0.0
                                                 : angle_of(p) > 0.0 && angle_of(p) < limit;
    if (within) arc.clearance = d;
  }
  arc.clearance = std::max(0.0, arc.clearance);
  const double a = length * curvature;  // signed turn along the arc
  arc.end = length == 0.0 ? Eigen::Vector2d::Zero() : Eigen::Vector2d(radius * std::sin(a), radius * (1.0 - std::cos(a)));
  return arc;
}

std::vector<Arc> sampleArcs(const Eigen::Vector2d& target, std::span<const Eigen::Vector2d> points, double speed,
                            double max_decel, const ArcPlannerConfig& c) {
  std::vector<Arc> arcs;
  arcs.reserve(static_cast<std::size_t>(c.num_options));
  for (int i = 0; i < c.num_options; ++i) {
    const double curvature = -c.max_curvature + 2.0 * c.max_curvature * i / (c.num_options - 1);
    arcs.push_back(evaluateArc(curvature, target, points, speed, max_decel, c));
  }
  return arcs;
}

double straightLineClearance(const Eigen::Vector2d& a, const Eigen::Vector2d& b, std::span<const Eigen::Vector2d> points) {
  const Eigen::Vector2d d = b - a;
  const double length = d.norm();
  double clearance = kInf;
  if (length <= 0.0) return clearance;
  const Eigen::Vector2d u = d / length;
  for (const Eigen::Vector2d& p : points) {
    const Eigen::Vector2d ap = p - a;
    const double along = u.dot(ap);
    if (along < 0.0 || along > length) continue;
    clearance = std::min(clearance, std::abs(u.x() * ap.y() - u.y() * ap.x()));
  }
  return clearance;
}

int chooseArc(std::span<const Arc> arcs, const Eigen::Vector2d& target, std::span<const Eigen::Vector2d> points,
              const ArcPlannerConfig& c) {
  // The distance on from each arc's end, if the straight line from there sees the target.
  std::vector<double> to_target(arcs.size(), kInf);
  bool any_sees_target = false;
  for (std::size_t i = 0; i < arcs.size(); ++i)
    if (straightLineClearance(arcs[i].end, target, points) > 0.0) {
      to_target[i] = (arcs[i].end - target).norm();
      any_sees_target = true;
    }
  auto path_length = [&](std::size_t i) { return any_sees_target ? arcs[i].length + to_target[i] : to_target[i]; };
  // The shortest way to the target sets the baseline ...
  int best = -1;
  double best_length = kInf;
  for (std::size_t i = 0; i < arcs.size(); ++i) {
    if (arcs[i].length <= 0.0) continue;
    if (path_length(i) < best_length) {
      best_length = path_length(i);
      best = static_cast<int>(i);
    }
  }
  if (best < 0) return -1;
  // ... which a cheaper arc beats; the baseline's own distance counts subopt times.
  const Arc& base = arcs[static_cast<std::size_t>(best)];
  double best_cost = c.dw * (c.subopt * best_length) + c.fw * base.length + c.cw * base.clearance;
  for (std::size_t i = 0; i < arcs.size(); ++i) {
    if (arcs[i].length <= 0.0) continue;
    const double cost = c.dw * path_length(i) + c.fw * arcs[i].length + c.cw * arcs[i].clearance;
    if (cost < best_cost) {
      best_cost = cost;
      best = static_cast<int>(i);
    }
  }
  return best;
}

ArcCommand haltCommand(double speed, const MotionLimits& linear, double dt) {
  ArcCommand command;
  if (std::abs(speed) > 0.01) {
    const double dv = linear.max_decel * dt;
    if (speed < -dv) command.linear = speed + dv;
    else if (speed > dv) command.linear = speed - dv;
  }
  return command;
}

ArcCommand turnInPlaceCommand(double angle, double speed, double yaw_rate, const MotionLimits& linear,
                              const MotionLimits& angular, double max_turn_speed, double dt) {
  if (std::abs(speed) > max_turn_speed) return haltCommand(speed, linear, dt);
  ArcCommand command;
  const double s = angle >= 0.0 ? 1.0 : -1.0;
  if (yaw_rate * angle < 0.0) {
    // Turning the wrong way: slow the turn down first.
    const double dw = dt * angular.max_accel;
    command.angular = std::abs(yaw_rate) < dw ? 0.0 : yaw_rate - (yaw_rate > 0.0 ? dw : -dw);
  } else {
    command.angular = s * timeOptimalSpeed(angular, s * yaw_rate, s * angle, dt);
  }
  return command;
}

}  // namespace barn::controllers
