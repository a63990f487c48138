#pragma once
/// One BARN episode as the official run.py runs it: spawn at the protocol's start, drive
/// until success, collision or timeout, and score.
///
/// The rules that end an episode and time it (run.py's timer, 0.1 s status checks, success
/// radius, collision, timeout) are bench::ProtocolMonitor's (protocol_monitor.hpp); an
/// Episode runs the latency queue and the physics and asks the monitor after every step.

#include <cstdint>
#include <deque>
#include <optional>
#include <string>
#include <string_view>
#include <vector>

#include "barn/bench/odometry_drift.hpp"
#include "barn/bench/protocol_monitor.hpp"
#include "barn/controllers/controller.hpp"
#include "barn/core/config.hpp"
#include "barn/core/protocol.hpp"
#include "barn/core/rng.hpp"
#include "barn/core/robot_config.hpp"
#include "barn/core/world.hpp"
#include "barn/sim/lidar.hpp"
#include "barn/sim/obstacle_field.hpp"
#include "barn/sim/simulator.hpp"

namespace barn::bench {

/// The odometry a controller sees: the ground truth shifted to the start (the default), an
/// integrated dead-reckoning estimate that drifts (`drift`, see odometry_drift.hpp), and/or
/// white Gaussian noise added on top at every control tick.
struct OdometryNoise {
  double position_stddev = 0.0;
  double yaw_stddev = 0.0;
  double speed_stddev = 0.0;
  OdometryDriftConfig drift;
  // Upper bounds, our choice: noise larger than the field (or a turn) means nothing.
  template <class V> void visit(V& v) {
    v("position_stddev", position_stddev, {.unit = "m", .range = core::closed(0.0, 10.0), .doc = "on x and y"});
    v("yaw_stddev", yaw_stddev, {.unit = "rad", .range = core::closed(0.0, 10.0)});
    v("speed_stddev", speed_stddev,
      {.unit = "m/s, rad/s", .range = core::closed(0.0, 10.0), .doc = "on the forward speed and on the yaw rate"});
    v("drift", drift);
  }
};

/// Delays between the controller and the robot, a realism setting (0 = none, the default).
/// Under ROS a command reaches Gazebo's drive plugin some time after the scan it was computed
/// from: costmap updates run in their own thread at 20 Hz, the controller reads whatever map is
/// there, and cmd_vel crosses a topic. Rounded to whole physics steps.
struct LatencyConfig {
  double command = 0.0;  // none
  template <class V> void visit(V& v) {
    v("command", command,
      {.unit = "s", .range = core::closed(0.0, 1.0), .doc = "from the controller's tick to the drive applying its command"});
  }
};

/// Everything about an episode except the world and the controller.
struct EpisodeConfig {
  core::ProtocolName protocol = core::ProtocolName::Barn2023;
  /// Robot centre to goal at success. Every edition's run.py uses 1 m; its drafts of
  /// March 2022 used less, so logs of that time compare only at their radius (docs/fidelity.md).
  double success_radius = core::Protocol{}.success_radius;
  sim::PhysicsConfig physics;
  core::RobotConfig robot;
  core::LidarConfig lidar;
  OdometryNoise odometry;
  LatencyConfig latency;

  template <class V> void visit(V& v) {
    v("protocol", protocol, {.doc = "preset; YAML names it (barn2023, barn2024)"});
    // The goal lies 3.4 m past the obstacle field: a larger disc would reach back into it.
    v("success_radius", success_radius,
      {.unit = "m", .range = core::openClosed(0.0, 3.0), .doc = "robot centre to goal at success"});
    v("physics", physics);
    v("robot", robot);
    v("lidar", lidar);
    v("odometry", odometry);
    v("latency", latency);
  }
};

/// The protocol an episode runs: the preset `config.protocol` with the config's success radius.
core::Protocol episodeProtocol(const EpisodeConfig& config);

/// Checks every field and the cross-field rule that scans fall on physics steps.
void validate(const EpisodeConfig& config, core::Errors& errors);

/// Reads and validates an episode config (a sim config file's contents); InputError naming
/// `where` and the field otherwise.
EpisodeConfig validatedEpisodeConfig(const core::ConfigNode& node, const std::string& where);

/// InputError unless a controller acting every `controller_period` seconds acts on physics
/// steps (physics.rate a whole multiple of the controller's rate): a rate that is not would be
/// rounded to another one (30 Hz at 200 Hz physics would run at 28.6 Hz).
void checkControllerPeriod(double controller_period, const EpisodeConfig& config);
/// Everything about `controller` that can be checked before a run: its period (above) and
/// that it can read the configured LiDAR's scans. InputError otherwise.
void checkControllerFits(const controllers::Controller& controller, const EpisodeConfig& config);
/// A warning when the controller drives by a learned policy trained on another plant than
/// `config`'s robot and physics (sim::plantHash): such a policy steers as if the robot
/// moved like the one it learned on. "" when the plants agree or the policy does not say.
std::string plantMismatch(const controllers::Controller& controller, const EpisodeConfig& config);

/// Bounds on a controller's state labels (stateLabel(), an external program's "state", a
/// Python controller's third value), kept by every episode whichever route the controller
/// came by: a label longer than this, or more distinct labels than this in one episode, ends
/// the episode as an error naming the limit, so a controller cannot fill barn's memory or a
/// record with labels. Our choice: the shipped controllers use at most 8 labels of at most 12
/// bytes.
inline constexpr std::size_t kMaxStateLabelBytes = 64;  // [bytes]
inline constexpr std::size_t kMaxStateLabels = 64;      // distinct labels per episode

/// One control tick of the trajectory record (world frame).
struct TrajectorySample {
  double time = 0.0;    // [s]
  core::Pose2 pose;     // world frame
  core::Twist command;  // what the controller returned
  std::string state;    // controller state label
  std::string parameters;  // stack parameters the controller set at this tick (`key=value;...`)
};

struct EpisodeResult {
  int world_id = 0;
  int trial = 0;
  std::uint64_t seed = 0;
  Outcome outcome = Outcome::Error;
  double actual_time = 0.0;    // [s] AT (elapsed at the final check; time of contact for collisions)
  double optimal_time = 0.0;   // [s] OT for the protocol
  double score = 0.0;          // BARN score
  double path_length = 0.0;    // [m] distance driven
  double mean_speed = 0.0;     // [m/s] path_length / simulated time
  double sim_time = 0.0;       // [s] simulated time in total
  std::optional<sim::CollisionInfo> collision;
  std::string error;           // what went wrong, for Outcome::Error
  /// How often the controller entered each state (by stateLabel()), in order of first entry;
  /// empty for controllers without states.
  std::vector<std::pair<std::string, int>> state_entries;
  std::vector<TrajectorySample> trajectory;  // filled when recording
};

/// One episode as a steppable object, for callers that drive the controller themselves
/// (runEpisode, the Python Env, external controllers):
///
///   Episode episode(world, field, config, seed, controller_period);
///   while (!episode.done()) episode.step(my_controller(episode.observation()));
///   EpisodeResult r = episode.result();
///
/// It stops at each control tick: observation() is what a controller sees then (computed once
/// at the tick, so reading it twice draws no extra noise), step() applies a command and runs
/// the physics to the next tick, applying the protocol at physics rate on the way.
class Episode {
 public:
  /// `world` and `field` must outlive the episode. Throws core::InputError if `controller_period` is not
  /// positive.
  Episode(const core::WorldSpec& world, const sim::ObstacleField& field, const EpisodeConfig& config,
          std::uint64_t seed, double controller_period);
  Episode(const Episode&) = delete;
  Episode& operator=(const Episode&) = delete;

  /// What the controller is told before the first tick.
  const controllers::EpisodeInfo& info() const { return info_; }
  /// The world's A* path in the odom frame, for test fixtures only (UsesReferencePath).
  std::vector<Eigen::Vector2d> referencePath() const;
  /// The current tick's observation (its scan points into this episode).
  const controllers::Observation& observation() const { return observation_; }
  /// The true pose (world frame) at the current tick, for trajectory records.
  const core::Pose2& tickPose() const { return tick_pose_; }
  double time() const { return simulator_.time(); }  // [s] simulated

  /// Applies `command` at this tick and advances to the next one (or to the end); `state` is
  /// the controller's state label then (counted in the record; "" for none). A non-finite
  /// command, or a label beyond kMaxStateLabelBytes or kMaxStateLabels, ends the episode as
  /// an error instead.
  void step(const core::Twist& command, std::string_view state = {});
  /// Ends the episode now as an error (the controller failed).
  void fail(const std::string& message);

  bool done() const { return done_; }
  /// The record so far (complete once done()); score 0 until success.
  EpisodeResult result() const;

 private:
  void arriveAtTick();
  void takeScan();         // the LiDAR fires: its pose and time are kept, the cast waits
  void castPendingScan();  // casts the latest scan, once, when a controller is to read it

  core::Protocol protocol_;
  EpisodeConfig config_;
  sim::Simulator simulator_;
  ProtocolMonitor monitor_;  // run.py's rules, asked after every physics step
  sim::LidarCaster lidar_;
  std::uint64_t scan_seed_;  // scan k's noise stream is mixSeed(scan_seed_, k)
  core::FastNoise odometry_noise_;
  std::optional<DriftingOdometry> drifting_;
  core::Pose2 start_;
  Eigen::Vector2d odom_origin_;
  Eigen::Vector2d goal_world_;
  controllers::EpisodeInfo info_;
  const core::WorldSpec* world_;
  long scan_steps_ = 1;
  long control_steps_ = 1;
  long latency_steps_ = 0;
  std::deque<std::pair<long, core::Twist>> in_flight_;  // (step it takes effect, command)
  long step_ = 0;  // physics steps taken
  struct PendingScan {
    core::Pose2 robot_pose;
    core::Pose2 odom_pose;  // the odometry at the capture (what tf gives at the scan's stamp)
    double stamp = 0.0;
    long number = -1;  // 0 for the scan at the start
    bool cast = false;
  };
  PendingScan pending_scan_;
  core::LaserScan scan_;  // the latest scan cast
  controllers::Observation observation_;
  core::Pose2 tick_pose_;
  core::Pose2 odomPose() const;  // the odometry estimate now, before any white noise
  Eigen::Vector2d previous_position_;
  bool done_ = false;
  std::string last_state_;
  EpisodeResult result_;
};

/// Runs one episode with `controller`. `seed` drives the LiDAR noise and the controller's
/// declared randomness, so the same seed gives the same trajectory bit for bit. Never throws
/// for controller failures (they become Outcome::Error).
EpisodeResult runEpisode(const core::WorldSpec& world, const sim::ObstacleField& field,
                         controllers::Controller& controller, const EpisodeConfig& config,
                         std::uint64_t seed, bool record_trajectory = false);

/// The world's A* path cells (at their centres) in the odom frame of `protocol`.
std::vector<Eigen::Vector2d> referencePathInOdom(const core::WorldSpec& world, const core::Protocol& protocol);

}  // namespace barn::bench
