#include "barn/controllers/almeria_tps.hpp"

#include <algorithm>
#include <cmath>
#include <limits>
#include <numbers>

namespace barn::controllers {

namespace {
constexpr double kPi = std::numbers::pi;

// Distance from `p` to the segment a-b (mrpt::math::TSegment2D::distance).
double segmentDistance(const Eigen::Vector2d& a, const Eigen::Vector2d& b, const Eigen::Vector2d& p) {
  const Eigen::Vector2d ab = b - a;
  const double len2 = ab.squaredNorm();
  const double s = len2 > 0.0 ? std::clamp((p - a).dot(ab) / len2, 0.0, 1.0) : 0.0;
  return (a + s * ab - p).norm();
}

bool isIndex(double value) {
  return value >= 0.0 && value < static_cast<double>(kFullEvalFactors) && value == std::floor(value);
}
}  // namespace

// ---- FullEval ----

void validate(const FullEvalConfig& c, core::Errors& errors, const std::string& prefix) {
  core::validateFields(c, errors, prefix);
  if (errors.check(c.factor_weights.size() == kFullEvalFactors, prefix + ".factor_weights", "must have 7 values"))
    for (double w : c.factor_weights)
      if (!errors.check(w >= 0.0, prefix + ".factor_weights", "must be >= 0")) break;
  if (errors.check(c.factor_normalize.size() == kFullEvalFactors, prefix + ".factor_normalize", "must have 7 values"))
    for (double n : c.factor_normalize)
      if (!errors.check(n == 0.0 || n == 1.0, prefix + ".factor_normalize", "must be 0 or 1")) break;
  errors.check(!c.phases.empty(), prefix + ".phases", "must have at least one phase");
  for (std::size_t p = 0; p < c.phases.size(); ++p) {
    const std::string where = prefix + ".phases[" + std::to_string(p) + "]";
    const FullEvalPhase& phase = c.phases[p];
    errors.check(phase.threshold > 0.0 && phase.threshold < 1.0, where + ".threshold", "must be in (0, 1)");
    if (!errors.check(!phase.factors.empty(), where + ".factors", "must list at least one factor")) continue;
    double weight = 0.0;
    bool indices = true;
    for (double f : phase.factors) {
      indices = indices && isIndex(f);
      if (indices && c.factor_weights.size() == kFullEvalFactors) weight += c.factor_weights[static_cast<std::size_t>(f)];
    }
    if (errors.check(indices, where + ".factors", "must be factor indices 0 ... 6") &&
        c.factor_weights.size() == kFullEvalFactors)
      errors.check(weight > 0.0, where + ".factors", "the factors' weights must not all be 0");
  }
}

FullEvalChoice FullEval::navigate(const TpSpaceInput& in) {
  const std::size_t n = in.obstacles.size();
  const int ni = static_cast<int>(n);
  const double too_close = config_.too_close_obstacle;
  const Eigen::Vector2d target = in.target;
  const int target_k = alphaIndex(std::atan2(target.y(), target.x()), ni);
  const double target_dist = target.norm();

  std::vector<Eigen::Vector2d> unit(n), obstacle_points(n);
  for (std::size_t i = 0; i < n; ++i) {
    const double a = pathAlpha(static_cast<int>(i), ni);
    unit[i] = {std::cos(a), std::sin(a)};
    obstacle_points[i] = in.obstacles[i] * unit[i];
  }

  // ---- The seven factors per direction ----
  factors_.assign(n, {});
  const int window = std::max(1, static_cast<int>(std::lround(0.1 * ni)));
  for (std::size_t i = 0; i < n; ++i) {
    const int ii = static_cast<int>(i);
    const double free = in.obstacles[i];
    auto& s = factors_[i];
    if (free < too_close && !(ii == target_k && free > 1.02 * target_dist)) continue;  // all factors 0
    const Eigen::Vector2d end = std::min(free, 0.95 * target_dist) * unit[i];
    const int from_target = std::abs(ii - target_k);

    // [0] free space; obstacles past a near target do not count.
    if (from_target <= 1 && target_dist < 1.0 - too_close && free > 1.05 * target_dist)
      s[0] = std::max(target_dist, free) / (target_dist * 1.05);
    else
      s[0] = std::max(0.0, free - too_close);
    s[0] = std::min(s[0], in.unlooped[i]);

    // [1] closest approach to the target along the segment 0-P (P/2-P when moving away).
    double approach = segmentDistance(Eigen::Vector2d::Zero(), end, target);
    const double end_to_target = std::min(1.0, (target - end).norm());
    if (end_to_target > target_dist && end_to_target >= 0.95 * target_dist &&
        approach > 1.05 * std::min(target_dist, end_to_target))
      approach = segmentDistance(0.5 * end, end, target);
    s[1] = 1.0 / (1.0 + approach * approach);

    // [2] and [5] the end point's nearness to the target.
    s[2] = std::sqrt(1.01 - end_to_target);
    s[5] = s[2];

    // [3] hysteresis.
    s[3] = 1.0;
    if (last_selected_ >= 0) {
      const double switched = std::abs(last_selected_ - ii);
      if (switched >= config_.hysteresis_sector_count) {
        const double h = 1.0 - (switched - config_.hysteresis_sector_count) / static_cast<double>(n);
        s[3] = h * h;
      }
    }

    // [4] clearance: the nearest TP-obstacle point of the neighbouring directions.
    s[4] = 1.0;
    for (int j = std::max(0, ii - window); j <= std::min(ni - 1, ii + window); ++j) {
      if (in.obstacles[static_cast<std::size_t>(j)] >= 0.99) continue;  // the end of the path, not an obstacle
      s[4] = std::min(s[4], segmentDistance(Eigen::Vector2d::Zero(), end, obstacle_points[static_cast<std::size_t>(j)]));
    }

    // [6] nearness to the target direction, in paths.
    const double sectors = 4.0 / static_cast<double>(n) * from_target;
    s[6] = 1.0 / (1.0 + sectors * sectors);

    // The target lies beyond this direction's free space.
    if (target_dist < 1.0 - too_close && free < 1.01 * target_dist) {
      s[1] *= 0.1;
      s[2] *= 0.1;
      s[6] *= 0.1;
    }
  }
  for (std::size_t l = 0; l < kFullEvalFactors; ++l) {
    if (config_.factor_normalize[l] == 0.0) continue;
    double lo = std::numeric_limits<double>::max(), hi = std::numeric_limits<double>::lowest();
    for (const auto& s : factors_) {
      lo = std::min(lo, s[l]);
      hi = std::max(hi, s[l]);
    }
    if (hi - lo <= 0.0) continue;
    for (auto& s : factors_) s[l] = (s[l] - lo) / (hi - lo);
  }

  // ---- Phases ----
  phases_.assign(config_.phases.size(), std::vector<double>(n, 0.0));
  double threshold = -1.0;
  for (std::size_t p = 0; p < config_.phases.size(); ++p) {
    const FullEvalPhase& phase = config_.phases[p];
    double weight_sum = 0.0;
    for (double f : phase.factors) weight_sum += config_.factor_weights[static_cast<std::size_t>(f)];
    double lo = std::numeric_limits<double>::max(), hi = 0.0;
    for (std::size_t i = 0; i < n; ++i) {
      double eval = 0.0;
      if (!(in.obstacles[i] < too_close || (p > 0 && phases_[p - 1][i] < threshold))) {
        for (double f : phase.factors) {
          const auto l = static_cast<std::size_t>(f);
          eval += config_.factor_weights[l] * std::log(std::max(1e-6, factors_[i][l]));
        }
        eval = std::exp(eval / weight_sum);
      }
      phases_[p][i] = eval;
      hi = std::max(hi, eval);
      lo = std::min(lo, eval);
    }
    threshold = phase.threshold * hi + (1.0 - phase.threshold) * lo;
  }
  std::vector<double>& scores = phases_.back();
  for (double& v : scores)
    if (v < threshold) v = 0.0;

  // ---- The best direction: runs ("gaps") of scores >= 0.01; the run holding the first
  // maximum; in it, the last direction scoring its maximum ----
  struct Gap {
    int best = -1;
    double max = -1.0;
  };
  std::vector<Gap> gaps;
  int best_gap = -1;
  bool inside = false;
  for (int i = 0; i < ni; ++i) {
    const double v = scores[static_cast<std::size_t>(i)];
    if (v < 0.01) {
      inside = false;
      continue;
    }
    if (!inside) gaps.emplace_back();
    inside = true;
    Gap& gap = gaps.back();
    if (v >= gap.max) gap.best = i;
    gap.max = std::max(gap.max, v);
    if (best_gap < 0 || v > gaps[static_cast<std::size_t>(best_gap)].max) best_gap = static_cast<int>(gaps.size()) - 1;
  }
  FullEvalChoice choice;
  if (best_gap >= 0) choice.direction = gaps[static_cast<std::size_t>(best_gap)].best;
  last_selected_ = choice.direction;
  if (choice.direction < 0) return choice;
  const auto k = static_cast<std::size_t>(choice.direction);
  choice.evaluation = scores[k];
  const double nearness =
      in.slow_down_at_target
          ? std::min(1.0, target_dist / (config_.target_slow_approaching_distance / in.ref_distance))
          : 1.0;
  const double slow_down = std::max(too_close, config_.obstacle_slow_down_distance / in.ref_distance);
  double risk = 1.0;
  if (in.obstacles[k] <= too_close)
    risk = 0.0;
  else if (in.obstacles[k] < slow_down && slow_down > too_close)
    risk = (in.obstacles[k] - too_close) / (slow_down - too_close);
  choice.speed = std::min(risk, nearness);
  return choice;
}

double secureDistanceScale(double free_distance, double start, double end) {
  if (free_distance >= end) return 1.0;
  if (free_distance <= start) return 0.0;
  return (free_distance - start) / (end - start);
}

double limitToRobot(core::Twist& cmd, double max_v, double max_w) {
  double scale = 1.0;
  if (std::abs(cmd.linear) > max_v) {
    const double f = max_v / std::abs(cmd.linear);
    cmd.linear *= f;
    cmd.angular *= f;
    scale *= f;
  }
  if (std::abs(cmd.angular) > max_w) {
    const double f = max_w / std::abs(cmd.angular);
    cmd.linear *= f;
    cmd.angular *= f;
    scale *= f;
  }
  return scale;
}

// ---- The controller ----

std::span<const std::string_view> enumNames(AlmeriaTpsState) {
  static constexpr std::string_view kNames[] = {"Navigating", "NoWay", "OutOfDomain", "Reached", "Aborted"};
  return kNames;
}

std::span<const std::string_view> enumNames(AlmeriaTarget) {
  static constexpr std::string_view kNames[] = {"plan_waypoints", "goal"};
  return kNames;
}

std::vector<Eigen::Vector2d> planWaypoints(const std::vector<Eigen::Vector2d>& plan, const Eigen::Vector2d& goal,
                                           double spacing) {
  std::vector<Eigen::Vector2d> waypoints;
  double walked = 0.0, next = spacing;
  for (std::size_t i = 1; i < plan.size(); ++i) {
    walked += (plan[i] - plan[i - 1]).norm();
    if (walked < next) continue;
    waypoints.push_back(plan[i]);
    while (next <= walked) next += spacing;
  }
  if (!waypoints.empty() && (waypoints.back() - goal).norm() < 0.5 * spacing) waypoints.pop_back();
  waypoints.push_back(goal);
  return waypoints;
}

nav::NavStackConfig AlmeriaTpsConfig::almeriaNav() {
  nav::NavStackConfig c = nav::NavStackConfig::moveBaseWithNavFn();
  c.planner.rate = 1.0;
  return c;
}

void validate(const AlmeriaTpsConfig& c, core::Errors& errors, const std::string& prefix) {
  core::validateFields(c, errors, prefix);
  errors.check(c.secure_distance_end > c.secure_distance_start, prefix + ".secure_distance_end",
               "must be > secure_distance_start");
  validate(c.ptg, errors, prefix + ".ptg");
  validate(c.full_eval, errors, prefix + ".full_eval");
  nav::validate(c.nav, errors, prefix + ".nav");
}

AlmeriaTpsController::AlmeriaTpsController(const AlmeriaTpsConfig& config, std::shared_ptr<const ArcPtg> ptg)
    : config_(config),
      ptg_(ptg ? std::move(ptg) : std::make_shared<const ArcPtg>(config.ptg)),
      full_eval_(config.full_eval),
      nav_(config.nav) {
  unlooped_.resize(static_cast<std::size_t>(ptg_->pathCount()));
  for (int k = 0; k < ptg_->pathCount(); ++k)
    unlooped_[static_cast<std::size_t>(k)] = ptg_->pathLength(k) / ptg_->refDistance();
}

void AlmeriaTpsController::reset(const EpisodeInfo& info) {
  info_ = info;
  full_eval_.reset();
  nav_.reset(info.goal);
  state_ = AlmeriaTpsState::Navigating;
  have_previous_ = false;
  previous_position_ = Eigen::Vector2d::Zero();
  waypoints_.assign(1, info.goal);
  sightings_.assign(1, 0);
  reached_ = 0;
  current_ = -1;
  plans_taken_ = 0;
  have_tp_ = false;
  min_target_distance_ = std::numeric_limits<double>::infinity();
  min_target_time_ = 0.0;
  last_command_ = {};
  choice_ = {};
  points_.clear();
  tp_obstacles_.clear();
}

core::Twist AlmeriaTpsController::stop(AlmeriaTpsState state) {
  state_ = state;
  last_command_ = {};
  return {};
}

bool AlmeriaTpsController::reachable(const Eigen::Vector2d& local) const {
  if (!have_tp_) return false;
  const TpPoint tp = ptg_->inverseMap(local);
  return tp.exact && tp_obstacles_[static_cast<std::size_t>(tp.k)] > 1.01 * tp.distance / ptg_->refDistance();
}

bool AlmeriaTpsController::stepWaypoints(const Observation& obs) {
  const Eigen::Vector2d position = obs.odom_pose.position();
  const Eigen::Vector2d from = have_previous_ ? previous_position_ : position;
  previous_position_ = position;
  have_previous_ = true;
  const int last = static_cast<int>(waypoints_.size()) - 1;
  const int before = current_;
  // Reached: the last move passed within the allowed distance.
  if (current_ >= 0) {
    const Eigen::Vector2d move = position - from;
    const Eigen::Vector2d& wp = waypoints_[static_cast<std::size_t>(current_)];
    const double s = move.squaredNorm() > 0.0 ? std::clamp((wp - from).dot(move) / move.squaredNorm(), 0.0, 1.0) : 0.0;
    const double allowed = current_ == last ? config_.target_allowed_distance : config_.waypoint_allowed_distance;
    if ((from + s * move - wp).norm() < allowed) {
      if (current_ == last) return false;
      reached_ = ++current_;
    }
  }
  // Skip ahead to the farthest waypoint seen reachable often enough (from the second tick of a
  // sequence: on its first there is no current waypoint yet).
  const core::PoseFrame robot(obs.odom_pose);
  int most_advanced = current_;
  for (int i = current_ < 0 ? last + 1 : reached_; i <= last; ++i) {
    const Eigen::Vector2d local = robot.toLocal(waypoints_[static_cast<std::size_t>(i)]);
    if (config_.max_distance_to_allow_skip_waypoint > 0.0 && local.norm() > config_.max_distance_to_allow_skip_waypoint)
      continue;
    if (reachable(local) && ++sightings_[static_cast<std::size_t>(i)] > config_.min_timesteps_confirm_skip_waypoints)
      most_advanced = i;
  }
  if (most_advanced > current_) {
    current_ = most_advanced;
    reached_ = current_;
  }
  if (current_ < 0) current_ = 0;
  if (current_ != before) {
    // A new target: CAbstractNavigator restarts its not-approaching alarm.
    min_target_distance_ = std::numeric_limits<double>::infinity();
    min_target_time_ = obs.time;
  }
  return true;
}

core::Twist AlmeriaTpsController::act(const Observation& obs) {
  if (state_ == AlmeriaTpsState::Reached || state_ == AlmeriaTpsState::Aborted) return {};
  const core::Pose2& pose = obs.odom_pose;
  const core::LaserScan& scan = *obs.scan;

  // 0. Waypoints: a new plan is a new sequence.
  if (config_.target == AlmeriaTarget::PlanWaypoints) {
    nav_.update(obs.time, scan, info_.lidar.sensorPose(obs.scan_odom_pose), pose);
    if (nav_.plansMade() != plans_taken_ && nav_.lastPlanFound() && nav_.hasPath()) {
      plans_taken_ = nav_.plansMade();
      waypoints_ = planWaypoints(nav_.path(), info_.goal, config_.waypoint_spacing);
      sightings_.assign(waypoints_.size(), 0);
      reached_ = 0;
      current_ = -1;
    }
  }
  if (!stepWaypoints(obs)) return stop(AlmeriaTpsState::Reached);
  const Eigen::Vector2d target_odom = waypoints_[static_cast<std::size_t>(current_)];
  const bool final_target = current_ + 1 == static_cast<int>(waypoints_.size());

  // 1. The not-approaching alarm.
  const double target_distance = (target_odom - pose.position()).norm();
  if (target_distance < min_target_distance_) {
    min_target_distance_ = target_distance;
    min_target_time_ = obs.time;
  } else if (obs.time - min_target_time_ > config_.not_approaching_timeout) {
    return stop(AlmeriaTpsState::Aborted);
  }

  // 2. Obstacle points in the robot frame.
  points_.clear();
  const core::PoseFrame sensor(info_.lidar.sensorPose(obs.scan_odom_pose));
  const core::PoseFrame robot(pose);
  for (std::size_t i = 0; i < scan.ranges.size(); ++i) {
    const double r = scan.ranges[i];
    if (!(r >= scan.range_min && r < scan.range_max)) continue;
    const double a = scan.angle(i);
    points_.push_back(robot.toLocal(sensor.toParent({r * std::cos(a), r * std::sin(a)})));
  }

  // 4. TP-obstacles (kept for the next tick's waypoint sightings).
  ptg_->tpObstacles(points_, tp_obstacles_);
  have_tp_ = true;

  // 3. The target in TP-space.
  const Eigen::Vector2d target = robot.toLocal(target_odom);
  const TpPoint tp = ptg_->inverseMap(target);
  if (!tp.exact) {
    choice_ = {};
    return stop(AlmeriaTpsState::OutOfDomain);
  }
  const double ref = ptg_->refDistance();
  const double target_alpha = ptg_->alpha(tp.k);
  TpSpaceInput input;
  input.obstacles = tp_obstacles_;
  input.unlooped = unlooped_;
  input.target = tp.distance / ref * Eigen::Vector2d(std::cos(target_alpha), std::sin(target_alpha));
  input.ref_distance = ref;
  input.slow_down_at_target = final_target;

  // 5. FullEval.
  choice_ = full_eval_.navigate(input);
  if (choice_.direction < 0) return stop(AlmeriaTpsState::NoWay);

  // 6. Speed: the secure-distance ramp, then the target slow-down (last waypoint only).
  const auto k = static_cast<std::size_t>(choice_.direction);
  double speed = choice_.speed * secureDistanceScale(tp_obstacles_[k], config_.secure_distance_start,
                                                      config_.secure_distance_end);
  if (final_target) speed = std::min(speed, target.norm() / config_.full_eval.target_slow_approaching_distance);
  if (speed <= 0.0) return stop(AlmeriaTpsState::NoWay);

  // 7. Path k's command, scaled; robot limits; low-pass filter (keeping the curvature).
  core::Twist cmd{ptg_->linearSpeed(choice_.direction) * speed, ptg_->angularSpeed(choice_.direction) * speed};
  const double max_v = config_.robot_max_v, max_w = config_.robot_max_w_deg * kPi / 180.0;
  limitToRobot(cmd, max_v, max_w);
  const double beta = config_.nav_period / (config_.nav_period + config_.speedfilter_tau);
  if (std::abs(cmd.linear) < 0.01) {
    cmd.angular = beta * cmd.angular + (1.0 - beta) * last_command_.angular;
  } else {
    const double ratio = cmd.angular / cmd.linear;
    cmd.linear = beta * cmd.linear + (1.0 - beta) * last_command_.linear;
    cmd.angular = ratio * cmd.linear;
    limitToRobot(cmd, max_v, max_w);
  }
  last_command_ = cmd;
  state_ = AlmeriaTpsState::Navigating;
  return cmd;
}

}  // namespace barn::controllers
