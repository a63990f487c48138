#include "barn/bench/episode.hpp"

#include <cmath>
#include <deque>
#include <exception>

#include "barn/core/world_geometry.hpp"

namespace barn::bench {

std::string_view toString(Outcome outcome) {
  switch (outcome) {
    case Outcome::Success: return "success";
    case Outcome::Collision: return "collision";
    case Outcome::Timeout: return "timeout";
    case Outcome::Error: return "error";
  }
  return "unknown";
}

namespace {

// Number of physics steps in `period`, if it is a whole number of steps.
std::optional<long> stepsIn(double period, double dt) {
  const double steps = period / dt;
  const long rounded = std::lround(steps);
  if (rounded < 1 || std::abs(steps - static_cast<double>(rounded)) > 1e-6) return std::nullopt;
  return rounded;
}

// Counts a state entry when the controller's label changes.
void countStateEntry(std::vector<std::pair<std::string, int>>& entries, std::string& last, std::string_view label) {
  if (label.empty() || label == last) return;
  last = label;
  for (auto& [name, count] : entries) {
    if (name == label) {
      ++count;
      return;
    }
  }
  entries.emplace_back(std::string(label), 1);
}

}  // namespace

void validate(const EpisodeConfig& config, core::Errors& errors) {
  try {
    core::protocolPreset(config.protocol);
  } catch (const core::InputError& e) {
    errors.add("protocol", e.what());
  }
  sim::validate(config.physics, errors);
  sim::validate(config.robot, errors);
  sim::validate(config.lidar, errors);
  errors.check(config.odometry.position_stddev >= 0.0, "odometry.position_stddev", "must be >= 0");
  errors.check(config.odometry.yaw_stddev >= 0.0, "odometry.yaw_stddev", "must be >= 0");
  errors.check(config.odometry.speed_stddev >= 0.0, "odometry.speed_stddev", "must be >= 0");
  validate(config.odometry.drift, errors, "odometry.drift");
  errors.check(config.latency.command >= 0.0 && config.latency.command <= 1.0, "latency.command", "must be in [0, 1] s");
  if (config.physics.rate > 0 && config.lidar.rate > 0) {
    errors.check(stepsIn(1.0 / config.lidar.rate, config.physics.dt()).has_value(), "lidar.rate",
                 "the scan period must be a whole number of physics steps (physics.rate / lidar.rate integer)");
    errors.check(stepsIn(0.1, config.physics.dt()).has_value(), "physics.rate",
                 "the 0.1 s status check must be a whole number of physics steps");
  }
}

std::vector<Eigen::Vector2d> referencePathInOdom(const core::WorldSpec& world, const core::Protocol& protocol) {
  std::vector<Eigen::Vector2d> path;
  for (const core::Cell& cell : world.path) {
    const Eigen::Vector2d p = core::cellCentre(cell) - protocol.start();
    if (path.empty() || (path.back() - p).norm() > 1e-12) path.push_back(p);
  }
  return path;
}

EpisodeResult runEpisode(const core::WorldSpec& world, const sim::ObstacleField& field,
                         controllers::Controller& controller, const EpisodeConfig& config, std::uint64_t seed,
                         bool record_trajectory) {
  const core::Protocol protocol = core::protocolPreset(config.protocol);
  EpisodeResult result;
  result.world_id = world.id;
  result.seed = seed;
  result.optimal_time = core::optimalTime(world.path, protocol);

  const core::Pose2 start{protocol.start_x, protocol.start_y, protocol.start_yaw};
  const Eigen::Vector2d odom_origin = protocol.start();  // odom = world shifted to the start
  const Eigen::Vector2d goal_world = protocol.goal();
  sim::Simulator simulator(field, config.robot, config.physics, start, core::mixSeed(seed, 5));
  sim::LidarCaster lidar(config.lidar, field);
  core::FastNoise noise(core::mixSeed(seed, 1));
  core::FastNoise odometry_noise(core::mixSeed(seed, 3));
  const OdometryNoise& odom_sigma = config.odometry;
  std::optional<DriftingOdometry> drifting;
  if (odom_sigma.drift.enabled()) drifting.emplace(odom_sigma.drift, start, core::mixSeed(seed, 4));

  controllers::EpisodeInfo info;
  info.start = {0.0, 0.0, protocol.start_yaw};
  info.goal = goal_world - odom_origin;
  info.goal_tolerance = protocol.success_radius;
  info.seed = core::mixSeed(seed, 2);
  info.lidar = config.lidar;
  info.robot = config.robot;
  info.reference_path = referencePathInOdom(world, protocol);

  const double dt = simulator.dt();
  const long scan_steps = *stepsIn(1.0 / config.lidar.rate, dt);
  const long check_steps = *stepsIn(protocol.check_period, dt);
  const long control_steps = std::max(1L, std::lround(controller.period() / dt));
  const long max_steps = std::lround((protocol.timeout + 1.0) / dt);
  const long latency_steps = std::lround(config.latency.command / dt);
  std::deque<std::pair<long, core::Twist>> in_flight;  // (step it takes effect, command)

  try {
    controller.reset(info);
  } catch (const std::exception& e) {
    result.outcome = Outcome::Error;
    result.error = std::string("controller reset threw: ") + e.what();
    return result;
  }

  core::LaserScan scan;
  std::string last_state;
  std::optional<long> timer_start_step;
  Eigen::Vector2d previous = start.position();
  bool finished = false;
  for (long step = 0; !finished; ++step) {
    const double now = simulator.time();
    if (step % scan_steps == 0) scan = lidar.scan(simulator.pose(), now, &noise);
    if (step % control_steps == 0) {
      const core::Pose2 pose = simulator.pose();
      controllers::Observation obs;
      obs.time = now;
      obs.scan = &scan;
      obs.odom_pose = drifting ? drifting->pose() : core::Pose2{pose.x - odom_origin.x(), pose.y - odom_origin.y(), pose.yaw};
      obs.odom_twist = {simulator.forwardSpeed(), simulator.yawRate()};
      if (odom_sigma.position_stddev > 0.0 || odom_sigma.yaw_stddev > 0.0 || odom_sigma.speed_stddev > 0.0) {
        obs.odom_pose.x += odom_sigma.position_stddev * odometry_noise.normal();
        obs.odom_pose.y += odom_sigma.position_stddev * odometry_noise.normal();
        obs.odom_pose.yaw = core::wrapAngle(obs.odom_pose.yaw + odom_sigma.yaw_stddev * odometry_noise.normal());
        obs.odom_twist.linear += odom_sigma.speed_stddev * odometry_noise.normal();
        obs.odom_twist.angular += odom_sigma.speed_stddev * odometry_noise.normal();
      }
      obs.goal = info.goal;
      core::Twist cmd;
      try {
        cmd = controller.act(obs);
      } catch (const std::exception& e) {
        result.outcome = Outcome::Error;
        result.error = std::string("controller threw: ") + e.what();
        break;
      }
      if (!std::isfinite(cmd.linear) || !std::isfinite(cmd.angular)) {
        result.outcome = Outcome::Error;
        result.error = "controller returned a non-finite command";
        break;
      }
      if (latency_steps == 0) simulator.command(cmd);
      else in_flight.emplace_back(step + latency_steps, cmd);
      countStateEntry(result.state_entries, last_state, controller.stateLabel());
      if (record_trajectory) result.trajectory.push_back({now, pose, cmd, std::string(controller.stateLabel())});
    }

    while (!in_flight.empty() && in_flight.front().first <= step) {
      simulator.command(in_flight.front().second);
      in_flight.pop_front();
    }
    simulator.step();
    const core::Pose2 pose = simulator.pose();
    if (drifting) drifting->update(pose, dt);
    result.path_length += (pose.position() - previous).norm();
    previous = pose.position();

    if (simulator.collision()) {
      result.outcome = Outcome::Collision;
      result.collision = simulator.collision();
      result.actual_time = timer_start_step ? simulator.time() - static_cast<double>(*timer_start_step) * dt : 0.0;
      break;
    }
    if (!timer_start_step) {
      if ((pose.position() - start.position()).norm() >= protocol.start_distance) timer_start_step = step + 1;
      else if (simulator.time() >= protocol.timeout) {
        result.outcome = Outcome::Timeout;  // never left the start
        result.actual_time = protocol.timeout;
        break;
      }
      continue;
    }
    const long since_start = step + 1 - *timer_start_step;
    if (since_start % check_steps != 0) continue;
    // Whole checks since the timer started, so AT is a multiple of the check period; divided
    // by the checks per second (10) so that 189 checks print as 18.9, not 18.900000000000002.
    const double checks = static_cast<double>(since_start / check_steps);
    const double per_second = std::round(1.0 / protocol.check_period);
    const double elapsed = std::abs(per_second * protocol.check_period - 1.0) < 1e-12 ? checks / per_second
                                                                                    : checks * protocol.check_period;
    if (elapsed >= protocol.timeout - 1e-9) {
      result.outcome = Outcome::Timeout;
      result.actual_time = elapsed;
      finished = true;
    } else if ((pose.position() - goal_world).norm() <= protocol.success_radius) {
      result.outcome = Outcome::Success;
      result.actual_time = elapsed;
      finished = true;
    }
    if (since_start > max_steps) {  // cannot happen with the rules above; a guard against a hang
      result.outcome = Outcome::Timeout;
      result.actual_time = elapsed;
      finished = true;
    }
  }
  result.sim_time = simulator.time();
  result.mean_speed = result.sim_time > 0 ? result.path_length / result.sim_time : 0.0;
  result.score = core::barnScore(result.outcome == Outcome::Success, result.actual_time, result.optimal_time, protocol);
  return result;
}

}  // namespace barn::bench
