#include "barn/controllers/in2bot.hpp"

#include <cmath>
#include <limits>
#include <numbers>

namespace barn::controllers {

FuzzySystemConfig in2botSpeedFuzzy() {
  FuzzySystemConfig c = rrslSpeedFuzzy();
  c.output = {0.0, 0.9 + 0.01, 0.01};  // team: lin_vel_max 0.9
  // team: RRSL's points times scale = 1.25 (exact in binary); Very_High ends at its peak.
  c.rules[0].output = {0.65625, 0.875, 0.875};
  c.rules[1].output = {0.4375, 0.65625, 0.875};
  c.rules[2].output = {0.21875, 0.4375, 0.65625};
  c.rules[3].output = {0.0, 0.21875, 0.4375};
  c.rules[4].output = {-0.21875, 0.0, 0.21875};
  return c;
}

void validate(const In2botConfig& c, core::Errors& errors, const std::string& prefix) {
  core::validateFields(c, errors, prefix);
  validate(c.map, errors, prefix + ".map");
  validate(c.esdf, errors, prefix + ".esdf");
  validate(c.planner, errors, prefix + ".planner");
  validate(c.vfh, errors, prefix + ".vfh");
}

Eigen::Vector2d lookaheadTarget(const std::vector<Eigen::Vector2d>& path, const std::vector<double>& arc_length,
                                const Eigen::Vector2d& robot, std::size_t& nearest, const In2botConfig& config) {
  const Eigen::Vector2d& end = path.back();
  if ((end - robot).norm() <= config.goal_lock_distance) return end;

  const auto window = static_cast<std::size_t>(config.nearest_window);
  const std::size_t first = nearest > window ? nearest - window : 0;
  const std::size_t last = std::min(path.size(), nearest + window + 1);
  double closest = std::numeric_limits<double>::infinity();
  std::size_t best = nearest;
  for (std::size_t i = first; i < last; ++i) {
    const double d = (path[i] - robot).norm();
    if (d < closest) {
      closest = d;
      best = i;
    }
  }
  if (closest > config.nearest_reset) {
    closest = std::numeric_limits<double>::infinity();
    for (std::size_t i = 0; i < path.size(); ++i) {
      const double d = (path[i] - robot).norm();
      if (d < closest) {
        closest = d;
        best = i;
      }
    }
  }
  nearest = best;

  const double wanted = arc_length[best] + config.lookahead;
  if (wanted >= arc_length.back()) return end;
  for (std::size_t i = best; i + 1 < path.size(); ++i) {
    if (arc_length[i + 1] >= wanted) {
      const double segment = arc_length[i + 1] - arc_length[i];
      const double ratio = segment > 0 ? (wanted - arc_length[i]) / segment : 0.0;
      return path[i] + ratio * (path[i + 1] - path[i]);
    }
  }
  return end;
}

std::optional<double> turnInPlaceRate(const core::Pose2& pose, const Eigen::Vector2d& target, double limit_deg,
                                      double rate) {
  constexpr double kDegPerRad = 180.0 / std::numbers::pi;
  const Eigen::Vector2d d = target - pose.position();
  const double diff = std::atan2(d.y(), d.x()) * kDegPerRad - core::wrapAngle(pose.yaw) * kDegPerRad;
  double wrapped = std::fmod(diff + 180.0, 360.0);  // Python's (diff + 180) % 360 - 180
  if (wrapped < 0.0) wrapped += 360.0;
  wrapped -= 180.0;
  if (std::abs(wrapped) <= limit_deg) return std::nullopt;
  return wrapped > 0.0 ? rate : -rate;
}

In2botController::In2botController(const In2botConfig& config)
    : config_(config), vfh_(config.vfh), grid_(config.map) {}

void In2botController::reset(const EpisodeInfo& info) {
  info_ = info;
  vfh_.reset();
  grid_.clear();
  action_ = VfhAction::WaitPath;
  integrated_ = false;
  travelled_ = turned_ = 0.0;
  next_plan_ = 0.0;
  plan_.clear();
  path_.clear();
  arc_length_.clear();
  nearest_ = 0;
}

void In2botController::updateMap(const Observation& obs) {
  if (integrated_) {
    travelled_ += (obs.odom_pose.position() - last_pose_.position()).norm();
    turned_ += std::abs(core::wrapAngle(obs.odom_pose.yaw - last_pose_.yaw));
  }
  last_pose_ = obs.odom_pose;
  if (integrated_ && travelled_ < config_.map.linear_update && turned_ < config_.map.angular_update) return;
  grid_.integrate(*obs.scan, info_.lidar.sensorPose(obs.scan_odom_pose));
  integrated_ = true;
  travelled_ = turned_ = 0.0;
}

void In2botController::replan(const Observation& obs) {
  const std::vector<std::int8_t> costs =
      esdfCosts(grid_.occupancy(), grid_.width(), grid_.height(), grid_.resolution(), config_.esdf);
  if (!plan_.empty() &&
      !pathCollides(plan_, costs, grid_.width(), grid_.height(), grid_.resolution(), config_.planner))
    return;
  plan_ = planGridPath(costs, grid_.width(), grid_.height(), grid_.cellOf(obs.odom_pose.position()),
                       grid_.cellOf(obs.goal), grid_.resolution(), config_.planner);
  if (plan_.empty()) return;  // the local planner keeps the last path it was sent
  // Cell centres, as the team publishes them.
  const double res = grid_.resolution();
  path_.clear();
  arc_length_.clear();
  for (const GridCell& cell : plan_) {
    path_.push_back(grid_.origin() + Eigen::Vector2d(cell.x * res + res / 2, cell.y * res + res / 2));
    arc_length_.push_back(arc_length_.empty() ? 0.0 : arc_length_.back() + (path_.back() - path_[path_.size() - 2]).norm());
  }
  nearest_ = 0;
}

core::Twist In2botController::act(const Observation& obs) {
  // A fuzzy error ends the team's node: no more commands.
  if (action_ == VfhAction::Halted) return {};
  updateMap(obs);
  if (obs.time + 1e-9 >= next_plan_) {
    replan(obs);
    while (next_plan_ <= obs.time + 1e-9) next_plan_ += 1.0 / config_.planner.rate;
  }
  if (path_.empty()) {
    action_ = VfhAction::WaitPath;
    return {};
  }
  const Eigen::Vector2d target = lookaheadTarget(path_, arc_length_, obs.odom_pose.position(), nearest_, config_);
  const VfhStep step = vfh_.step(*obs.scan, obs.odom_pose, target);
  action_ = step.action;
  if (action_ == VfhAction::Halted) return {};
  core::Twist command = step.command;
  if (const auto rate =
          turnInPlaceRate(obs.odom_pose, target, config_.turn_in_place_deg, config_.turn_in_place_rate)) {
    command = {0.0, *rate};
    action_ = VfhAction::TurnInPlace;
  }
  return command;
}

}  // namespace barn::controllers
