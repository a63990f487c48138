#include "barn/controllers/ut_amrl.hpp"

#include <algorithm>
#include <cmath>
#include <numbers>

namespace barn::controllers {

void validate(const UtAmrlConfig& c, core::Errors& errors, const std::string& prefix) {
  core::validateFields(c, errors, prefix);
  const GraphNavConfig& n = c.navigation;
  const std::string nav = prefix + ".navigation";
  core::validateFields(n, errors, nav);
  if (n.rate > 0.0) {
    const double ticks = c.plan_period * n.rate;
    errors.check(c.plan_period > 0.0 && std::abs(ticks - std::round(ticks)) < 1e-6 && std::round(ticks) >= 1.0,
                 prefix + ".plan_period", "must be a whole number (>= 1) of control periods (1 / navigation.rate)");
  }
  validate(c.voronoi, errors, prefix + ".voronoi");
  validate(n.arcs, errors, nav + ".arcs");
}

std::span<const std::string_view> enumNames(UtAmrlState) {
  static constexpr std::array<std::string_view, 6> kNames = {"Idle", "Arcs", "TurnInPlace", "NoArc", "FaceGoal", "Stopped"};
  return kNames;
}

std::optional<Eigen::Vector2d> shiftedLocalGoal(std::span<const Eigen::Vector2d> path, const Eigen::Vector2d& robot,
                                                double distance) {
  if (path.empty()) return std::nullopt;
  const Eigen::Vector2d shift = robot - path.front();
  for (const Eigen::Vector2d& p : path)
    if ((p + shift - robot).norm() > distance) return p + shift;
  return std::nullopt;
}

std::optional<Eigen::Vector2d> carrotOnPlan(const Eigen::Vector2d& plan_start, const Eigen::Vector2d& goal,
                                            const Eigen::Vector2d& robot, double carrot_dist) {
  if ((goal - robot).squaredNorm() < carrot_dist * carrot_dist) return goal;
  // |start + t (goal - start) - robot| = carrot_dist for t in [0, 1]; the larger t is nearer the goal.
  const Eigen::Vector2d d = goal - plan_start;
  const Eigen::Vector2d f = plan_start - robot;
  const double a = d.squaredNorm();
  const double b = 2.0 * f.dot(d);
  const double c = f.squaredNorm() - carrot_dist * carrot_dist;
  const double disc = b * b - 4.0 * a * c;
  if (a <= 0.0 || disc < 0.0) return std::nullopt;
  const double root = std::sqrt(disc);
  for (const double t : {(-b + root) / (2.0 * a), (-b - root) / (2.0 * a)})
    if (t >= 0.0 && t <= 1.0) return Eigen::Vector2d(plan_start + t * d);
  return std::nullopt;
}

UtAmrlController::UtAmrlController(const UtAmrlConfig& config) : config_(config), planner_(config.voronoi) {
  plan_every_ = std::max(1, static_cast<int>(std::lround(config_.plan_period * config_.navigation.rate)));
}

void UtAmrlController::reset(const EpisodeInfo& info) {
  info_ = info;
  planner_.reset();
  tick_ = 0;
  local_goal_.reset();
  // The team's local goals are path poses with the identity orientation in their odom frame,
  // which starts at the robot's first pose: the heading the robot started with.
  goal_heading_ = info.start.yaw;
  plan_start_.reset();
  state_ = NavState::Stopped;
  action_ = UtAmrlState::Idle;
  history_.clear();
  points_.clear();
}

std::string_view UtAmrlController::stateLabel() const { return core::enumName(action_); }

core::Twist UtAmrlController::act(const Observation& obs) {
  if (tick_++ % plan_every_ == 0 &&
      planner_.plan(*obs.scan, obs.scan_odom_pose, info_.lidar.sensorPose(obs.scan_odom_pose))) {
    const std::optional<Eigen::Vector2d> goal =
        shiftedLocalGoal(planner_.pathMetres(), obs.odom_pose.position(), config_.local_goal_distance);
    if (goal) {
      // graph_navigation's SetNavGoal: head for it, its old plan forgotten.
      local_goal_ = goal;
      state_ = NavState::Goto;
      plan_start_.reset();
    }
  }
  const ArcCommand command = navigate(obs);
  history_.push_back({obs.time + config_.navigation.system_latency, command.linear, command.angular});
  return {command.linear, command.angular};
}

void UtAmrlController::predictPoints(const Observation& obs) {
  const GraphNavConfig& n = config_.navigation;
  const double dt = 1.0 / n.rate;
  const double t_scan = obs.scan->stamp;
  const double horizon = obs.time + n.system_latency;
  // Commands that acted before the older of the scan and the odometry (less a period) are
  // forgotten; the last one sent always stays.
  const double forget_before = std::min(t_scan, obs.time) - dt;
  while (history_.size() > 1 && history_.front().acts_at < forget_before) history_.pop_front();
  // The scan moved back by the motion of the commands that act within a period of its stamp.
  double yaw = 0.0;
  Eigen::Vector2d shift = Eigen::Vector2d::Zero();
  for (const SentCommand& c : history_) {
    if (c.acts_at > horizon || t_scan < c.acts_at - dt) continue;
    const double span = t_scan > c.acts_at ? std::min(t_scan - c.acts_at, dt) : std::min(horizon - c.acts_at, dt);
    const double turn = -c.angular * span;
    const double cs = std::cos(turn), sn = std::sin(turn);
    shift = Eigen::Vector2d(cs * shift.x() - sn * shift.y() - span * c.linear, sn * shift.x() + cs * shift.y());
    yaw += turn;
  }
  const double cs = std::cos(yaw), sn = std::sin(yaw);
  const core::LaserScan& scan = *obs.scan;
  points_.clear();
  if (!n.see_obstacles) return;
  for (std::size_t i = 0; i < scan.ranges.size(); ++i) {
    const double r = scan.ranges[i];
    if (!std::isfinite(r) || r < scan.range_min) continue;
    const double a = scan.angle(i);
    const Eigen::Vector2d p(n.laser_x + r * std::cos(a), r * std::sin(a));
    points_.emplace_back(cs * p.x() - sn * p.y() + shift.x(), sn * p.x() + cs * p.y() + shift.y());
  }
}

ArcCommand UtAmrlController::navigate(const Observation& obs) {
  const GraphNavConfig& n = config_.navigation;
  const double dt = 1.0 / n.rate;
  // graph_navigation takes the last command as the robot's velocity.
  const double speed = history_.empty() ? 0.0 : history_.back().linear;
  const double yaw_rate = history_.empty() ? 0.0 : history_.back().angular;
  predictPoints(obs);
  const Eigen::Vector2d robot = obs.odom_pose.position();
  const double yaw = obs.odom_pose.yaw;

  Eigen::Vector2d local_target = Eigen::Vector2d::Zero();
  if (state_ == NavState::Goto) {
    // The plan is a straight line from where the robot was to the local goal (an empty map);
    // it is made again when the robot strays max_plan_deviation from it.
    const Eigen::Vector2d& goal = *local_goal_;
    if (plan_start_) {
      const Eigen::Vector2d d = goal - *plan_start_;
      const double t = d.squaredNorm() > 0.0 ? std::clamp((robot - *plan_start_).dot(d) / d.squaredNorm(), 0.0, 1.0) : 0.0;
      if ((*plan_start_ + t * d - robot).norm() >= n.max_plan_deviation) plan_start_.reset();
    }
    if (!plan_start_) plan_start_ = robot;
    const std::optional<Eigen::Vector2d> carrot = carrotOnPlan(*plan_start_, goal, robot, n.carrot_dist);
    if (!carrot) {
      action_ = UtAmrlState::NoArc;
      return haltCommand(speed, n.linear(), dt);
    }
    local_target = core::Pose2{robot.x(), robot.y(), yaw}.inverseTransform(*carrot);
    // graph_navigation compares the speed with the distance tolerance; both are 0.1 in UT's config.
    if (local_target.norm() < n.target_dist_tolerance && std::abs(speed) < n.target_vel_tolerance)
      state_ = NavState::FaceGoal;
  }
  if (state_ == NavState::FaceGoal && std::abs(core::wrapAngle(goal_heading_ - yaw)) < n.target_angle_tolerance)
    state_ = NavState::Stopped;

  if (state_ == NavState::Stopped) {
    action_ = local_goal_ ? UtAmrlState::Stopped : UtAmrlState::Idle;
    return haltCommand(speed, n.linear(), dt);
  }
  if (state_ == NavState::FaceGoal) {
    action_ = UtAmrlState::FaceGoal;
    return turnInPlaceCommand(core::wrapAngle(goal_heading_ - yaw), speed, yaw_rate, n.linear(), n.angular(),
                              n.max_turn_speed, dt);
  }
  const double bearing = std::atan2(local_target.y(), local_target.x());
  if (std::abs(bearing) > n.local_fov_deg * std::numbers::pi / 180.0) {
    action_ = UtAmrlState::TurnInPlace;
    return turnInPlaceCommand(bearing, speed, yaw_rate, n.linear(), n.angular(), n.max_turn_speed, dt);
  }
  if (local_target.norm() > n.carrot_dist) local_target *= n.carrot_dist / local_target.norm();
  const std::vector<Arc> arcs = sampleArcs(local_target, points_, speed, n.max_linear_decel, n.arcs);
  const int best = chooseArc(arcs, local_target, points_, n.arcs);
  if (best < 0) {
    action_ = UtAmrlState::NoArc;
    return haltCommand(speed, n.linear(), dt);
  }
  action_ = UtAmrlState::Arcs;
  const Arc& arc = arcs[static_cast<std::size_t>(best)];
  ArcCommand command;
  command.linear = timeOptimalSpeed(n.linear(), speed, arc.length, dt);
  command.angular = command.linear * arc.curvature;
  return command;
}

}  // namespace barn::controllers
