#pragma once
/// The physics of one episode: a Box2D world holding BARN's static cylinders and the Jackal
/// as a dynamic body driven like diff_drive_controller, with a traction limit.
///
/// Nothing advances unless step() is called; every step has the same fixed dt. Box2D stays
/// behind this interface (no Box2D header is included here), and each Simulator owns its own
/// b2World, so episodes run in parallel threads without sharing anything.
///
/// Drive model, per physics step of dt:
///  1. Command timeout: without a command newer than `cmd_timeout`, the target is (0, 0).
///  2. diff_drive_controller: the wheel set-point (v_w, w_w) moves toward the clamped target by
///     at most max_linear_accel dt and max_angular_accel dt.
///  3. Traction: the body velocity moves toward the wheel set-point (v_w along the heading, no
///     sideways motion) by at most mu g dt (one friction circle for forward and sideways
///     change) and the yaw rate by at most max_angular_traction_accel dt. The 20 m/s^2 of the
///     controller exceeds the ~4.9 m/s^2 the ground can give, so hard braking slides.
///  4. Box2D integrates the body with that velocity. Robot fixtures create no contacts (they
///     would push the robot 1 cm early, Box2D's polygon skin); instead the step ends with an
///     exact rectangle-circle overlap test of the five collision rectangles against the
///     cylinders that Box2D's broad-phase returns near the robot.

#include <cstdint>
#include <memory>
#include <optional>
#include <vector>

#include <Eigen/Core>

#include "barn/core/config.hpp"
#include "barn/core/errors.hpp"
#include "barn/core/rng.hpp"
#include "barn/core/robot_config.hpp"
#include "barn/core/types.hpp"
#include "barn/sim/lidar.hpp"
#include "barn/sim/obstacle_field.hpp"

namespace barn::sim {

struct PhysicsConfig {
  double rate = 200.0;
  int velocity_iterations = 8;
  int position_iterations = 3;

  // Iterations' upper bounds (our choice, 100x Box2D's defaults of 8 and 3): more makes an
  // episode take hours while changing nothing, and a stop (Ctrl-C, SIGTERM) waits for running
  // episodes.
  template <class V> void visit(V& v) {
    v("rate", rate,
      {.unit = "Hz", .range = core::closed(10.0, 100000.0), .doc = "fixed physics step (Gazebo: 1000); see the README for the choice"});
    v("velocity_iterations", velocity_iterations, {.range = core::closed(1, 1000), .doc = "Box2D solver iterations"});
    v("position_iterations", position_iterations, {.range = core::closed(1, 1000)});
  }
  double dt() const { return 1.0 / rate; }
};

void validate(const PhysicsConfig& config, core::Errors& errors, const std::string& prefix = "physics");

/// Identifies a plant: FNV-1a of the effective `robot` and `physics` sections. A policy learns
/// how one plant moves (it steers wrongly on another), so recordings and policies carry it and a
/// run can tell when a policy drives a robot it was not trained on. Never 0.
std::uint64_t plantHash(const core::RobotConfig& robot, const PhysicsConfig& physics);

/// Where a collision happened: the first contact found at the first colliding step.
struct CollisionInfo {
  double time = 0.0;                          // [s]
  Eigen::Vector2d point = Eigen::Vector2d::Zero();  // [m] cylinder centre that was hit
  int rect_index = -1;                        // 0 chassis, 1-4 wheels
  core::Pose2 pose;                           // the robot's pose at contact (not kept in episodes.csv)
};

class Simulator {
 public:
  /// `seed` drives the robot's random turn slip (core::RobotConfig::turn_slip_speed), if any.
  Simulator(const ObstacleField& field, const core::RobotConfig& robot, const PhysicsConfig& physics,
            const core::Pose2& start, std::uint64_t seed = 0);
  ~Simulator();
  Simulator(const Simulator&) = delete;
  Simulator& operator=(const Simulator&) = delete;

  /// A new cmd_vel at the current time (it is clamped to the speed limits when applied).
  void command(const core::Twist& cmd);
  /// Advances one fixed physics step.
  void step();

  double time() const { return time_; }     // [s]
  double dt() const { return physics_.dt(); }
  core::Pose2 pose() const { return pose_; }
  /// Body velocity in the robot frame: forward, sideways (slip) and yaw rate.
  double forwardSpeed() const;   // [m/s]
  double sidewaysSpeed() const;  // [m/s]
  double yawRate() const { return yaw_rate_; }  // [rad/s]
  /// The drive's wheel set-point (what the wheels turn at, slip included).
  core::Twist wheelSetpoint() const { return wheel_; }
  const std::optional<CollisionInfo>& collision() const { return collision_; }

  /// Box2D RayCast scan from `sensor_pose` (world frame), the reference for LidarCaster:
  /// one b2World::RayCast per beam, closest hit. Box2D works in float32, so its ranges carry
  /// errors of up to ~1e-4 m at 10 m; `hit` names the cylinder each beam hit (-1: none) so a
  /// test can also compare which obstacle was seen.
  struct ReferenceScan {
    std::vector<double> ranges;  // [m] +inf for no hit within range_max
    std::vector<int> hit;        // index into ObstacleField::centres, -1 for no hit
  };
  ReferenceScan referenceScan(const core::LidarConfig& lidar, const core::Pose2& sensor_pose) const;

  /// True if the robot's collision shape at `pose` overlaps a cylinder (exact geometry).
  bool overlaps(const core::Pose2& pose) const;

 private:
  struct Box2D;  // the b2World and the robot body
  std::optional<CollisionInfo> findCollision(const core::Pose2& pose) const;

  const ObstacleField* field_;
  core::RobotConfig robot_;
  PhysicsConfig physics_;
  std::vector<core::Rect> rects_;
  std::unique_ptr<Box2D> box2d_;

  double time_ = 0.0;
  core::Pose2 pose_;
  Eigen::Vector2d velocity_ = Eigen::Vector2d::Zero();  // [m/s] world frame
  double yaw_rate_ = 0.0;
  core::Twist cmd_;                  // last command received
  double cmd_time_ = -1e9;           // [s] when it arrived
  core::Twist wheel_;                // diff_drive_controller set-point
  core::FastNoise slip_noise_;
  Eigen::Vector2d slip_ = Eigen::Vector2d::Zero();  // [m/s] world frame, turn slip velocity
  std::optional<CollisionInfo> collision_;
};

/// Exact overlap of a rectangle (in `pose`'s frame) with a circle in the world frame.
bool rectOverlapsCircle(const core::Pose2& pose, const core::Rect& rect, const Eigen::Vector2d& centre, double radius);

/// Box2D 2.4.1 initialises a static table on its first contact; call once before running
/// simulators on several threads.
void prepareForThreads();

}  // namespace barn::sim
