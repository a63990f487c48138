#include "barn/bench/episode.hpp"

#include <cmath>
#include <cstdio>
#include <exception>

#include "barn/core/text_io.hpp"
#include "barn/core/world_geometry.hpp"
#include "barn/sim/simulator.hpp"

namespace barn::bench {

namespace {

// The episode seed's independent streams, one per consumer. The numbers are part of every
// record (changing one changes the episodes), so they are fixed here, once.
enum class EpisodeStream : std::uint64_t {
  ScanNoise = 1,      // the LiDAR's noise: scan k draws from mixSeed(this stream, k)
  Controller = 2,     // the controller's own randomness (EpisodeInfo::seed)
  OdometryNoise = 3,  // white noise on the odometry
  OdometryDrift = 4,  // the per-episode wheel-scale, turn-rate and gyro-bias errors
  TurnSlip = 5,       // the simulator's random turn slip
};

std::uint64_t streamSeed(std::uint64_t episode_seed, EpisodeStream stream) {
  return core::mixSeed(episode_seed, static_cast<std::uint64_t>(stream));
}

std::optional<long> stepsIn(double period, double dt) { return wholeStepsIn(period, dt); }

// Counts a state entry when the controller's label changes; the error if the label breaks
// a bound (kMaxStateLabelBytes, kMaxStateLabels), else "".
std::string countStateEntry(std::vector<std::pair<std::string, int>>& entries, std::string& last, std::string_view label) {
  if (label.empty() || label == last) return {};
  if (label.size() > kMaxStateLabelBytes)
    return "controller state label of " + std::to_string(label.size()) + " bytes (the limit is " +
           std::to_string(kMaxStateLabelBytes) + " bytes)";
  last = label;
  for (auto& [name, count] : entries) {
    if (name == label) {
      ++count;
      return {};
    }
  }
  if (entries.size() >= kMaxStateLabels)
    return "controller used more than " + std::to_string(kMaxStateLabels) + " distinct state labels in one episode (the limit)";
  entries.emplace_back(std::string(label), 1);
  return {};
}

}  // namespace

core::Protocol episodeProtocol(const EpisodeConfig& config) {
  core::Protocol protocol = core::protocolPreset(config.protocol);
  protocol.success_radius = config.success_radius;
  return protocol;
}

void validate(const EpisodeConfig& config, core::Errors& errors) {
  // protocol needs no check: reading the config resolved its name (or named the field).
  core::validateFields(config, errors, "");
  sim::validate(config.physics, errors);
  core::validate(config.robot, errors);
  core::validate(config.lidar, errors);
  core::validateFields(config.odometry, errors, "odometry");
  validate(config.odometry.drift, errors, "odometry.drift");
  core::validateFields(config.latency, errors, "latency");
  if (config.physics.rate > 0 && config.lidar.rate > 0) {
    errors.check(stepsIn(1.0 / config.lidar.rate, config.physics.dt()).has_value(), "lidar.rate",
                 "the scan period must be a whole number of physics steps (physics.rate / lidar.rate integer)");
    errors.check(stepsIn(0.1, config.physics.dt()).has_value(), "physics.rate",
                 "the 0.1 s status check must be a whole number of physics steps");
  }
}

EpisodeConfig validatedEpisodeConfig(const core::ConfigNode& node, const std::string& where) {
  EpisodeConfig config = core::readConfig<EpisodeConfig>(node);
  core::Errors errors(where);
  validate(config, errors);
  errors.throwIfAny();
  return config;
}

std::vector<Eigen::Vector2d> referencePathInOdom(const core::WorldSpec& world, const core::Protocol& protocol) {
  std::vector<Eigen::Vector2d> path;
  for (const core::Cell& cell : world.path) {
    const Eigen::Vector2d p = core::cellCentre(cell) - protocol.start();
    if (path.empty() || (path.back() - p).norm() > 1e-12) path.push_back(p);
  }
  return path;
}

void checkControllerPeriod(double controller_period, const EpisodeConfig& config) {
  if (!(controller_period > 0.0) || !std::isfinite(controller_period))
    throw core::InputError("controller period must be a positive number of seconds");
  if (!stepsIn(controller_period, config.physics.dt())) {
    char message[192];
    std::snprintf(message, sizeof(message),
                  "controller rate %g Hz: not a whole number of physics steps (physics.rate %g Hz); choose a rate "
                  "that divides it",
                  1.0 / controller_period, config.physics.rate);
    throw core::InputError(message);
  }
}

void checkControllerFits(const controllers::Controller& controller, const EpisodeConfig& config) {
  checkControllerPeriod(controller.period(), config);
  controller.checkLidar(config.lidar);
}

std::string plantMismatch(const controllers::Controller& controller, const EpisodeConfig& config) {
  const std::uint64_t trained = controller.trainedPlant();
  const std::uint64_t running = sim::plantHash(config.robot, config.physics);
  if (trained == 0 || trained == running) return {};
  return "its policy was trained on another plant (plant_hash " + core::formatHex(trained) +
         ") than this run's robot and physics (" + core::formatHex(running) +
         "), so it steers as if the robot moved like that one; train one on this plant with "
         "`barn lflh collect --sim-config` and `barn lflh train`";
}

Episode::Episode(const core::WorldSpec& world, const sim::ObstacleField& field, const EpisodeConfig& config,
                 std::uint64_t seed, double controller_period)
    : protocol_(episodeProtocol(config)),
      config_(config),
      simulator_(field, config.robot, config.physics, core::Pose2{protocol_.start_x, protocol_.start_y, protocol_.start_yaw},
                 streamSeed(seed, EpisodeStream::TurnSlip)),
      monitor_(protocol_, simulator_.dt()),
      lidar_(config.lidar, field),
      scan_seed_(streamSeed(seed, EpisodeStream::ScanNoise)),
      odometry_noise_(streamSeed(seed, EpisodeStream::OdometryNoise)) {
  checkControllerPeriod(controller_period, config);
  start_ = {protocol_.start_x, protocol_.start_y, protocol_.start_yaw};
  odom_origin_ = protocol_.start();  // odom = world shifted to the start
  goal_world_ = protocol_.goal();
  if (config.odometry.drift.enabled()) drifting_.emplace(config.odometry.drift, start_, streamSeed(seed, EpisodeStream::OdometryDrift));
  result_.world_id = world.id;
  result_.seed = seed;
  result_.optimal_time = core::optimalTime(world.path, protocol_);

  info_.start = {0.0, 0.0, protocol_.start_yaw};
  info_.goal = goal_world_ - odom_origin_;
  info_.goal_tolerance = protocol_.success_radius;
  info_.seed = streamSeed(seed, EpisodeStream::Controller);
  info_.lidar = config.lidar;
  info_.robot = config.robot;
  world_ = &world;

  const double dt = simulator_.dt();
  scan_steps_ = *stepsIn(1.0 / config.lidar.rate, dt);
  control_steps_ = *stepsIn(controller_period, dt);
  latency_steps_ = std::lround(config.latency.command / dt);
  previous_position_ = start_.position();
  takeScan();
  arriveAtTick();
}

std::vector<Eigen::Vector2d> Episode::referencePath() const { return referencePathInOdom(*world_, protocol_); }

core::Pose2 Episode::odomPose() const {
  const core::Pose2 pose = simulator_.pose();
  return drifting_ ? drifting_->pose() : core::Pose2{pose.x - odom_origin_.x(), pose.y - odom_origin_.y(), pose.yaw};
}

void Episode::takeScan() {
  pending_scan_ = {simulator_.pose(), odomPose(), simulator_.time(), pending_scan_.number + 1, false};
}

void Episode::castPendingScan() {
  if (pending_scan_.cast) return;
  // Each scan's noise has its own stream, keyed by the scan's number: casting only the scans a
  // controller reads (at most every other one at 50 Hz) draws the same noise as casting all.
  core::FastNoise noise(core::mixSeed(scan_seed_, static_cast<std::uint64_t>(pending_scan_.number)));
  scan_ = lidar_.scan(pending_scan_.robot_pose, pending_scan_.stamp, &noise);
  pending_scan_.cast = true;
}

void Episode::arriveAtTick() {
  castPendingScan();
  const core::Pose2 pose = simulator_.pose();
  const OdometryNoise& sigma = config_.odometry;
  controllers::Observation& obs = observation_;
  obs.time = simulator_.time();
  obs.scan = &scan_;
  obs.odom_pose = odomPose();
  obs.scan_odom_pose = pending_scan_.odom_pose;
  obs.odom_twist = {simulator_.forwardSpeed(), simulator_.yawRate()};
  if (sigma.position_stddev > 0.0 || sigma.yaw_stddev > 0.0 || sigma.speed_stddev > 0.0) {
    obs.odom_pose.x += sigma.position_stddev * odometry_noise_.normal();
    obs.odom_pose.y += sigma.position_stddev * odometry_noise_.normal();
    obs.odom_pose.yaw = core::wrapAngle(obs.odom_pose.yaw + sigma.yaw_stddev * odometry_noise_.normal());
    obs.odom_twist.linear += sigma.speed_stddev * odometry_noise_.normal();
    obs.odom_twist.angular += sigma.speed_stddev * odometry_noise_.normal();
  }
  obs.goal = info_.goal;
  tick_pose_ = pose;
}

void Episode::fail(const std::string& message) {
  if (done_) return;
  result_.outcome = Outcome::Error;
  result_.error = message;
  done_ = true;
}

void Episode::step(const core::Twist& command, std::string_view state) {
  if (done_) return;
  if (!std::isfinite(command.linear) || !std::isfinite(command.angular)) {
    fail("controller returned a non-finite command");
    return;
  }
  if (const std::string error = countStateEntry(result_.state_entries, last_state_, state); !error.empty()) {
    fail(error);
    return;
  }
  if (latency_steps_ == 0) simulator_.command(command);
  else in_flight_.emplace_back(step_ + latency_steps_, command);
  const double dt = simulator_.dt();
  // Physics steps up to the next control tick: the commands due, a step, the odometry and
  // path length, then the benchmark's rules (ProtocolMonitor).
  for (;;) {
    while (!in_flight_.empty() && in_flight_.front().first <= step_) {
      simulator_.command(in_flight_.front().second);
      in_flight_.pop_front();
    }
    simulator_.step();
    ++step_;
    const core::Pose2 pose = simulator_.pose();
    if (drifting_) drifting_->update(pose, dt);
    result_.path_length += (pose.position() - previous_position_).norm();
    previous_position_ = pose.position();

    if (const std::optional<Outcome> outcome =
            monitor_.afterPhysicsStep(simulator_.time(), pose.position(), simulator_.collision().has_value())) {
      result_.outcome = *outcome;
      result_.actual_time = monitor_.actualTime();
      if (*outcome == Outcome::Collision) result_.collision = simulator_.collision();
      done_ = true;
      return;
    }
    if (step_ % scan_steps_ == 0) takeScan();
    if (step_ % control_steps_ == 0) {
      arriveAtTick();
      return;
    }
  }
}

EpisodeResult Episode::result() const {
  EpisodeResult r = result_;
  r.sim_time = simulator_.time();
  r.mean_speed = r.sim_time > 0 ? r.path_length / r.sim_time : 0.0;
  r.score = core::barnScore(r.outcome == Outcome::Success, r.actual_time, r.optimal_time, protocol_);
  return r;
}

EpisodeResult runEpisode(const core::WorldSpec& world, const sim::ObstacleField& field,
                         controllers::Controller& controller, const EpisodeConfig& config, std::uint64_t seed,
                         bool record_trajectory) {
  Episode episode(world, field, config, seed, controller.period());
  std::vector<TrajectorySample> trajectory;
  try {
    if (auto* fixture = dynamic_cast<controllers::UsesReferencePath*>(&controller)) fixture->setReferencePath(episode.referencePath());
    controller.reset(episode.info());
  } catch (const std::exception& e) {
    episode.fail(std::string("controller reset threw: ") + e.what());
  }
  while (!episode.done()) {
    core::Twist command;
    try {
      command = controller.act(episode.observation());
    } catch (const std::exception& e) {
      episode.fail(std::string("controller threw: ") + e.what());
      break;
    }
    const std::string_view state = controller.stateLabel();
    // A label beyond the bound ends the episode in step(); the trajectory keeps it cut to the bound.
    if (record_trajectory && std::isfinite(command.linear) && std::isfinite(command.angular))
      trajectory.push_back({episode.observation().time, episode.tickPose(), command,
                            std::string(state.substr(0, kMaxStateLabelBytes)), std::string(controller.parameterChanges())});
    episode.step(command, state);
  }
  EpisodeResult result = episode.result();
  result.trajectory = std::move(trajectory);
  return result;
}

}  // namespace barn::bench
