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

/// A costmap as costmap_2d publishes it: costs 0 free, 1-252 inflated, 253 inscribed, 254
/// lethal, 255 unknown, one byte per cell, rows from the lower edge up (x fastest), as
/// nav_msgs/OccupancyGrid orders its data.
struct CostGrid {
  Eigen::Vector2d origin = Eigen::Vector2d::Zero();  // [m] odom frame: the lower-left corner of cell (0, 0)
  double resolution = 0.0;                           // [m] cell size
  int width = 0;                                     // [cells] along x
  int height = 0;                                    // [cells] along y
  const std::uint8_t* costs = nullptr;               // width x height, valid until the next tick
  std::uint64_t version = 0;                         // changes whenever a cost or the origin changed
};

/// The global plan as move_base publishes it: poses from the robot to the goal, made at `stamp`.
struct GlobalPlan {
  std::vector<core::Pose2> poses;  // odom frame, robot -> goal; empty until the first plan is found
  double stamp = -1.0;             // [s] simulated time the plan was made (-1: none yet)
};

/// Stack parameters a controller may change while it runs, as dynamic_reconfigure sets them
/// on a ROS move_base (docs/controllers.md lists the keys). set() throws
/// std::invalid_argument, naming the key, for a key that is not settable or a bad value.
class StackParameters {
 public:
  virtual ~StackParameters() = default;
  virtual void set(std::string_view key, double value) = 0;
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
  // With a `global_plan` block in the controller's config (docs/controllers.md, "Bring your
  // own local planner"), move_base's plan and, on request, its costmaps; null otherwise.
  const GlobalPlan* global_plan = nullptr;
  const CostGrid* local_costmap = nullptr;
  const CostGrid* global_costmap = nullptr;
  StackParameters* stack_parameters = nullptr;  // settable while acting; null without the block
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
  /// sim::plantHash of the plant the controller's learned policy was trained on; 0 if it
  /// has none or the policy does not say. A run warns when it is not the run's plant.
  virtual std::uint64_t trainedPlant() const { return 0; }
  /// The stack parameters the last act() changed, as `key=value` pairs separated by ';'
  /// ("" if none), for the trajectory record.
  virtual std::string_view parameterChanges() const { return {}; }
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
