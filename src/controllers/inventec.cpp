#include "barn/controllers/inventec.hpp"

#include <algorithm>
#include <cmath>
#include <numbers>

#include "inventec_safety.hpp"

namespace barn::controllers {

std::span<const std::string_view> enumNames(SafetyCheck) {
  static constexpr std::string_view kNames[] = {"front", "fi", "mpc", "none"};
  return kNames;
}

std::span<const std::string_view> enumNames(InventecVariant) {
  static constexpr std::string_view kNames[] = {"code", "paper"};
  return kNames;
}

namespace {
double degrees(double d) { return d * std::numbers::pi / 180.0; }
constexpr std::uint64_t kWiggleStream = 0x57169;  // sub-stream of the episode seed for the Wiggle
// The breadcrumb BackTrack reverses to lies behind the robot: the robot within this angle of
// straight ahead of it, seen along the robot's heading (code and paper).
constexpr double kBreadcrumbConeDeg = 60.0;
}  // namespace

InventecRules InventecRules::of(const InventecConfig& config) {
  const bool code = config.variant == InventecVariant::Code;
  InventecRules rules;
  rules.start_in_lflh = code;
  rules.wiggle_on_rear_block = code;
  rules.forward_backs_off = code;
  rules.check_raw_command = code;
  rules.code_path_cues = code;
  rules.code_turn_checks = code;
  rules.heading_limit = degrees(config.heading_limit_deg);
  rules.heading_tolerance = degrees(config.heading_tolerance_deg);
  return rules;
}

std::string_view toString(InventecState state) {
  switch (state) {
    case InventecState::Initial: return "Initial";
    case InventecState::Lflh: return "LfLH";
    case InventecState::HardTurn: return "HardTurn";
    case InventecState::BackTrack: return "BackTrack";
    case InventecState::Wiggle: return "Wiggle";
    case InventecState::Forward: return "Forward";
  }
  return "";
}

void validate(const InventecConfig& c, core::Errors& errors, const std::string& prefix) {
  core::validateFields(c, errors, prefix);
  core::validateFields(c.safety, errors, prefix + ".safety");
  validate(c.drive, errors, prefix);
  errors.check(c.heading_tolerance_deg > 0.0 && c.heading_tolerance_deg <= c.heading_limit_deg,
               prefix + ".heading_tolerance_deg", "must be in (0, heading_limit_deg]");
  const InventecSafetyConfig& s = c.safety;
  errors.check(s.front_pad_x >= 0.0 && s.front_pad_y >= 0.0, prefix + ".safety.front_pad_x", "pads must be >= 0");
  errors.check(s.ring_front > 0.0 && s.ring_edge > 0.0, prefix + ".safety.ring_front", "ring thresholds must be > 0");
  nav::validate(c.nav, errors, prefix + ".nav");
}

InventecState nextInventecState(InventecState state, const InventecInputs& in, const InventecRules& rules) {
  switch (state) {
    case InventecState::Initial:
      if (!in.has_path) return InventecState::Initial;
      // The code starts in LfLH; the paper turns toward the path first.
      return rules.start_in_lflh ? InventecState::Lflh : InventecState::HardTurn;
    case InventecState::Lflh:
      if (in.command_unsafe) return InventecState::BackTrack;
      if (std::abs(in.heading_error) > rules.heading_limit) return InventecState::HardTurn;
      return InventecState::Lflh;
    case InventecState::HardTurn:
      if (in.rotation_unsafe) return InventecState::BackTrack;
      if (std::abs(in.heading_error) < rules.heading_tolerance) return InventecState::Lflh;
      return InventecState::HardTurn;
    case InventecState::BackTrack:
      if (in.rear_blocked) return rules.wiggle_on_rear_block ? InventecState::Wiggle : InventecState::Forward;
      if (in.backtrack_done) return InventecState::HardTurn;
      return InventecState::BackTrack;
    case InventecState::Wiggle:
      return in.wiggle_done ? InventecState::Forward : InventecState::Wiggle;
    case InventecState::Forward:
      if (in.forward_unsafe) return InventecState::BackTrack;
      if (in.forward_done) return InventecState::HardTurn;
      return InventecState::Forward;
  }
  return state;
}

PathCues codePathCues(const nav::Path& local_path, double goal_distance, double direction_distance) {
  PathCues cues;
  if (local_path.empty()) return cues;
  const Eigen::Vector2d start = local_path.front().norm() <= 0.05 ? Eigen::Vector2d::Zero() : local_path.front();

  Eigen::Vector2d goal = local_path.back();
  for (const auto& p : local_path) {
    if ((p - start).norm() > goal_distance) {
      goal = p;
      break;
    }
  }
  if ((goal - start).norm() > 1e-9) cues.goal_direction = (goal - start).normalized();

  Eigen::Vector2d sum = Eigen::Vector2d::Zero();
  Eigen::Vector2d previous = start;
  double walked = 0.0;
  for (const auto& p : local_path) {
    walked += (p - previous).norm();
    previous = p;
    const Eigen::Vector2d d = p - start;
    if (d.norm() > 0.1) sum += d.normalized();
    if (walked > direction_distance) break;
  }
  if (sum.squaredNorm() > 1e-18) cues.path_direction = std::atan2(sum.y(), sum.x());
  return cues;
}

double wiggleTarget(double yaw, double path_direction, double min_angle, double span, int choices, core::Rng& rng) {
  const double k = static_cast<double>(rng.below(static_cast<std::uint64_t>(choices)));
  const double offset = choices > 1 ? k * span / (choices - 1) : 0.0;
  const double side = path_direction >= 0.0 ? 1.0 : -1.0;
  return core::wrapAngle(yaw + side * (min_angle + offset));
}

InventecController::InventecController(const InventecConfig& config, std::shared_ptr<const learning::Policy> policy)
    : config_(config), rules_(InventecRules::of(config)), policy_(std::move(policy)), nav_(config.nav) {}

InventecController::~InventecController() = default;

void InventecController::reset(const EpisodeInfo& info) {
  info_ = info;
  // The checks size the robot by its planning footprint (0.508 x 0.43, the paper's and the code's).
  safety_ = makeInventecSafety(config_, rules_, info);
  roi_box_ = core::Rect::centred(config_.roi_length, config_.roi_width);
  nav_.reset(info.goal);
  rng_ = core::Rng(core::mixSeed(info.seed, kWiggleStream));
  state_ = InventecState::Initial;
  breadcrumbs_.clear();
  aligned_ = false;
  reversed_ = 0.0;
  reverse_ticks_ = 0;
}

core::Twist InventecController::turnToward(double error) const {
  double w = std::clamp(config_.heading_gain * error, -config_.drive.max_turn_rate, config_.drive.max_turn_rate);
  if (std::abs(w) < config_.min_turn_rate) w = std::copysign(config_.min_turn_rate, error);
  return {0.0, w};
}

core::Twist InventecController::shape(const core::Twist& raw, const core::LaserScan& scan) const {
  core::Twist out = raw;
  if (config_.boost && raw.linear > config_.boost_threshold &&
      frontClear(scan, degrees(config_.safety.front_angle_deg), config_.boost_clearance)) {
    out.linear = config_.boost_speed;
  } else {
    out.linear = std::clamp(raw.linear, -config_.drive.max_speed, config_.drive.max_speed);
  }
  out.angular = std::clamp(raw.angular, -config_.drive.max_turn_rate, config_.drive.max_turn_rate);
  return out;
}

void InventecController::enter(InventecState state, const core::Pose2& pose, double time, double path_direction) {
  if (state == InventecState::BackTrack) {
    // The breadcrumb: walking the driven path backwards, the first point at least
    // backtrack_distance away that lies behind the robot (the robot is within 60 degrees of
    // straight ahead of it, seen along the robot's heading). The path is cut there.
    // Without one the code returned (0, 0) and went on to HardTurn, which can repeat without
    // moving; here the target is then the point backtrack_distance straight behind, so the
    // robot reverses straight (with the rear check) instead.
    aligned_ = false;
    reversed_ = 0.0;
    reverse_ticks_ = 0;
    backtrack_target_ = pose.transform({-config_.backtrack_distance, 0.0});
    const Eigen::Vector2d heading(std::cos(pose.yaw), std::sin(pose.yaw));
    for (std::size_t k = breadcrumbs_.size(); k-- > 0;) {
      const Eigen::Vector2d away = pose.position() - breadcrumbs_[k];
      if (away.norm() < config_.backtrack_distance) continue;
      if (away.normalized().dot(heading) < std::cos(degrees(kBreadcrumbConeDeg))) continue;
      backtrack_target_ = breadcrumbs_[k];
      breadcrumbs_.resize(k);
      break;
    }
  }
  if (state == InventecState::Wiggle) {
    wiggle_target_ = wiggleTarget(pose.yaw, path_direction, degrees(config_.wiggle_min_deg), config_.wiggle_span,
                                  config_.wiggle_choices, rng_);
  }
  if (state == InventecState::Forward) forward_started_ = time;
  state_ = state;
}

PathCues InventecController::pathCues(const core::Pose2& pose) const {
  PathCues cues;
  if (!nav_.hasPath()) return cues;
  const nav::Path& path = nav_.path();
  if (!rules_.code_path_cues) {
    cues.path_direction = nav::headingError(path, pose, config_.path_direction_distance);
    cues.goal_direction = localGoalDirection(path, pose, config_.drive.local_goal_distance);
    return cues;
  }
  // The code planned at 20 Hz from the robot's pose, so its path began at the robot; ours is
  // replanned less often, so the part already driven is cut off at the closest point.
  const nav::Path ahead(path.begin() + static_cast<std::ptrdiff_t>(nav::closestIndex(path, pose.position())),
                        path.end());
  return codePathCues(nav::pathInRobotFrame(ahead, pose), config_.drive.local_goal_distance, config_.path_direction_distance);
}

core::Twist InventecController::lflhCommand(const SafetyScene& scene, const Eigen::Vector2d& goal_direction,
                                            InventecInputs& in) const {
  const core::Twist raw = policy_->act(scene.scan, goal_direction);
  if (rules_.check_raw_command) {
    // The code checks the network's command and shapes the speed when publishing.
    in.command_unsafe = safety_->commandUnsafe(scene, raw);
    return shape(raw, scene.scan);
  }
  const core::Twist command{std::clamp(raw.linear, -config_.drive.max_speed, config_.drive.max_speed),
                            std::clamp(raw.angular, -config_.drive.max_turn_rate, config_.drive.max_turn_rate)};
  in.command_unsafe = safety_->commandUnsafe(scene, command);
  return command;
}

core::Twist InventecController::hardTurnCommand(const SafetyScene& scene, InventecInputs& in) const {
  const core::Twist command = turnToward(in.heading_error);
  in.rotation_unsafe = safety_->turnUnsafe(scene, command);
  return command;
}

core::Twist InventecController::backTrackCommand(const SafetyScene& scene, InventecInputs& in) {
  const core::Pose2& pose = scene.pose;
  core::Twist command;
  if (!aligned_) {
    // Turn the rear toward the target; an unsafe turn ends the alignment early.
    const Eigen::Vector2d away = pose.position() - backtrack_target_;
    const double error = core::wrapAngle(std::atan2(away.y(), away.x()) - pose.yaw);
    command = turnToward(error);
    if (std::abs(error) <= degrees(config_.align_tolerance_deg) || safety_->alignmentAborted(scene, command)) {
      aligned_ = true;
      reverse_start_ = pose.position();
      reversed_ = 0.0;
      reverse_ticks_ = 0;
    }
  }
  if (!aligned_) return command;
  const double reversed = (pose.position() - reverse_start_).norm();
  // Done when far enough (code: ~0.1 m; paper: at or past the breadcrumb), or when the
  // distance stopped growing (the code's loop condition; a stall cannot last).
  const bool far_enough = config_.backtrack_reverse > 0.0
                              ? reversed > config_.backtrack_reverse
                              : (pose.position() - backtrack_target_).norm() < 0.05 ||
                                    pose.inverseTransform(backtrack_target_).x() >= 0.0;
  const bool stalled = reverse_ticks_ >= 2 && reversed <= reversed_ + 1e-4;
  in.backtrack_done = far_enough || stalled;
  in.rear_blocked = config_.backtrack_roi &&
                    rearRegionBlocked(nav_.localObstacleLayer(), pose, rearStrip(roi_box_, config_.roi_depth), config_.rear_weight);
  reversed_ = reversed;
  ++reverse_ticks_;
  return {-config_.backtrack_speed, 0.0};
}

core::Twist InventecController::wiggleCommand(const SafetyScene& scene, InventecInputs& in) const {
  const double error = core::wrapAngle(wiggle_target_ - scene.pose.yaw);
  const core::Twist command = turnToward(error);
  in.wiggle_done = std::abs(error) <= degrees(config_.align_tolerance_deg) || safety_->alignmentAborted(scene, command);
  return command;
}

core::Twist InventecController::forwardCommand(const SafetyScene& scene, double time, InventecInputs& in) const {
  const double turn_sign = in.heading_error >= 0.0 ? 1.0 : -1.0;
  core::Twist command{config_.forward_speed, turn_sign * config_.forward_turn_rate};
  const bool unsafe = safety_->forwardUnsafe(scene, command);
  if (rules_.forward_backs_off) {
    if (unsafe) command.linear = -config_.forward_speed;  // the code backs off with the same turn
  } else {
    in.forward_unsafe = unsafe;
  }
  in.forward_done = time - forward_started_ >= config_.forward_duration - 1e-9;
  return command;
}

core::Twist InventecController::act(const Observation& obs) {
  const core::Pose2 pose = obs.odom_pose;
  const core::LaserScan& scan = *obs.scan;
  nav_.update(obs.time, scan, info_.lidar.sensorPose(obs.scan_odom_pose), pose);
  const std::vector<Eigen::Vector2d> points = scanPoints(scan, info_.lidar, beams_);
  const SafetyScene scene{scan, points, pose, nav_};
  const PathCues cues = pathCues(pose);
  InventecInputs in;
  in.has_path = nav_.hasPath();
  in.heading_error = cues.path_direction;

  // The checks of the current state, then at most one transition per tick.
  core::Twist command;
  switch (state_) {
    case InventecState::Initial: break;
    case InventecState::Lflh: command = lflhCommand(scene, cues.goal_direction, in); break;
    case InventecState::HardTurn: command = hardTurnCommand(scene, in); break;
    case InventecState::BackTrack: command = backTrackCommand(scene, in); break;
    case InventecState::Wiggle: command = wiggleCommand(scene, in); break;
    case InventecState::Forward: command = forwardCommand(scene, obs.time, in); break;
  }
  const InventecState next = nextInventecState(state_, in, rules_);
  if (next != state_) {
    enter(next, pose, obs.time, in.heading_error);
    return {};  // every transition stops the robot for one tick, as the original publishes (0, 0)
  }
  if (state_ == InventecState::Lflh &&
      (breadcrumbs_.empty() || (breadcrumbs_.back() - pose.position()).norm() >= 0.05))
    breadcrumbs_.push_back(pose.position());
  return command;
}

}  // namespace barn::controllers
