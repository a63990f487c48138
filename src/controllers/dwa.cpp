#include "barn/controllers/dwa.hpp"

#include <algorithm>
#include <cmath>
#include <limits>
#include <numbers>

#include "barn/nav/grid_line.hpp"

namespace barn::controllers {

namespace {

// Moves `value` toward `target` by at most `step` (the roll-out's acceleration limit).
double approach(double value, double target, double step) {
  return value < target ? std::min(target, value + step) : std::max(target, value - step);
}

}  // namespace

void validate(const DwaConfig& c, core::Errors& errors, const std::string& prefix) {
  errors.check(c.rate > 0.0, prefix + ".rate", "must be > 0");
  errors.check(c.max_vel_x > 0.0, prefix + ".max_vel_x", "must be > 0");
  errors.check(c.min_vel_x >= 0.0 && c.min_vel_x <= c.max_vel_x, prefix + ".min_vel_x", "must be in [0, max_vel_x]");
  errors.check(c.max_vel_theta > 0.0, prefix + ".max_vel_theta", "must be > 0");
  errors.check(c.min_in_place_vel_theta >= 0.0, prefix + ".min_in_place_vel_theta", "must be >= 0");
  errors.check(c.acc_lim_x > 0.0, prefix + ".acc_lim_x", "must be > 0");
  errors.check(c.acc_lim_theta > 0.0, prefix + ".acc_lim_theta", "must be > 0");
  errors.check(c.sim_time > 0.0, prefix + ".sim_time", "must be > 0");
  errors.check(c.sim_granularity > 0.0, prefix + ".sim_granularity", "must be > 0");
  errors.check(c.angular_sim_granularity > 0.0, prefix + ".angular_sim_granularity", "must be > 0");
  errors.check(c.vx_samples >= 2, prefix + ".vx_samples", "must be >= 2");
  errors.check(c.vtheta_samples >= 2, prefix + ".vtheta_samples", "must be >= 2");
  errors.check(c.pdist_scale >= 0.0 && c.gdist_scale >= 0.0 && c.occdist_scale >= 0.0, prefix + ".pdist_scale",
               "the scoring scales must be >= 0");
  errors.check(c.scoring_window > 0.0, prefix + ".scoring_window", "must be > 0");
  errors.check(c.escape_vel < 0.0, prefix + ".escape_vel", "must be < 0 (backwards)");
  errors.check(c.recovery.controller_patience > 0.0, prefix + ".recovery.controller_patience", "must be > 0");
  errors.check(c.escape_reset_dist > 0.0, prefix + ".escape_reset_dist", "must be > 0");
  errors.check(c.escape_reset_theta > 0.0, prefix + ".escape_reset_theta", "must be > 0");
  errors.check(c.recovery.max_rotation_speed > 0.0, prefix + ".recovery.max_rotation_speed", "must be > 0");
  errors.check(c.recovery.min_rotation_speed > 0.0 && c.recovery.min_rotation_speed <= c.recovery.max_rotation_speed,
               prefix + ".recovery.min_rotation_speed", "must be in (0, max_rotation_speed]");
  errors.check(c.recovery.rotation_acceleration > 0.0, prefix + ".recovery.rotation_acceleration", "must be > 0");
  errors.check(c.recovery.rotation_tolerance > 0.0, prefix + ".recovery.rotation_tolerance", "must be > 0");
  errors.check(c.recovery.sweep_step > 0.0, prefix + ".recovery.sweep_step", "must be > 0");
  nav::validate(c.nav, errors, prefix + ".nav");
}

DwaController::DwaController(const DwaConfig& config)
    : config_(config), nav_(config.nav), footprint_(nav_.paddedFootprint()) {}

void DwaController::reset(const EpisodeInfo& info) {
  info_ = info;
  nav_.reset(info.goal);
  mode_ = Mode::Planning;
  last_valid_time_ = 0.0;
  recovery_index_ = 0;
  rotated_ = 0.0;
  escaping_ = false;
  rotating_left_ = rotating_right_ = stuck_left_ = stuck_right_ = false;
  last_rotation_position_ = Eigen::Vector2d::Zero();  // upstream starts prev_x_, prev_y_ at 0
}

std::string_view DwaController::stateLabel() const {
  switch (mode_) {
    case Mode::Planning: return escaping_ ? "escaping" : "planning";
    case Mode::RecoveryRotate: return "recovery";
    case Mode::GaveUp: return "aborted";
  }
  return "";
}

double DwaController::footprintCost(double x, double y, double theta) const {
  // CostmapModel::footprintCost: only the padded outline is walked (lethal or unknown: -1,
  // a corner off the map: -1); the highest cost on it otherwise. Inscribed (253) is legal.
  const nav::Costmap& map = nav_.localCostmap();
  const double c = std::cos(theta), s = std::sin(theta);
  nav::CellIndex corners[4];
  for (int k = 0; k < 4; ++k) {
    const Eigen::Vector2d& p = footprint_[static_cast<std::size_t>(k)];
    if (!map.toCell({x + c * p.x() - s * p.y(), y + s * p.x() + c * p.y()}, corners[k])) return -1.0;
  }
  int worst = 0;
  for (int k = 0; k < 4; ++k) {
    const nav::CellIndex a = corners[k], b = corners[(k + 1) % 4];
    const bool clear = nav::walkLine(a.x, a.y, b.x, b.y, [&](int cx, int cy) {
      const std::uint8_t cost = map.cost(cx, cy);
      if (cost == nav::kLethalCost || cost == nav::kUnknownCost) return false;
      worst = std::max(worst, static_cast<int>(cost));
      return true;
    });
    if (!clear) return -1.0;
  }
  return worst;
}

void DwaController::updateDistanceMaps(const core::Pose2& pose) {
  // MapGrid: 4-connected breadth-first wavefronts on the local costmap from the global path
  // (its first run of points inside the map, starting at the point nearest the robot, up to
  // the first point beyond the window) and from the local goal (that run's last point).
  // Inscribed, lethal and unknown cells get obstacle_distance_ when reached and are not
  // expanded, except, in the path map, cells under the robot's padded footprint.
  // The wavefronts cover +-scoring_window around the robot (ROS: the whole local map).
  const nav::Costmap& map = nav_.localCostmap();
  const int w = map.widthCells(), h = map.heightCells();
  const std::size_t n = static_cast<std::size_t>(w) * static_cast<std::size_t>(h);
  obstacle_distance_ = static_cast<int>(n);
  nav::CellIndex robot;
  map.toCell(pose.position(), robot);
  const int reach = static_cast<int>(std::ceil(config_.scoring_window / map.resolution()));
  const int wx0 = std::max(0, robot.x - reach), wx1 = std::min(w - 1, robot.x + reach);
  const int wy0 = std::max(0, robot.y - reach), wy1 = std::min(h - 1, robot.y + reach);
  blocked_.assign(n, 1);
  for (int y = wy0; y <= wy1; ++y)
    for (int x = wx0; x <= wx1; ++x) blocked_[static_cast<std::size_t>(y * w + x)] = map.cost(x, y) >= nav::kInscribedCost;
  within_robot_.assign(n, 0);
  std::vector<Eigen::Vector2d> outline;
  for (const Eigen::Vector2d& corner : footprint_) outline.push_back(pose.transform(corner));
  for (const nav::CellIndex& cell : map.polygonCells(outline)) within_robot_[static_cast<std::size_t>(cell.y * w + cell.x)] = 1;

  const int unreached = obstacle_distance_ + 1;
  const auto inWindow = [&](const nav::CellIndex& c) { return c.x >= wx0 && c.x <= wx1 && c.y >= wy0 && c.y <= wy1; };
  const auto wavefront = [&](std::vector<int>& distance, const std::vector<int>& seeds, bool pass_robot) {
    distance.assign(n, unreached);
    queue_.clear();
    for (int i : seeds) {
      if (distance[static_cast<std::size_t>(i)] == 0) continue;
      distance[static_cast<std::size_t>(i)] = 0;  // a seed counts whatever its cost
      queue_.push_back(i);
    }
    for (std::size_t head = 0; head < queue_.size(); ++head) {
      const int i = queue_[head];
      const int x = i % w, y = i / w;
      const int next = distance[static_cast<std::size_t>(i)] + 1;
      const auto visit = [&](int j) {
        const std::size_t at = static_cast<std::size_t>(j);
        if (distance[at] != unreached) return;
        if (blocked_[at] && !(pass_robot && within_robot_[at])) {
          distance[at] = obstacle_distance_;
          return;
        }
        distance[at] = next;
        queue_.push_back(j);
      };
      if (x > wx0) visit(i - 1);
      if (x < wx1) visit(i + 1);
      if (y > wy0) visit(i - w);
      if (y < wy1) visit(i + w);
    }
  };
  std::vector<int> path_cells;
  int goal_cell = -1;
  if (nav_.hasPath()) {
    // The path densified to one point per cell length, so every cell it crosses is a seed.
    const nav::Path& path = nav_.path();
    const double res = map.resolution();
    const auto seed = [&](const Eigen::Vector2d& p) {
      nav::CellIndex cell;
      if (!map.toCell(p, cell) || !inWindow(cell) || map.cost(cell.x, cell.y) == nav::kUnknownCost) return false;
      const int at = cell.y * w + cell.x;
      if (path_cells.empty() || path_cells.back() != at) path_cells.push_back(at);
      goal_cell = at;
      return true;
    };
    bool inside = true;
    const std::size_t first = nav::closestIndex(path, pose.position());
    for (std::size_t i = first; i < path.size() && inside; ++i) {
      if (i > first) {
        const Eigen::Vector2d a = path[i - 1], b = path[i];
        const int steps = static_cast<int>(std::ceil((b - a).norm() / res));
        for (int k = 1; k < steps && inside; ++k) inside = seed(a + (b - a) * (static_cast<double>(k) / steps));
      }
      if (inside) inside = seed(path[i]);
    }
  }
  wavefront(path_distance_, path_cells, true);
  wavefront(goal_distance_, goal_cell >= 0 ? std::vector<int>{goal_cell} : std::vector<int>{}, false);
}

DwaTrajectory DwaController::rollOut(const core::Pose2& pose, const core::Twist& velocity, double vx,
                                     double vtheta) const {
  // TrajectoryPlanner::generateTrajectory: steps of sim_granularity metres (or of
  // angular_sim_granularity per rad/s of yaw rate), the velocity approaching the sample at the
  // acceleration limits, every point checked; the distances of the last point count.
  const int steps = std::max(1, static_cast<int>(std::max(std::abs(vx) * config_.sim_time / config_.sim_granularity,
                                                          std::abs(vtheta) / config_.angular_sim_granularity) + 0.5));
  const double dt = config_.sim_time / steps;
  const nav::Costmap& map = nav_.localCostmap();
  const int w = map.widthCells();
  DwaTrajectory trajectory{vx, vtheta, -1.0, pose};
  double x = pose.x, y = pose.y, theta = pose.yaw;
  double v = velocity.linear, omega = velocity.angular;
  int occupancy = 0, path_cells = 0, goal_cells = 0;
  for (int i = 0; i < steps; ++i) {
    nav::CellIndex cell;
    if (!map.toCell({x, y}, cell)) return trajectory;
    const double outline = footprintCost(x, y, theta);
    if (outline < 0.0) return trajectory;
    occupancy = std::max({occupancy, static_cast<int>(outline), static_cast<int>(map.cost(cell.x, cell.y))});
    const std::size_t at = static_cast<std::size_t>(cell.y * w + cell.x);
    path_cells = path_distance_.empty() ? obstacle_distance_ : path_distance_[at];
    goal_cells = goal_distance_.empty() ? obstacle_distance_ : goal_distance_[at];
    if (path_cells >= obstacle_distance_ || goal_cells >= obstacle_distance_) {
      trajectory.cost = -2.0;
      return trajectory;
    }
    trajectory.end = {x, y, theta};
    v = approach(v, vx, config_.acc_lim_x * dt);
    omega = approach(omega, vtheta, config_.acc_lim_theta * dt);
    x += v * std::cos(theta) * dt;
    y += v * std::sin(theta) * dt;
    theta += omega * dt;
  }
  // The path and goal weights count per metre under meter_scoring; the occupancy weight is
  // never scaled.
  const double distance_unit = config_.meter_scoring ? map.resolution() : 1.0;
  trajectory.cost = distance_unit * (config_.pdist_scale * path_cells + config_.gdist_scale * goal_cells) +
                    config_.occdist_scale * occupancy;
  return trajectory;
}

DwaTrajectory DwaController::findBestPath(const core::Pose2& pose, const core::Twist& velocity) {
  // The window spans one control period (dwa mode); samples by repeated addition, as upstream.
  const double period = 1.0 / config_.rate;
  const double max_x = std::max(std::min(config_.max_vel_x, velocity.linear + config_.acc_lim_x * period), config_.min_vel_x);
  const double min_x = std::max(config_.min_vel_x, velocity.linear - config_.acc_lim_x * period);
  const double max_th = std::min(config_.max_vel_theta, velocity.angular + config_.acc_lim_theta * period);
  const double min_th = std::max(-config_.max_vel_theta, velocity.angular - config_.acc_lim_theta * period);
  const double dvx = (max_x - min_x) / (config_.vx_samples - 1);
  const double dvth = (max_th - min_th) / (config_.vtheta_samples - 1);

  DwaTrajectory best;
  // Forward arcs (not while escaping): the straight sample first, then vtheta_samples - 1 turn
  // rates from the bottom of the window (its top is never tried); ties keep the earlier one.
  if (!escaping_) {
    double vx = min_x;
    for (int i = 0; i < config_.vx_samples; ++i, vx += dvx) {
      const auto consider = [&](double vth) {
        const DwaTrajectory t = rollOut(pose, velocity, vx, vth);
        if (t.cost >= 0.0 && (best.cost < 0.0 || t.cost < best.cost)) best = t;
      };
      consider(0.0);
      double vth = min_th;
      for (int j = 0; j < config_.vtheta_samples - 1; ++j, vth += dvth) consider(vth);
    }
  }
  // In place: a rotation replaces the best arc if it costs no more and the point
  // heading_lookahead ahead of its end is nearer the local goal than the rotations taken so
  // far. stuck_right (turned clockwise on two cycles without moving) locks out
  // counter-clockwise turns, stuck_left clockwise ones.
  const nav::Costmap& map = nav_.localCostmap();
  double heading_distance = std::numeric_limits<double>::max();
  double sample = min_th;
  for (int j = 0; j < config_.vtheta_samples; ++j, sample += dvth) {
    const double vth = sample > 0 ? std::max(sample, config_.min_in_place_vel_theta)
                                  : std::min(sample, -config_.min_in_place_vel_theta);
    const DwaTrajectory t = rollOut(pose, velocity, 0.0, vth);
    if (t.cost < 0.0 || !(best.cost < 0.0 || t.cost <= best.cost) || !(std::abs(sample) > dvth)) continue;
    nav::CellIndex ahead;
    const Eigen::Vector2d look = t.end.position() + config_.heading_lookahead * Eigen::Vector2d(std::cos(t.end.yaw), std::sin(t.end.yaw));
    if (!map.toCell(look, ahead)) continue;
    const double ahead_distance = goal_distance_[static_cast<std::size_t>(ahead.y * map.widthCells() + ahead.x)];
    if (!(ahead_distance < heading_distance)) continue;
    if ((sample < 0 && !stuck_left_) || (sample > 0 && !stuck_right_)) {
      best = t;
      heading_distance = ahead_distance;
    }
  }

  const auto clearOscillationIfMoved = [&] {
    if ((pose.position() - last_rotation_position_).norm() > config_.oscillation_reset_dist)
      rotating_left_ = rotating_right_ = stuck_left_ = stuck_right_ = false;
  };
  const auto checkEscapeDone = [&] {
    if ((pose.position() - escape_pose_.position()).norm() > config_.escape_reset_dist ||
        std::abs(core::wrapAngle(pose.yaw - escape_pose_.yaw)) > config_.escape_reset_theta)
      escaping_ = false;
  };
  if (best.cost >= 0.0) {
    if (!(best.vx > 0.0)) {
      if (best.vtheta < 0) {
        if (rotating_right_) stuck_right_ = true;
        rotating_right_ = true;
      } else if (best.vtheta > 0) {
        if (rotating_left_) stuck_left_ = true;
        rotating_left_ = true;
      }
      last_rotation_position_ = pose.position();
    }
    clearOscillationIfMoved();
    checkEscapeDone();
    return best;
  }
  // Nothing forward or in place is legal: back up at escape_vel whatever the map says behind
  // ("backing up slowly is allowed even when the map shows it blocked"); only a back-up with
  // no way on from its points (-2) leaves the robot standing.
  DwaTrajectory escape = rollOut(pose, velocity, config_.escape_vel, 0.0);
  clearOscillationIfMoved();
  if (!escaping_ && escape.cost > -2.0) {
    escaping_ = true;
    escape_pose_ = pose;
  }
  checkEscapeDone();
  if (escape.cost == -1.0) escape.cost = 1.0;
  return escape;
}

bool DwaController::sweepClear(const core::Pose2& pose, double sweep) const {
  for (double turned = 0.0; turned <= sweep; turned += config_.recovery.sweep_step)
    if (footprintCost(pose.x, pose.y, pose.yaw + turned) < 0.0) return false;
  return true;
}

core::Twist DwaController::recover(const Observation& obs) {
  // move_base runs its recoveries in order, each after a failing controller cycle, until
  // one lets the controller find a command again; after the last it aborts the goal.
  const core::Pose2& pose = obs.odom_pose;
  const DwaRecoveryConfig& r = config_.recovery;
  if (mode_ == Mode::RecoveryRotate) {
    rotated_ += std::abs(core::wrapAngle(pose.yaw - last_yaw_));
    last_yaw_ = pose.yaw;
    const double remaining = 2.0 * std::numbers::pi - rotated_;
    if (remaining > r.rotation_tolerance && sweepClear(pose, remaining)) {
      const double speed = std::clamp(std::sqrt(2.0 * r.rotation_acceleration * remaining), r.min_rotation_speed,
                                      r.max_rotation_speed);
      return {0.0, speed};
    }
    mode_ = Mode::Planning;  // the turn is done (or would hit): plan again
    nav_.replan(pose);
    return {};
  }
  if (recovery_index_ >= 4) {
    mode_ = Mode::GaveUp;
    return {};
  }
  const int step = recovery_index_++;
  if (step % 2 == 0) {
    if (r.clear_costmaps) {
      const double keep = step == 0 ? r.conservative_reset_distance : r.aggressive_reset_distance;
      nav_.mutableGlobalCostmap().clearOutside(pose.position(), keep);
      nav_.mutableLocalCostmap().clearOutside(pose.position(), keep);
    }
    nav_.replan(pose);
    return {};
  }
  mode_ = Mode::RecoveryRotate;
  rotated_ = 0.0;
  last_yaw_ = pose.yaw;
  return recover(obs);
}

core::Twist DwaController::act(const Observation& obs) {
  const core::Pose2 pose = obs.odom_pose;
  const core::Pose2 sensor{pose.transform({info_.lidar.mount_x, info_.lidar.mount_y}).x(),
                           pose.transform({info_.lidar.mount_x, info_.lidar.mount_y}).y(), pose.yaw};
  nav_.update(obs.time, *obs.scan, sensor, pose);

  if (mode_ == Mode::GaveUp) return {};
  if (mode_ == Mode::RecoveryRotate) {
    const core::Twist turn = recover(obs);
    if (mode_ == Mode::RecoveryRotate) return turn;
  }
  updateDistanceMaps(pose);
  const DwaTrajectory best = findBestPath(pose, obs.odom_twist);
  if (best.cost >= 0.0) {
    last_valid_time_ = obs.time;
    recovery_index_ = 0;
    return {best.vx, best.vtheta};
  }
  // move_base: a failed cycle publishes zero; after controller_patience, the recoveries.
  if (config_.recovery.enabled && obs.time - last_valid_time_ >= config_.recovery.controller_patience) return recover(obs);
  return {};
}

}  // namespace barn::controllers
