#include "barn/controllers/eband.hpp"

#include <algorithm>
#include <cmath>
#include <limits>

namespace barn::controllers {

namespace {

// The fraction of a bubble's radius the trajectory controller counts as drivable (a constant
// in EBandTrajectoryCtrl, not eband_min_relative_overlap, although both are 0.7).
constexpr double kBubbleRadiusFraction = 0.7;
// Within this distance of the band's end the speed limit is halved (a constant upstream).
constexpr double kSlowDownDistance = 0.75;  // [m]
// BARN's run.py sends the goal with the identity quaternion: yaw 0 in the odom frame. NavFn
// gives every plan pose the identity orientation too and ends the plan with the goal pose.
constexpr double kPlanYaw = 0.0;

double sign(double x) { return x < 0.0 ? -1.0 : 1.0; }

}  // namespace

void validate(const EbandConfig& c, core::Errors& errors, const std::string& prefix) {
  core::validateFields(c, errors, prefix);
  errors.check(c.min_vel_lin >= 0.0 && c.min_vel_lin <= c.max_vel_lin, prefix + ".min_vel_lin", "must be in [0, max_vel_lin]");
  errors.check(c.min_vel_th >= 0.0 && c.min_vel_th <= c.max_vel_th, prefix + ".min_vel_th", "must be in [0, max_vel_th]");
  errors.check(c.min_in_place_vel_th >= 0.0 && c.min_in_place_vel_th <= c.max_vel_th, prefix + ".min_in_place_vel_th",
               "must be in [0, max_vel_th]");
  validate(c.recovery, errors, prefix + ".recovery");
  nav::validate(c.nav, errors, prefix + ".nav");
}

// ---------------------------------------------------------------------------------------------
// ElasticBand (EBandPlanner)

ElasticBand::ElasticBand(const EbandConfig& config, double circumscribed_radius)
    : config_(config), circumscribed_radius_(circumscribed_radius) {
  // calcObstacleKinematicDistance: inscribed and lethal give 0; free (0) and unknown (255)
  // count as 1; otherwise the inflation inverted, -ln(c / 252) / weight = d - inscribed.
  for (int c = 0; c < 256; ++c) {
    if (c == nav::kInscribedCost || c == nav::kLethalCost) {
      distance_by_cost_[c] = 0.0;
      continue;
    }
    const int cost = (c == nav::kFreeCost || c == nav::kUnknownCost) ? 1 : c;
    distance_by_cost_[c] = -std::log(cost / static_cast<double>(nav::kInscribedCost - 1)) / config_.costmap_weight;
  }
}

int ElasticBand::costAt(const core::Pose2& pose) const {
  nav::CellIndex cell;
  // Off the map (e.g. the window's last pose beyond the local costmap): cost 1, as upstream.
  if (!costmap_->toCell(pose.x, pose.y, cell)) return 1;
  return costmap_->cost(cell.x, cell.y);
}

bool ElasticBand::overlap(const EbandBubble& a, const EbandBubble& b) const {
  // calcBubbleDistance: the centres' distance in the plane only.
  const double distance = std::hypot(b.center.x - a.center.x, b.center.y - a.center.y);
  return distance < config_.eband_min_relative_overlap * (a.expansion + b.expansion);
}

Eigen::Vector3d ElasticBand::difference(const core::Pose2& from, const core::Pose2& to) const {
  return {to.x - from.x, to.y - from.y, circumscribed_radius_ * core::wrapAngle(to.yaw - from.yaw)};
}

bool ElasticBand::convertPlanToBand(const std::vector<core::Pose2>& poses, std::vector<EbandBubble>& band) const {
  band.clear();
  band.reserve(poses.size());
  for (const core::Pose2& pose : poses) {
    const double r = obstacleDistance(pose);
    if (r <= 0.0) return false;  // a pose in collision
    band.push_back({pose, r});
  }
  return true;
}

bool ElasticBand::fillGap(std::vector<EbandBubble>& band, std::size_t start, std::size_t& end) const {
  // The midpoint bubble between two neighbours that do not overlap (yaw halfway the short
  // way round), then the two halves recursively until every pair overlaps.
  const core::Pose2& a = band[start].center;
  const core::Pose2& b = band[end].center;
  EbandBubble mid;
  mid.center = {0.5 * (a.x + b.x), 0.5 * (a.y + b.y), core::wrapAngle(a.yaw + 0.5 * core::wrapAngle(b.yaw - a.yaw))};
  mid.expansion = obstacleDistance(mid.center);
  if (mid.expansion <= config_.eband_tiny_bubble_expansion) return false;  // the gap is blocked
  band.insert(band.begin() + static_cast<std::ptrdiff_t>(end), mid);
  std::size_t m = end;
  end = m + 1;
  if (!overlap(band[start], band[m])) {
    if (!fillGap(band, start, m)) return false;
    end = m + 1;
  }
  if (!overlap(band[m], band[end])) {
    if (!fillGap(band, m, end)) return false;
  }
  return true;
}

bool ElasticBand::removeAndFill(std::vector<EbandBubble>& band, std::size_t start, std::size_t& end) const {
  // Overlapping ends make everything between redundant.
  if (overlap(band[start], band[end])) {
    if (start + 1 < end) {
      band.erase(band.begin() + static_cast<std::ptrdiff_t>(start + 1), band.begin() + static_cast<std::ptrdiff_t>(end));
      end = start + 1;
    }
    return true;
  }
  if (start + 1 < end) {
    // Split at the middle, both halves recursively, then drop the middle bubble if its two
    // neighbours overlap without it.
    std::size_t mid = start + (end - start) / 2;
    const std::size_t after_mid = end - mid;
    if (!removeAndFill(band, start, mid)) return false;
    end = mid + after_mid;
    if (!removeAndFill(band, mid, end)) return false;
    if (overlap(band[mid - 1], band[mid + 1])) {
      band.erase(band.begin() + static_cast<std::ptrdiff_t>(mid));
      --end;
    }
    return true;
  }
  return fillGap(band, start, end);  // neighbours that do not overlap
}

bool ElasticBand::refineBand(std::vector<EbandBubble>& band) const {
  if (band.size() < 2) return false;
  std::vector<EbandBubble> refined = band;
  std::size_t end = refined.size() - 1;
  if (!removeAndFill(refined, 0, end)) return false;
  band = std::move(refined);
  return true;
}

Eigen::Vector3d ElasticBand::internalForce(std::size_t i, const std::vector<EbandBubble>& band,
                                           const EbandBubble& bubble) const {
  // The band's contraction: unit vectors to both neighbours (normed by the planar distance
  // only, the yaw scaled by the circumscribed radius), none toward a neighbour closer than
  // tiny_bubble_distance.
  const Eigen::Vector3d to_previous = difference(bubble.center, band[i - 1].center);
  const Eigen::Vector3d to_next = difference(bubble.center, band[i + 1].center);
  double d1 = std::hypot(to_previous.x(), to_previous.y());
  double d2 = std::hypot(to_next.x(), to_next.y());
  if (d1 <= config_.eband_tiny_bubble_distance) d1 = 1e6;
  if (d2 <= config_.eband_tiny_bubble_distance) d2 = 1e6;
  return config_.eband_internal_force_gain * (to_previous / d1 + to_next / d2);
}

Eigen::Vector3d ElasticBand::externalForce(const EbandBubble& bubble) const {
  // The obstacles' repulsion: the gradient of the free radius by central differences across
  // the bubble's rim. The yaw term is 0: upstream never writes the turned yaw into its sample
  // pose (and the radius ignores yaw anyway). A bubble at most tiny_bubble_expansion wide is
  // sampled at that distance (upstream's guard against dividing by 0; the note gives 0.01,
  // which both tiny_bubble parameters are).
  const double s = bubble.expansion <= config_.eband_tiny_bubble_expansion ? config_.eband_tiny_bubble_expansion
                                                                          : bubble.expansion;
  const core::Pose2& c = bubble.center;
  const double fx = obstacleDistance({c.x + s, c.y, c.yaw}) - obstacleDistance({c.x - s, c.y, c.yaw});
  const double fy = obstacleDistance({c.x, c.y + s, c.yaw}) - obstacleDistance({c.x, c.y - s, c.yaw});
  return {config_.eband_external_force_gain * fx / (2.0 * s), config_.eband_external_force_gain * fy / (2.0 * s), 0.0};
}

Eigen::Vector3d ElasticBand::forcesAt(std::size_t i, const std::vector<EbandBubble>& band,
                                      const EbandBubble& bubble) const {
  Eigen::Vector3d force = internalForce(i, band, bubble) + externalForce(bubble);
  // suppressTangentialForces: only the part across the band (the direction from the previous
  // to the next bubble, in the same (x, y, R_c yaw) space) moves a bubble. Upstream divides
  // by the direction's squared length unguarded; when the two neighbours coincide exactly
  // (never seen in practice) that is 0 / 0 and the force is left whole here instead.
  const Eigen::Vector3d along = difference(band[i - 1].center, band[i + 1].center);
  const double length2 = along.squaredNorm();
  if (length2 > 0.0) force -= (force.dot(along) / length2) * along;
  return force;
}

bool ElasticBand::reversesSignificantly(const Eigen::Vector3d& after, const Eigen::Vector3d& before) const {
  if (after.dot(before) >= 0.0) return false;
  // Upstream's norm of the earlier force squares its x twice and leaves out its y.
  const double before_norm = std::sqrt(before.x() * before.x() + before.x() * before.x() + before.z() * before.z());
  const double after_norm = after.norm();
  return after_norm > config_.eband_equilibrium_relative_overshoot * before_norm &&
         after_norm > config_.eband_significant_force_lower_bound;
}

bool ElasticBand::moveApproximateEquilibrium(std::size_t i, const std::vector<EbandBubble>& band, EbandBubble& bubble,
                                             const Eigen::Vector3d& bubble_force, const Eigen::Vector3d& step,
                                             int depth) const {
  // One step of the search; `bubble` becomes the candidate when it is not in collision, and
  // the search goes on from there with half the step: back if the force reversed
  // significantly, on if it did not reverse, not at all if it reversed insignificantly. A
  // deeper step that fails leaves the candidate of this one.
  EbandBubble candidate = bubble;
  candidate.center = {bubble.center.x + step.x(), bubble.center.y + step.y(), core::wrapAngle(bubble.center.yaw + step.z())};
  candidate.expansion = obstacleDistance(candidate.center);
  if (candidate.expansion == 0.0) return false;
  const Eigen::Vector3d candidate_force = forcesAt(i, band, candidate);
  bubble = candidate;
  if (depth >= config_.eband_equilibrium_approx_max_recursion_depth) return true;
  if (candidate_force.dot(bubble_force) < 0.0) {
    // The recursion's overshoot test is assumed to be applyForces' (a copy upstream), with
    // its norm.
    if (reversesSignificantly(candidate_force, bubble_force))
      moveApproximateEquilibrium(i, band, bubble, candidate_force, -0.5 * step, depth + 1);
  } else {
    moveApproximateEquilibrium(i, band, bubble, candidate_force, 0.5 * step, depth + 1);
  }
  return true;
}

void ElasticBand::applyForces(std::size_t i, std::vector<EbandBubble>& band, const Eigen::Vector3d& force) const {
  // The step is the force times the bubble's radius (the yaw part through R_c).
  const EbandBubble& old = band[i];
  const Eigen::Vector3d jump(old.expansion * force.x(), old.expansion * force.y(),
                             core::wrapAngle(old.expansion / circumscribed_radius_ * force.z()));
  EbandBubble moved = old;
  moved.center = {old.center.x + jump.x(), old.center.y + jump.y(), core::wrapAngle(old.center.yaw + jump.z())};
  moved.expansion = obstacleDistance(moved.center);
  if (moved.expansion <= config_.eband_tiny_bubble_expansion) return;  // into collision: not moved
  const Eigen::Vector3d moved_force = forcesAt(i, band, moved);
  if (reversesSignificantly(moved_force, force)) {
    // Overshot: search the equilibrium from the old pose with half the step; if even its
    // first step is in collision, the full step stands.
    EbandBubble candidate = old;
    if (moveApproximateEquilibrium(i, band, candidate, force, 0.5 * jump, 0)) moved = candidate;
  }
  // The moved bubble must stay connected to both neighbours, directly or through a gap that
  // can be filled (tried on copies; the filled bubbles are not kept, the next refinement
  // fills them again).
  const auto connected = [&](std::size_t first) {
    if (overlap(first == i ? moved : band[first], first + 1 == i ? moved : band[first + 1])) return true;
    std::vector<EbandBubble> copy = band;
    copy[i] = moved;
    std::size_t end = first + 1;
    return fillGap(copy, first, end);
  };
  if (!connected(i - 1) || !connected(i)) return;
  band[i] = moved;
}

void ElasticBand::modifyBandArtificialForce(std::vector<EbandBubble>& band) const {
  // One sweep forward and one back (the last inner bubble twice), ends fixed, each bubble
  // moved with the forces of its already moved neighbours.
  if (band.size() <= 2) return;
  std::size_t i = 1;
  bool forward = true;
  while (i > 0 && i < band.size() - 1) {
    const Eigen::Vector3d force = forcesAt(i, band, band[i]);
    applyForces(i, band, force);
    if (forward) {
      ++i;
      if (i == band.size() - 1) {
        forward = false;
        --i;
      }
    } else {
      --i;
    }
  }
}

bool ElasticBand::optimizeBand(std::vector<EbandBubble>& band) const {
  if (band.empty()) return false;
  for (EbandBubble& bubble : band) {
    bubble.expansion = obstacleDistance(bubble.center);
    if (bubble.expansion == 0.0) return false;  // a bubble in collision: the band is invalid
  }
  if (!refineBand(band)) return false;
  for (int k = 0; k < config_.num_iterations_eband_optimization; ++k) {
    modifyBandArtificialForce(band);
    if (!refineBand(band)) return false;
  }
  return true;
}

bool ElasticBand::optimize() {
  std::vector<EbandBubble> band = band_;
  if (!optimizeBand(band)) return false;
  band_ = std::move(band);
  return true;
}

bool ElasticBand::setPlan(const std::vector<core::Pose2>& poses) {
  std::vector<EbandBubble> band;
  if (!convertPlanToBand(poses, band)) return false;
  if (!refineBand(band)) return false;
  band_ = std::move(band);
  return true;
}

bool ElasticBand::addFrames(const std::vector<core::Pose2>& poses, bool at_front) {
  if (band_.empty() || poses.empty()) return false;
  std::vector<EbandBubble> added;
  if (!convertPlanToBand(poses, added)) return false;
  const std::size_t n = band_.size();
  std::vector<EbandBubble> joined = added;
  if (at_front) {
    // The farthest bubble the last new one overlaps; the ones before it are passed.
    for (std::size_t k = n; k-- > 0;)
      if (overlap(added.back(), band_[k])) {
        joined.insert(joined.end(), band_.begin() + static_cast<std::ptrdiff_t>(k), band_.end());
        std::size_t end = added.size();
        removeAndFill(joined, added.size() - 1, end);  // they overlap: nothing to do
        band_ = std::move(joined);
        return true;
      }
    joined.insert(joined.end(), band_.begin(), band_.end());
    std::size_t end = added.size();
    if (!fillGap(joined, added.size() - 1, end)) return false;
  } else {
    // The first bubble (the last excluded) the first new one overlaps; the ones after it go.
    for (std::size_t k = 0; k + 1 < n; ++k)
      if (overlap(added.front(), band_[k])) {
        joined.insert(joined.begin(), band_.begin(), band_.begin() + static_cast<std::ptrdiff_t>(k + 1));
        std::size_t end = k + 1;
        removeAndFill(joined, k, end);
        band_ = std::move(joined);
        return true;
      }
    joined.insert(joined.begin(), band_.begin(), band_.end());
    std::size_t end = n;
    if (!fillGap(joined, n - 1, end)) return false;
  }
  band_ = std::move(joined);
  return true;
}

// ---------------------------------------------------------------------------------------------
// EbandController (EBandPlannerROS + EBandTrajectoryCtrl on move_base)

EbandController::EbandController(const EbandConfig& config)
    : config_(config),
      nav_(config.nav),
      move_base_(config.recovery),
      band_(config, config.nav.circumscribedRadius()) {}

void EbandController::reset(const EpisodeInfo& info) {
  info_ = info;
  nav_.reset(info.goal);
  move_base_.reset();
  band_.clear();
  plan_.clear();
  plan_start_count_ = plan_end_count_ = 0;
  plans_seen_ = 0;
  in_final_goal_turn_ = false;
  goal_reached_ = false;
  turning_ = false;
  costmap_resets_ = 0;
}

std::string_view EbandController::stateLabel() const {
  switch (move_base_.mode()) {
    case MoveBase::Mode::Controlling: return goal_reached_ ? "goal" : turning_ ? "turning" : "driving";
    case MoveBase::Mode::WaitingForPlan: return "waiting";
    case MoveBase::Mode::RecoveryRotate: return "recovery";
    case MoveBase::Mode::Aborted: return "aborted";
  }
  return "";
}

std::vector<core::Pose2> EbandController::windowPlan(const core::Pose2& robot, int& start_count, int& end_count) const {
  // Half of the local costmap's larger side as costmap_2d reports it ((cells - 1 + 0.5) res).
  const nav::Costmap& map = nav_.localCostmap();
  const double size = (std::max(map.widthCells(), map.heightCells()) - 0.5) * map.resolution();
  const double threshold2 = 0.25 * size * size;
  const int n = static_cast<int>(plan_.size());
  const auto distance2 = [&](int i) {
    const double dx = robot.x - plan_[static_cast<std::size_t>(i)].x, dy = robot.y - plan_[static_cast<std::size_t>(i)].y;
    return dx * dx + dy * dy;
  };
  std::vector<core::Pose2> window;
  int i = std::max(0, n - start_count);
  double d2 = std::numeric_limits<double>::max();
  while (i < n && d2 > threshold2) {
    d2 = distance2(i);
    if (d2 > threshold2) ++i;
    else start_count = n - i;
  }
  while (i < n && d2 < threshold2) {
    d2 = distance2(i);
    window.push_back(plan_[static_cast<std::size_t>(i)]);
    end_count = n - i;
    ++i;
  }
  return window;
}

bool EbandController::setPlan(const core::Pose2& robot) {
  plan_.clear();
  for (const Eigen::Vector2d& p : nav_.path()) plan_.push_back({p.x(), p.y(), kPlanYaw});
  int start_count = static_cast<int>(plan_.size()), end_count = start_count;
  const std::vector<core::Pose2> window = windowPlan(robot, start_count, end_count);
  if (window.empty()) return false;
  if (!band_.setPlan(window)) {
    // Upstream's answer to plans through obstacles of the local costmap (its issue #5): reset
    // the local costmap (until its next update, the next cycle here) and try once more.
    nav_.resetLocalCostmap();
    ++costmap_resets_;
    band_.setCostmap(nav_.localCostmap());
    if (!band_.setPlan(window)) return false;
  }
  plan_start_count_ = start_count;
  plan_end_count_ = end_count;
  band_.optimize();  // upstream ignores the result
  return true;
}

std::optional<core::Twist> EbandController::computeVelocityCommands(const core::Pose2& robot) {
  if (band_.bubbles().empty()) return std::nullopt;
  // The robot joins the band at the front (fails with its centre inscribed or lethal).
  if (!band_.addFrames({robot}, true)) return std::nullopt;
  // Plan poses that entered the window join at the back. The counters are kept only when
  // that worked, so a failed append is tried again next cycle (upstream's order; an
  // assumption where the note is silent).
  int start_count = plan_start_count_, end_count = plan_end_count_;
  const std::vector<core::Pose2> window = windowPlan(robot, start_count, end_count);
  if (window.empty()) return std::nullopt;
  if (end_count < plan_end_count_) {
    const std::size_t added = std::min(window.size(), static_cast<std::size_t>(plan_end_count_ - end_count));
    const std::vector<core::Pose2> poses(window.end() - static_cast<std::ptrdiff_t>(added), window.end());
    if (!band_.addFrames(poses, false)) return std::nullopt;
  }
  plan_start_count_ = start_count;
  plan_end_count_ = end_count;
  if (!band_.optimize()) return std::nullopt;
  const Command command = commandFor(band_.bubbles());
  turning_ = command.turning_in_place;
  if (command.goal_reached) goal_reached_ = true;
  return command.twist;
}

EbandController::Command EbandController::commandFor(const std::vector<EbandBubble>& band) {
  Command command;
  if (band.size() < 2) return command;
  const core::Pose2& robot = band.front().center;
  const auto inRobotFrame = [&](const EbandBubble& b) { return robot.inverseTransform(b.center.position()); };
  const auto clampTurn = [&](double w) { return std::clamp(w, -config_.max_vel_th, config_.max_vel_th); };

  // Goal: the band's end within 0.6 of the xy tolerance on both axes (or still turning to
  // it): turn to its yaw, then report the goal reached. Leaving the tolerance box ends the
  // final turn unless hysteresis is disallowed.
  const Eigen::Vector2d to_end = inRobotFrame(band.back());
  const double tol = config_.xy_goal_tolerance;
  if (!config_.disallow_hysteresis && (std::abs(to_end.x()) > tol || std::abs(to_end.y()) > tol))
    in_final_goal_turn_ = false;
  if ((std::abs(to_end.x()) <= 0.6 * tol && std::abs(to_end.y()) <= 0.6 * tol) || in_final_goal_turn_) {
    const double error = core::wrapAngle(band.back().center.yaw - robot.yaw);
    if (std::abs(error) > config_.yaw_goal_tolerance) {
      in_final_goal_turn_ = true;
      command.twist.angular = clampTurn(sign(error) * config_.min_in_place_vel_th + config_.k_prop * error);
      command.turning_in_place = true;
      return command;
    }
    command.goal_reached = true;
    return command;
  }

  // Align: rotate in place while the next bubble lies outside the cone its drivable radius
  // spans.
  const EbandBubble& next = band[1];
  const Eigen::Vector2d to_next = inRobotFrame(next);
  const double bearing = std::atan2(to_next.y(), to_next.x());
  const double distance = to_next.norm();
  const double threshold =
      config_.rotation_threshold_multiplier * std::abs(std::atan2(kBubbleRadiusFraction * next.expansion, distance));
  if (std::abs(bearing) > threshold) {
    double w = config_.k_prop * bearing;
    if (std::abs(w) < config_.min_in_place_vel_th) w = sign(w) * config_.min_in_place_vel_th;
    command.twist.angular = clampTurn(w);
    command.turning_in_place = true;
    return command;
  }

  // Drive: speed from the robot bubble's radius, halved limit near the band's end, slowed by
  // the bearing; clamped to [min, max] (the unhalved max) with the sign of the next bubble's
  // forward offset.
  double limit = config_.max_vel_lin;
  if (to_end.norm() < kSlowDownDistance) limit = config_.max_vel_lin < 0.3 ? 0.15 : config_.max_vel_lin / 2.0;
  double v = config_.bubble_velocity_multiplier * (kBubbleRadiusFraction * band.front().expansion) * limit *
             std::cos(bearing);
  if (std::abs(v) > config_.max_vel_lin) v = sign(to_next.x()) * config_.max_vel_lin;
  if (std::abs(v) < config_.min_vel_lin) v = sign(to_next.x()) * config_.min_vel_lin;
  double w = config_.k_prop * bearing;
  if (std::abs(w) < config_.min_vel_th) w = sign(w) * config_.min_vel_th;
  command.twist = {v, clampTurn(w)};
  return command;
}

core::Twist EbandController::act(const Observation& obs) {
  const core::Pose2 pose = obs.odom_pose;
  nav_.update(obs.time, *obs.scan, info_.lidar.sensorPose(obs.scan_odom_pose), pose);

  if (goal_reached_) return {};  // move_base succeeded (BARN's episode ends 1 m before)
  if (const auto command = move_base_.beforeController(obs, nav_)) return *command;
  band_.setCostmap(nav_.localCostmap());
  // A plan the global planner found since the last cycle is handed over first.
  if (nav_.lastPlanFound() && nav_.plansMade() != plans_seen_) {
    plans_seen_ = nav_.plansMade();
    if (!setPlan(pose)) {
      move_base_.abort();  // "Failed to pass global plan to the controller"
      return {};
    }
  }
  return move_base_.afterController(obs, nav_, computeVelocityCommands(pose));
}

}  // namespace barn::controllers
