#include "barn/controllers/lflh.hpp"

#include <algorithm>
#include <cmath>
#include <filesystem>

namespace barn::controllers {

nav::NavStackConfig LflhConfig::lflhNav() {
  nav::NavStackConfig c;
  c.footprint_padding = 0.075;
  c.global_costmap.inscribed_radius = 0.24;  // 0.165 + 0.075
  c.global_costmap.inflation_radius = 1.0;
  c.global_costmap.cost_scaling_factor = 3.0;
  c.local_costmap.inscribed_radius = 0.24;
  c.local_costmap.inflation_radius = 1.0;
  c.local_costmap.cost_scaling_factor = 1.0;
  // BARN updates the global costmap at 10 Hz; 5 Hz halves the replanning work (the planner
  // reuses its field between updates) and changes little at these speeds.
  c.global_update_rate = 5.0;
  c.planner.smoothing_window = 9;  // stands in for the Savitzky-Golay smoothing of the original
  return c;
}

void validate(const LflhConfig& c, core::Errors& errors, const std::string& prefix) {
  errors.check(!c.policy.empty(), prefix + ".policy", "must name a policy file");
  errors.check(c.rate > 0.0, prefix + ".rate", "must be > 0");
  errors.check(c.local_goal_distance > 0.0, prefix + ".local_goal_distance", "must be > 0");
  errors.check(c.max_speed > 0.0, prefix + ".max_speed", "must be > 0");
  errors.check(c.max_turn_rate > 0.0, prefix + ".max_turn_rate", "must be > 0");
  nav::validate(c.nav, errors, prefix + ".nav");
}

std::string resolvePolicyPath(const std::string& policy, const std::string& config_source) {
  namespace fs = std::filesystem;
  const fs::path path(policy);
  if (path.is_absolute()) return path.string();
  std::error_code ec;
  const fs::path source(config_source);
  if (!config_source.empty() && fs::is_regular_file(source, ec)) {
    const fs::path beside = source.parent_path() / path;
    if (fs::exists(beside, ec)) return fs::absolute(beside).lexically_normal().string();
  }
  return fs::absolute(path).lexically_normal().string();
}

Eigen::Vector2d localGoalDirection(const nav::Path& path, const core::Pose2& pose, double distance) {
  const Eigen::Vector2d target = nav::pointAlongPath(path, pose.position(), distance);
  const Eigen::Vector2d local = pose.inverseTransform(target);
  return local.norm() > 1e-9 ? Eigen::Vector2d(local.normalized()) : Eigen::Vector2d(1.0, 0.0);
}

LflhController::LflhController(const LflhConfig& config, std::shared_ptr<const learning::Policy> policy)
    : config_(config), policy_(std::move(policy)), nav_(config.nav) {}

void LflhController::reset(const EpisodeInfo& info) {
  info_ = info;
  nav_.reset(info.goal);
}

core::Twist LflhController::act(const Observation& obs) {
  nav_.update(obs.time, *obs.scan, info_.lidar.sensorPose(obs.odom_pose), obs.odom_pose);
  // Until the first plan (and if planning never succeeds) the goal itself is the target.
  const nav::Path path = nav_.hasPath() ? nav_.path() : nav::Path{obs.odom_pose.position(), obs.goal};
  const core::Twist raw = policy_->act(*obs.scan, localGoalDirection(path, obs.odom_pose, config_.local_goal_distance));
  return {std::clamp(raw.linear, -config_.max_speed, config_.max_speed),
          std::clamp(raw.angular, -config_.max_turn_rate, config_.max_turn_rate)};
}

}  // namespace barn::controllers
