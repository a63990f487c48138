#pragma once
/// The controller interface: what a navigation stack sees and what it returns.
///
/// A controller sees only what the real robot would: the latest LiDAR scan, odometry in the
/// odom frame, the goal and the time. It never sees Box2D or the world file's grid. It returns
/// a cmd_vel. Everything a controller remembers lives in its members (no statics), and reset()
/// starts it afresh, so one object can run many episodes one after another.

#include <cstdint>
#include <memory>
#include <string>
#include <string_view>
#include <vector>

#include <Eigen/Core>

#include "barn/core/lidar_config.hpp"
#include "barn/core/robot_config.hpp"
#include "barn/core/types.hpp"

namespace barn::controllers {

/// What a controller is told once per episode.
struct EpisodeInfo {
  core::Pose2 start;                   // odom frame: the origin, heading as the protocol says
  Eigen::Vector2d goal = Eigen::Vector2d::Zero();  // [m] odom frame
  double goal_tolerance = 1.0;         // [m] success radius
  std::uint64_t seed = 0;              // for any randomness the controller declares
  core::LidarConfig lidar;              // sensor geometry: mount offset, beam layout, range
  core::RobotConfig robot;              // speed limits and the planning footprint
};

/// One control tick's input.
struct Observation {
  double time = 0.0;                 // [s] simulated time since the episode began
  const core::LaserScan* scan = nullptr;  // the latest scan (never null during an episode)
  core::Pose2 odom_pose;             // odom frame
  // The odometry when the scan was taken (what tf gives a ROS node at the scan's stamp; the
  // drift included, the optional white noise of odom_pose not): the pose to place the scan's
  // returns with. The scan is up to one LiDAR period older than the tick.
  core::Pose2 scan_odom_pose;
  core::Twist odom_twist;            // robot frame: forward speed, yaw rate
  Eigen::Vector2d goal = Eigen::Vector2d::Zero();  // [m] odom frame
};

class Controller {
 public:
  virtual ~Controller() = default;
  /// Forget everything: a new episode starts.
  virtual void reset(const EpisodeInfo& info) = 0;
  /// One control tick. No I/O, no globals. Throwing or returning NaN ends the episode with an
  /// error outcome.
  virtual core::Twist act(const Observation& observation) = 0;
  /// Control period [s]; act() is called every period of simulated time.
  virtual double period() const = 0;
  /// Current state label for the trajectory record ("" if the controller has no states).
  virtual std::string_view stateLabel() const { return {}; }
  /// Throws core::InputError if the controller cannot read this LiDAR's scans (a learned
  /// policy trained on another beam count); checked once before a run starts.
  virtual void checkLidar(const core::LidarConfig& /*lidar*/) const {}
  /// learning::plantHash of the plant the controller's learned policy was trained on; 0 if it
  /// has none or the policy does not say. A run warns when it is not the run's plant.
  virtual std::uint64_t trainedPlant() const { return 0; }
};

/// A test fixture that is handed the world's A* path (odom frame) before each reset, by the
/// episode runner and nobody else. Real controllers never implement this: they see only what
/// the robot sees.
class UsesReferencePath {
 public:
  virtual ~UsesReferencePath() = default;
  virtual void setReferencePath(std::vector<Eigen::Vector2d> path) = 0;
};

}  // namespace barn::controllers
