#pragma once
/// Plain types shared by the simulator, the controllers and the runner.

#include <cmath>
#include <numbers>
#include <vector>

#include <Eigen/Core>

namespace barn::core {

/// A planar pose. Angles are radians, counter-clockwise from +x.
struct Pose2 {
  double x = 0.0;    // [m]
  double y = 0.0;    // [m]
  double yaw = 0.0;  // [rad]

  Eigen::Vector2d position() const { return {x, y}; }
  /// The point `p` given in this pose's frame, expressed in the parent frame.
  Eigen::Vector2d transform(const Eigen::Vector2d& p) const;
  /// The parent-frame point `p` expressed in this pose's frame.
  Eigen::Vector2d inverseTransform(const Eigen::Vector2d& p) const;
};

/// Pose2::transform and inverseTransform with the pose's cosine and sine computed once, for
/// loops over many points (the compiler cannot hoist std::cos, which may set errno).
class PoseFrame {
 public:
  explicit PoseFrame(const Pose2& pose) : x_(pose.x), y_(pose.y), c_(std::cos(pose.yaw)), s_(std::sin(pose.yaw)) {}
  /// A point given in the pose's frame, in the parent frame (Pose2::transform).
  Eigen::Vector2d toParent(const Eigen::Vector2d& p) const {
    return {x_ + c_ * p.x() - s_ * p.y(), y_ + s_ * p.x() + c_ * p.y()};
  }
  /// A parent-frame point in the pose's frame (Pose2::inverseTransform).
  Eigen::Vector2d toLocal(const Eigen::Vector2d& p) const {
    const double dx = p.x() - x_, dy = p.y() - y_;
    return {c_ * dx + s_ * dy, -s_ * dx + c_ * dy};
  }

 private:
  double x_, y_, c_, s_;
};

inline Eigen::Vector2d Pose2::transform(const Eigen::Vector2d& p) const { return PoseFrame(*this).toParent(p); }
inline Eigen::Vector2d Pose2::inverseTransform(const Eigen::Vector2d& p) const { return PoseFrame(*this).toLocal(p); }

/// A velocity command in the robot frame, as ROS cmd_vel for a differential drive.
struct Twist {
  double linear = 0.0;   // [m/s] forward
  double angular = 0.0;  // [rad/s] counter-clockwise
};

/// One 2D LiDAR scan, as a ROS LaserScan: beam i points at angle_min + i * angle_increment
/// in the sensor frame. Rays that hit nothing within range_max report +infinity.
struct LaserScan {
  double stamp = 0.0;            // [s] simulated time of the scan
  double angle_min = 0.0;        // [rad]
  double angle_increment = 0.0;  // [rad]
  double range_min = 0.0;        // [m]
  double range_max = 0.0;        // [m]
  std::vector<double> ranges;    // [m] +inf for no return

  double angle(std::size_t i) const { return angle_min + static_cast<double>(i) * angle_increment; }
};

/// Wraps an angle to [-pi, pi).
inline double wrapAngle(double a) {
  constexpr double kTwoPi = 2.0 * std::numbers::pi;
  a = std::fmod(a + std::numbers::pi, kTwoPi);
  if (a < 0) a += kTwoPi;
  return a - std::numbers::pi;
}

}  // namespace barn::core
