#include "barn/controllers/inventec.hpp"

#include <algorithm>
#include <cmath>
#include <numbers>

namespace barn::controllers {

namespace {
double degrees(double d) { return d * std::numbers::pi / 180.0; }
}  // namespace

std::string_view toString(InventecState state) {
  switch (state) {
    case InventecState::Initial: return "Initial";
    case InventecState::Heading: return "Heading";
    case InventecState::Lflh: return "LfLH";
    case InventecState::Backtrack: return "Backtrack";
    case InventecState::Forward: return "Forward";
  }
  return "";
}

void validate(const InventecConfig& c, core::Errors& errors, const std::string& prefix) {
  errors.check(!c.policy.empty(), prefix + ".policy", "must name a policy file");
  errors.check(c.rate > 0.0, prefix + ".rate", "must be > 0");
  errors.check(c.max_speed > 0.0, prefix + ".max_speed", "must be > 0");
  errors.check(c.max_turn_rate > 0.0, prefix + ".max_turn_rate", "must be > 0");
  errors.check(c.local_goal_distance > 0.0, prefix + ".local_goal_distance", "must be > 0");
  errors.check(c.path_direction_distance > 0.0, prefix + ".path_direction_distance", "must be > 0");
  errors.check(c.heading_tolerance_deg > 0.0 && c.heading_tolerance_deg <= c.heading_limit_deg,
               prefix + ".heading_tolerance_deg", "must be in (0, heading_limit_deg]");
  errors.check(c.heading_limit_deg <= 180.0, prefix + ".heading_limit_deg", "must be <= 180");
  errors.check(c.heading_gain > 0.0, prefix + ".heading_gain", "must be > 0");
  errors.check(c.min_turn_rate >= 0.0, prefix + ".min_turn_rate", "must be >= 0");
  errors.check(c.footprint_length > 0.0 && c.footprint_width > 0.0, prefix + ".footprint_length", "the footprint must be > 0");
  errors.check(c.safety.type == "fi" || c.safety.type == "mpc" || c.safety.type == "none", prefix + ".safety.type",
               "must be fi, mpc or none");
  errors.check(c.safety.fi_offset >= 0.0, prefix + ".safety.fi_offset", "must be >= 0");
  errors.check(c.safety.mpc_steps >= 1, prefix + ".safety.mpc_steps", "must be >= 1");
  errors.check(c.safety.mpc_dt > 0.0, prefix + ".safety.mpc_dt", "must be > 0");
  errors.check(c.roi_depth > 0.0, prefix + ".roi_depth", "must be > 0");
  errors.check(c.backtrack_distance > 0.0, prefix + ".backtrack_distance", "must be > 0");
  errors.check(c.backtrack_speed > 0.0, prefix + ".backtrack_speed", "must be > 0");
  errors.check(c.align_tolerance_deg > 0.0, prefix + ".align_tolerance_deg", "must be > 0");
  errors.check(c.forward_speed > 0.0, prefix + ".forward_speed", "must be > 0");
  errors.check(c.forward_duration > 0.0, prefix + ".forward_duration", "must be > 0");
  nav::validate(c.nav, errors, prefix + ".nav");
}

InventecState nextInventecState(InventecState state, const InventecInputs& in, const InventecConfig& config) {
  switch (state) {
    case InventecState::Initial:
      return in.has_path ? InventecState::Heading : InventecState::Initial;
    case InventecState::Heading:
      if (in.rotation_unsafe) return InventecState::Backtrack;
      if (std::abs(in.heading_error) <= degrees(config.heading_tolerance_deg)) return InventecState::Lflh;
      return InventecState::Heading;
    case InventecState::Lflh:
      if (in.command_unsafe) return InventecState::Backtrack;
      if (std::abs(in.heading_error) > degrees(config.heading_limit_deg)) return InventecState::Heading;
      return InventecState::Lflh;
    case InventecState::Backtrack:
      if (in.rear_blocked) return InventecState::Forward;
      if (in.backtrack_done) return InventecState::Heading;
      return InventecState::Backtrack;
    case InventecState::Forward:
      if (in.forward_unsafe) return InventecState::Backtrack;
      if (in.forward_done) return InventecState::Heading;
      return InventecState::Forward;
  }
  return state;
}

InventecController::InventecController(const InventecConfig& config, std::shared_ptr<const learning::Policy> policy)
    : config_(config), policy_(std::move(policy)), nav_(config.nav),
      footprint_(footprintBox(config.footprint_length, config.footprint_width, 0.0)) {}

void InventecController::reset(const EpisodeInfo& info) {
  info_ = info;
  nav_.reset(info.goal);
  state_ = InventecState::Initial;
  breadcrumbs_.clear();
  has_backtrack_target_ = false;
  aligned_ = false;
}

core::Twist InventecController::turnToward(double error) const {
  double w = std::clamp(config_.heading_gain * error, -config_.max_turn_rate, config_.max_turn_rate);
  if (std::abs(w) < config_.min_turn_rate) w = std::copysign(config_.min_turn_rate, error);
  return {0.0, w};
}

bool InventecController::commandUnsafe(const std::vector<Eigen::Vector2d>& points, const core::Twist& command) const {
  const InventecSafetyConfig& s = config_.safety;
  if (s.type == "fi") {
    // The static check of the paper's simulation entry: nothing inside the grown rectangle.
    return footprintInflationHit(points, footprintBox(config_.footprint_length, config_.footprint_width, s.fi_offset));
  }
  if (s.type == "mpc") {
    return rolloutHit(points, footprintBox(config_.footprint_length, config_.footprint_width, s.mpc_offset), command,
                      s.mpc_dt, s.mpc_steps);
  }
  return false;
}

void InventecController::enter(InventecState state, const core::Pose2& pose, double time) {
  if (state == InventecState::Backtrack) {
    // The breadcrumb: walking the driven path backwards, the first point at least
    // backtrack_distance away that lies behind the robot (the robot is within 60 degrees of
    // straight ahead of it, seen along the robot's heading). The path is cut there.
    has_backtrack_target_ = false;
    aligned_ = false;
    const Eigen::Vector2d heading(std::cos(pose.yaw), std::sin(pose.yaw));
    for (std::size_t k = breadcrumbs_.size(); k-- > 0;) {
      const Eigen::Vector2d away = pose.position() - breadcrumbs_[k];
      if (away.norm() < config_.backtrack_distance) continue;
      if (away.normalized().dot(heading) < std::cos(degrees(60.0))) continue;
      backtrack_target_ = breadcrumbs_[k];
      has_backtrack_target_ = true;
      breadcrumbs_.resize(k);
      break;
    }
  }
  if (state == InventecState::Forward) forward_started_ = time;
  state_ = state;
}

core::Twist InventecController::act(const Observation& obs) {
  const core::Pose2 pose = obs.odom_pose;
  nav_.update(obs.time, *obs.scan, sensorPose(pose, info_.lidar), pose);
  const std::vector<Eigen::Vector2d> points = scanPoints(*obs.scan, info_.lidar);

  InventecInputs in;
  in.has_path = nav_.hasPath();
  in.heading_error = in.has_path ? nav::headingError(nav_.path(), pose, config_.path_direction_distance) : 0.0;

  // The checks of the current state, then at most one transition per tick.
  core::Twist policy_command;
  switch (state_) {
    case InventecState::Initial:
      break;
    case InventecState::Heading:
      in.rotation_unsafe = config_.safety.type != "none" &&
                           rolloutHit(points, footprint_, turnToward(in.heading_error), config_.safety.mpc_dt,
                                      config_.safety.mpc_steps);
      break;
    case InventecState::Lflh: {
      const core::Twist raw =
          policy_->act(*obs.scan, localGoalDirection(nav_.path(), pose, config_.local_goal_distance));
      policy_command = {std::clamp(raw.linear, -config_.max_speed, config_.max_speed),
                        std::clamp(raw.angular, -config_.max_turn_rate, config_.max_turn_rate)};
      in.command_unsafe = commandUnsafe(points, policy_command);
      break;
    }
    case InventecState::Backtrack:
      in.backtrack_done = !has_backtrack_target_ || (pose.position() - backtrack_target_).norm() < 0.05 ||
                          (aligned_ && pose.inverseTransform(backtrack_target_).x() >= 0.0);
      in.rear_blocked = aligned_ && config_.backtrack_roi &&
                        rearRegionBlocked(nav_.localCostmap(), pose, footprint_, config_.roi_depth);
      break;
    case InventecState::Forward: {
      const core::Twist nudge{config_.forward_speed, std::copysign(config_.forward_turn_rate, in.heading_error)};
      in.forward_unsafe = commandUnsafe(points, nudge) && config_.safety.type != "none";
      in.forward_done = obs.time - forward_started_ >= config_.forward_duration - 1e-9;
      break;
    }
  }
  const InventecState next = nextInventecState(state_, in, config_);
  if (next != state_) {
    enter(next, pose, obs.time);
    return {};  // every transition stops the robot for one tick, as the original publishes (0, 0)
  }

  switch (state_) {
    case InventecState::Initial:
      return {};
    case InventecState::Heading:
      return turnToward(in.heading_error);
    case InventecState::Lflh:
      if (breadcrumbs_.empty() || (breadcrumbs_.back() - pose.position()).norm() >= 0.05)
        breadcrumbs_.push_back(pose.position());
      return policy_command;
    case InventecState::Backtrack: {
      if (!aligned_) {
        // Turn the rear toward the target, then reverse straight.
        const Eigen::Vector2d away = pose.position() - backtrack_target_;
        const double error = core::wrapAngle(std::atan2(away.y(), away.x()) - pose.yaw);
        const core::Twist turn = turnToward(error);
        const bool blocked = config_.safety.type != "none" &&
                             rolloutHit(points, footprint_, turn, config_.safety.mpc_dt, config_.safety.mpc_steps);
        if (std::abs(error) > degrees(config_.align_tolerance_deg) && !blocked) return turn;
        aligned_ = true;
      }
      return {-config_.backtrack_speed, 0.0};
    }
    case InventecState::Forward:
      return {config_.forward_speed, std::copysign(config_.forward_turn_rate, in.heading_error)};
  }
  return {};
}

}  // namespace barn::controllers
