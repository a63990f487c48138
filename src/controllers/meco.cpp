#include "barn/controllers/meco.hpp"

#include <algorithm>
#include <cmath>
#include <numbers>

namespace barn::controllers {

namespace {

/// Control ticks per cycle of a node running at `node_rate` under a controller at `rate`.
long ticksPer(double rate, double node_rate) { return std::max(1L, std::lround(rate / node_rate)); }

bool wholeMultiple(double rate, double node_rate) {
  const double ratio = rate / node_rate;
  return ratio >= 1.0 - 1e-9 && std::abs(ratio - std::round(ratio)) < 1e-9;
}

// More than any BARN episode lasts; guards the queue against a degenerate manoeuvre.
constexpr double kMaxManoeuvre = 120.0;  // [s]

}  // namespace

void validate(const MecoNavigatorConfig& c, core::Errors& errors, const std::string& prefix) {
  core::validateFields(c, errors, prefix);
}

void validate(const MecoConfig& c, core::Errors& errors, const std::string& prefix) {
  core::validateFields(c, errors, prefix);
  errors.check(std::isfinite(c.stretch_min_speed), prefix + ".stretch_min_speed", "must be finite");
  errors.check(std::isfinite(c.stretch_next_max_speed), prefix + ".stretch_next_max_speed", "must be finite");
  errors.check(std::isfinite(c.turn_stop_speed), prefix + ".turn_stop_speed", "must be finite");
  validate(c.fitter, errors, prefix + ".fitter");
  validate(c.manager, errors, prefix + ".manager");
  validate(c.navigator, errors, prefix + ".navigator");
  // The nodes run on whole numbers of control ticks.
  if (c.rate > 0.0) {
    if (c.fitter.rate > 0.0)
      errors.check(wholeMultiple(c.rate, c.fitter.rate), prefix + ".fitter.rate", "must divide the controller's rate");
    if (c.manager.rate > 0.0)
      errors.check(wholeMultiple(c.rate, c.manager.rate), prefix + ".manager.rate", "must divide the controller's rate");
    if (c.navigator.rate > 0.0)
      errors.check(wholeMultiple(c.rate, c.navigator.rate), prefix + ".navigator.rate",
                   "must divide the controller's rate");
  }
}

MecoPlannerParams plannerParams(const MecoNavigatorConfig& c, double gain) {
  MecoPlannerParams p;
  p.robot_length = c.robot_length;
  p.margin = c.margin;
  p.max_speed = gain * c.max_speed;
  p.max_turn_rate = gain * c.max_turn_rate;
  p.goal_offset = c.goal_offset;
  p.min_radius = c.min_radius;
  p.semi_backtrack_fraction = c.semi_backtrack_fraction;
  return p;
}

// ---------------------------------------------------------------------------------------------
// Navigator

void MecoNavigator::reset() {
  corridors_.clear();
  backtracking_ = backtrack_planned_ = goal_in_sight_ = heading_to_goal_ = false;
}

void MecoNavigator::receive(std::span<const MecoMessage> messages) {
  for (const MecoMessage& message : messages) {
    if (goal_in_sight_ || message.corridors.empty()) continue;
    switch (message.kind) {
      case MecoMessageKind::Next:
        // After a backtrack the route's last corridor is the one the robot is back in.
        if (backtracking_) corridors_ = {corridors_.back()};
        corridors_.push_back(message.corridors.front());
        backtracking_ = backtrack_planned_ = false;
        break;
      case MecoMessageKind::Final:
        corridors_ = {message.corridors.front()};
        goal_in_sight_ = true;
        backtracking_ = backtrack_planned_ = false;
        break;
      case MecoMessageKind::Backtrack:
        corridors_ = message.corridors;
        backtracking_ = true;
        backtrack_planned_ = false;
        break;
    }
  }
}

std::optional<MecoManoeuvre> MecoNavigator::tick(const core::Pose2& pose, const Eigen::Vector2d& goal) {
  if (corridors_.empty()) return std::nullopt;
  if (backtracking_) {
    if (backtrack_planned_) return std::nullopt;
    std::vector<MecoCorridor> turned;
    for (const MecoCorridor& c : corridors_) turned.push_back(c.reversed());
    const Eigen::Vector2d target = corridors_.back().frontPoint(config_.margin);
    const core::Pose2 reversed{pose.x, pose.y, core::wrapAngle(pose.yaw + std::numbers::pi)};
    MecoManoeuvre m = planSequence(turned, reversed, plannerParams(config_, config_.backtrack_gain), target);
    for (MecoSegment& s : m.segments) s.linear = -s.linear;
    backtrack_planned_ = true;
    return m;
  }
  const MecoCorridor first = corridors_[0];
  const std::optional<MecoCorridor> second =
      corridors_.size() > 1 ? std::optional<MecoCorridor>(corridors_[1]) : std::nullopt;
  const Eigen::Vector2d robot = pose.position();
  if (second && second->contains(robot, config_.inside_tolerance)) corridors_.erase(corridors_.begin());
  const MecoPlannerParams params = plannerParams(config_);
  const MecoCorridor* next = second ? &*second : nullptr;
  if (!first.contains(goal, config_.inside_tolerance)) return plan(first, next, pose, params);

  const auto to_goal = [&] {
    MecoManoeuvre m = plan(first, next, pose, params, goal);
    if (!m.segments.empty()) m.segments.back().linear = config_.final_speed;
    heading_to_goal_ = true;
    return m;
  };
  if (goal_in_sight_ && !heading_to_goal_) return to_goal();
  const double distance = (goal - robot).norm();
  const double threshold =
      std::abs(std::atan((0.5 * first.width - 0.5 * config_.robot_length - config_.margin) / distance));
  const double bearing = std::atan2(goal.y() - robot.y(), goal.x() - robot.x());
  if (std::abs(core::wrapAngle(pose.yaw - bearing)) >= threshold) return to_goal();
  return std::nullopt;
}

// ---------------------------------------------------------------------------------------------
// Controller

void stretchFirstSegment(std::vector<MecoSegment>& segments, const MecoConfig& c) {
  if (segments.size() < 2) return;
  MecoSegment& first = segments.front();
  if (first.duration < c.stretch_duration && first.linear >= c.stretch_min_speed &&
      segments[1].linear <= c.stretch_next_max_speed)
    first.duration = c.stretch_duration;
}

std::vector<core::Twist> expandSegments(std::span<const MecoSegment> segments, double rate) {
  std::vector<core::Twist> commands;
  const auto limit = static_cast<std::size_t>(kMaxManoeuvre * rate);
  for (const MecoSegment& s : segments) {
    if (!(s.duration >= 0.0)) continue;
    const auto repetitions = static_cast<std::size_t>(std::min(s.duration * rate, kMaxManoeuvre * rate));
    for (std::size_t k = 0; k < repetitions && commands.size() < limit; ++k) commands.push_back({s.linear, s.angular});
  }
  return commands;
}

core::Twist filterCommand(const core::Twist& previous, const core::Twist& target, const MecoConfig& c) {
  core::Twist out;
  out.linear = c.filter_gain * target.linear + (1.0 - c.filter_gain) * previous.linear;
  out.angular = c.filter_gain * target.angular + (1.0 - c.filter_gain) * previous.angular;
  if (std::abs(out.angular) > c.turn_stop_rate && out.linear < c.turn_stop_speed) out.linear = 0.0;
  return out;
}

MecoController::MecoController(const MecoConfig& config)
    : config_(config),
      manager_(config.manager),
      navigator_(config.navigator),
      fitter_every_(ticksPer(config.rate, config.fitter.rate)),
      manager_every_(ticksPer(config.rate, config.manager.rate)),
      navigator_every_(ticksPer(config.rate, config.navigator.rate)) {}

void MecoController::reset(const EpisodeInfo& info) {
  info_ = info;
  manager_.reset();
  navigator_.reset();
  tick_ = 0;
  queue_.clear();
  next_ = 0;
  last_ = {};
}

core::Twist MecoController::act(const Observation& obs) {
  if (tick_ % fitter_every_ == 0)
    manager_.receive(fitCorridors(*obs.scan, info_.lidar, obs.scan_odom_pose, obs.goal, config_.fitter));
  if (tick_ % manager_every_ == 0) {
    const std::vector<MecoMessage> messages = manager_.tick(obs.time, obs.odom_pose.position(), obs.goal);
    navigator_.receive(messages);
  }
  if (tick_ % navigator_every_ == 0) {
    if (std::optional<MecoManoeuvre> m = navigator_.tick(obs.odom_pose, obs.goal)) {
      stretchFirstSegment(m->segments, config_);
      queue_ = expandSegments(m->segments, config_.rate);
      next_ = 0;
    }
  }
  const core::Twist target = next_ < queue_.size() ? queue_[next_++] : core::Twist{};
  last_ = filterCommand(last_, target, config_);
  ++tick_;
  return last_;
}

}  // namespace barn::controllers
