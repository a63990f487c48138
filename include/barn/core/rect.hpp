#pragma once
/// The one rectangle type of the robot frame (x forward, y left): the robot's planning
/// footprint, the parts of its collision shape, and the regions the safety checks test.

#include <algorithm>
#include <array>
#include <cmath>

#include <Eigen/Core>

namespace barn::core {

/// An axis-aligned rectangle [m].
struct Rect {
  double min_x = 0.0, max_x = 0.0;
  double min_y = 0.0, max_y = 0.0;

  /// `length` along x by `width` along y, centred on the origin.
  static Rect centred(double length, double width) { return {-length / 2, length / 2, -width / 2, width / 2}; }
  /// Centred on (centre_x, centre_y) with the given half extents.
  static Rect around(double centre_x, double centre_y, double half_length, double half_width) {
    return {centre_x - half_length, centre_x + half_length, centre_y - half_width, centre_y + half_width};
  }

  bool contains(const Eigen::Vector2d& p) const {
    return p.x() >= min_x && p.x() <= max_x && p.y() >= min_y && p.y() <= max_y;
  }
  /// Squared distance from `p` to the rectangle (0 inside): `p` minus its nearest point.
  double squaredDistance(const Eigen::Vector2d& p) const {
    const double dx = p.x() - std::clamp(p.x(), min_x, max_x);
    const double dy = p.y() - std::clamp(p.y(), min_y, max_y);
    return dx * dx + dy * dy;
  }
  /// The rectangle grown by `offset` on every side (shrunk if negative).
  Rect grownBy(double offset) const { return {min_x - offset, max_x + offset, min_y - offset, max_y + offset}; }

  double centreX() const { return 0.5 * (min_x + max_x); }
  double centreY() const { return 0.5 * (min_y + max_y); }
  double halfLength() const { return 0.5 * (max_x - min_x); }
  double halfWidth() const { return 0.5 * (max_y - min_y); }
  /// Distance from the origin to the farthest corner: the radius the rectangle sweeps turning
  /// about the origin.
  double farthestCornerDistance() const {
    return std::hypot(std::max(std::abs(min_x), std::abs(max_x)), std::max(std::abs(min_y), std::abs(max_y)));
  }

  /// Front left, rear left, rear right, front right: counter-clockwise.
  std::array<Eigen::Vector2d, 4> corners() const {
    return {Eigen::Vector2d(max_x, max_y), Eigen::Vector2d(min_x, max_y), Eigen::Vector2d(min_x, min_y),
            Eigen::Vector2d(max_x, min_y)};
  }
};

}  // namespace barn::core
