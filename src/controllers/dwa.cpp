#include "barn/controllers/dwa.hpp"

#include <algorithm>
#include <cmath>
#include <limits>
#include <numbers>

namespace barn::controllers {

namespace {

constexpr int kUnreachable = std::numeric_limits<int>::max();

// Cells of a segment (Bresenham), for the footprint outline check.
template <class Visit>
bool forEachLineCell(int x0, int y0, int x1, int y1, Visit visit) {
  const int dx = std::abs(x1 - x0), dy = -std::abs(y1 - y0);
  const int sx = x0 < x1 ? 1 : -1, sy = y0 < y1 ? 1 : -1;
  int error = dx + dy;
  while (true) {
    if (!visit(x0, y0)) return false;
    if (x0 == x1 && y0 == y1) return true;
    const int e2 = 2 * error;
    if (e2 >= dy) {
      error += dy;
      x0 += sx;
    }
    if (e2 <= dx) {
      error += dx;
      y0 += sy;
    }
  }
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
  errors.check(c.recovery.rotation_speed > 0.0, prefix + ".recovery.rotation_speed", "must be > 0");
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
  rotating_left_ = rotating_right_ = stuck_left_ = stuck_right_ = false;
  oscillation_origin_ = info.start.position();
}

std::string_view DwaController::stateLabel() const {
  switch (mode_) {
    case Mode::Planning: return "planning";
    case Mode::Escaping: return "escaping";
    case Mode::RecoveryRotate: return "recovery";
    case Mode::GaveUp: return "aborted";
  }
  return "";
}

double DwaController::footprintCost(double x, double y, double theta) const {
  const nav::Costmap& map = nav_.localCostmap();
  nav::CellIndex centre;
  if (!map.toCell({x, y}, centre)) return -1.0;
  // As base_local_planner's CostmapModel: only the outline (and the centre) must stay off
  // lethal and unknown cells; inscribed costs only weigh in the score. Obstacles cannot get
  // inside the footprint without crossing its outline first.
  const std::uint8_t centre_cost = map.cost(centre.x, centre.y);
  if (centre_cost == nav::kLethalCost || centre_cost == nav::kUnknownCost) return -1.0;
  // The padded rectangle's outline must not cross an obstacle (costmap_2d footprintCost).
  const double c = std::cos(theta), s = std::sin(theta);
  nav::CellIndex corners[4];
  for (int k = 0; k < 4; ++k) {
    const Eigen::Vector2d& p = footprint_[static_cast<std::size_t>(k)];
    if (!map.toCell({x + c * p.x() - s * p.y(), y + s * p.x() + c * p.y()}, corners[k])) return -1.0;
  }
  double worst = centre_cost;
  for (int k = 0; k < 4; ++k) {
    const nav::CellIndex a = corners[k], b = corners[(k + 1) % 4];
    const bool clear = forEachLineCell(a.x, a.y, b.x, b.y, [&](int cx, int cy) {
      const std::uint8_t cost = map.cost(cx, cy);
      if (cost == nav::kLethalCost || cost == nav::kUnknownCost) return false;
      worst = std::max(worst, static_cast<double>(cost));
      return true;
    });
    if (!clear) return -1.0;
  }
  return worst;
}

void DwaController::updateDistanceMaps(const core::Pose2& pose) {
  // MapGrid: 4-connected wavefronts from the global path (pruned to what lies ahead of the
  // robot) and from the local goal (its last point inside the window).
  // The wavefronts cover a window of +-scoring_window around the robot (ROS: the whole local
  // map), which holds every trajectory end; cells outside count as blocked.
  const nav::Costmap& map = nav_.localCostmap();
  const int w = map.widthCells(), h = map.heightCells();
  const std::size_t n = static_cast<std::size_t>(w) * static_cast<std::size_t>(h);
  nav::CellIndex robot;
  map.toCell(pose.position(), robot);
  const int reach = static_cast<int>(std::ceil(config_.scoring_window / map.resolution()));
  const int wx0 = std::max(0, robot.x - reach), wx1 = std::min(w - 1, robot.x + reach);
  const int wy0 = std::max(0, robot.y - reach), wy1 = std::min(h - 1, robot.y + reach);
  blocked_.assign(n, 1);
  for (int y = wy0; y <= wy1; ++y)
    for (int x = wx0; x <= wx1; ++x) blocked_[static_cast<std::size_t>(y * w + x)] = map.cost(x, y) >= nav::kInscribedCost;
  const auto wavefront = [&](std::vector<int>& distance, const std::vector<int>& seeds) {
    distance.assign(n, kUnreachable);
    queue_.clear();
    for (int i : seeds) {
      if (distance[static_cast<std::size_t>(i)] == 0 || blocked_[static_cast<std::size_t>(i)]) continue;
      distance[static_cast<std::size_t>(i)] = 0;
      queue_.push_back(i);
    }
    for (std::size_t head = 0; head < queue_.size(); ++head) {
      const int i = queue_[head];
      const int x = i % w, y = i / w;
      const int next = distance[static_cast<std::size_t>(i)] + 1;
      const auto visit = [&](int j) {
        if (blocked_[static_cast<std::size_t>(j)] || distance[static_cast<std::size_t>(j)] <= next) return;
        distance[static_cast<std::size_t>(j)] = next;
        queue_.push_back(j);
      };
      if (x + 1 < w) visit(i + 1);
      if (x > 0) visit(i - 1);
      if (y + 1 < h) visit(i + w);
      if (y > 0) visit(i - w);
    }
  };
  std::vector<int> path_cells;
  int goal_cell = -1;
  if (nav_.hasPath()) {
    const nav::Path& path = nav_.path();
    for (std::size_t i = nav::closestIndex(path, pose.position()); i < path.size(); ++i) {
      nav::CellIndex cell;
      if (!map.toCell(path[i], cell) || cell.x < wx0 || cell.x > wx1 || cell.y < wy0 || cell.y > wy1) break;
      path_cells.push_back(cell.y * w + cell.x);
      goal_cell = path_cells.back();
    }
  }
  wavefront(path_distance_, path_cells);
  wavefront(goal_distance_, goal_cell >= 0 ? std::vector<int>{goal_cell} : std::vector<int>{});
}

double DwaController::scoreTrajectory(const core::Pose2& pose, double vx, double vtheta) const {
  // TrajectoryPlanner::generateTrajectory: steps of sim_granularity metres (or of
  // angular_sim_granularity per rad/s of yaw rate), every point checked, the score taken at
  // the last one.
  const int steps = std::max(1, static_cast<int>(std::max(std::abs(vx) * config_.sim_time / config_.sim_granularity,
                                                          std::abs(vtheta) / config_.angular_sim_granularity) + 0.5));
  const double dt = config_.sim_time / steps;
  const nav::Costmap& map = nav_.localCostmap();
  const int w = map.widthCells();
  double x = pose.x, y = pose.y, theta = pose.yaw;
  double occupancy = 0.0;
  int path_cells = kUnreachable, goal_cells = kUnreachable;
  for (int i = 0; i < steps; ++i) {
    nav::CellIndex cell;
    if (!map.toCell({x, y}, cell)) return -1.0;
    const double cost = footprintCost(x, y, theta);
    if (cost < 0.0) return -1.0;
    occupancy = std::max({occupancy, cost, static_cast<double>(map.cost(cell.x, cell.y))});
    const std::size_t at = static_cast<std::size_t>(cell.y * w + cell.x);
    path_cells = path_distance_.empty() ? kUnreachable : path_distance_[at];
    goal_cells = goal_distance_.empty() ? kUnreachable : goal_distance_[at];
    if (path_cells == kUnreachable || goal_cells == kUnreachable) return -2.0;  // no way on from here
    x += vx * std::cos(theta) * dt;
    y += vx * std::sin(theta) * dt;
    theta += vtheta * dt;
  }
  // meter_scoring: TrajectoryPlannerROS multiplies all three scales by the resolution, so the
  // distances count in metres and the occupancy term weighs occdist_scale * 0.05 per cost unit.
  const double res = map.resolution();
  return res * (config_.pdist_scale * path_cells + config_.gdist_scale * goal_cells + config_.occdist_scale * occupancy);
}

DwaTrajectory DwaController::bestTrajectory(const core::Pose2& pose, const core::Twist& velocity) {
  const double period = 1.0 / config_.rate;  // dwa: the window spans one control period
  const double max_x = std::min(config_.max_vel_x, velocity.linear + config_.acc_lim_x * period);
  const double min_x = std::max(config_.min_vel_x, velocity.linear - config_.acc_lim_x * period);
  const double max_th = std::min(config_.max_vel_theta, velocity.angular + config_.acc_lim_theta * period);
  const double min_th = std::max(-config_.max_vel_theta, velocity.angular - config_.acc_lim_theta * period);
  const double dvx = (max_x - min_x) / (config_.vx_samples - 1);
  const double dvth = (max_th - min_th) / (config_.vtheta_samples - 1);

  DwaTrajectory best;
  const auto consider = [&](double vx, double vth) {
    const double cost = scoreTrajectory(pose, vx, vth);
    if (cost >= 0.0 && (best.cost < 0.0 || cost < best.cost)) best = {vx, vth, cost};
  };
  if (mode_ != Mode::Escaping && max_x >= min_x) {
    for (int i = 0; i < config_.vx_samples; ++i) {
      const double vx = min_x + i * dvx;
      consider(vx, 0.0);
      for (int j = 0; j < config_.vtheta_samples - 1; ++j) consider(vx, min_th + j * dvth);
    }
  }
  // In place, toward open space: a rotation replaces the best trajectory if it is no worse and
  // the point heading_lookahead ahead of its end is nearer the goal than the rotations taken
  // so far. A direction that was abandoned for the other one since the robot last moved is
  // not tried again (TrajectoryPlanner's stuck_left / stuck_right against oscillation).
  double heading_distance = std::numeric_limits<double>::infinity();
  const nav::Costmap& map = nav_.localCostmap();
  for (int j = 0; j < config_.vtheta_samples; ++j) {
    const double sample = min_th + j * dvth;
    if (!(sample > dvth || sample < -dvth)) continue;  // too slow to turn the base in place
    const double vth = sample > 0 ? std::max(sample, config_.min_in_place_vel_theta)
                                  : std::min(sample, -config_.min_in_place_vel_theta);
    const double cost = scoreTrajectory(pose, 0.0, vth);
    if (cost < 0.0 || !(best.cost < 0.0 || cost <= best.cost)) continue;
    const double end_yaw = pose.yaw + vth * config_.sim_time;
    nav::CellIndex ahead;
    if (!map.toCell(pose.position() + config_.heading_lookahead * Eigen::Vector2d(std::cos(end_yaw), std::sin(end_yaw)), ahead))
      continue;
    const int ahead_cells = goal_distance_[static_cast<std::size_t>(ahead.y * map.widthCells() + ahead.x)];
    const double ahead_distance = ahead_cells == kUnreachable ? std::numeric_limits<double>::infinity() : ahead_cells;
    if (!(ahead_distance < heading_distance)) continue;
    if ((vth < 0 && !stuck_left_) || (vth > 0 && !stuck_right_)) {
      best = {0.0, vth, cost};
      heading_distance = ahead_distance;
    }
  }
  if (best.cost >= 0.0) return best;
  // Nothing forward or in place: try backing out.
  const double escape_cost = scoreTrajectory(pose, config_.escape_vel, 0.0);
  if (escape_cost >= 0.0) return {config_.escape_vel, 0.0, escape_cost};
  return {};
}

void DwaController::updateOscillationFlags(const core::Pose2& pose, const DwaTrajectory& chosen) {
  if (chosen.vx <= 0.0) {
    // Turning back the other way since the robot last moved marks the first way as stuck.
    if (chosen.vtheta < 0) {
      if (rotating_right_) stuck_right_ = true;
      rotating_left_ = true;
    } else if (chosen.vtheta > 0) {
      if (rotating_left_) stuck_left_ = true;
      rotating_right_ = true;
    }
  }
  if ((pose.position() - oscillation_origin_).norm() > config_.oscillation_reset_dist) {
    rotating_left_ = rotating_right_ = stuck_left_ = stuck_right_ = false;
    oscillation_origin_ = pose.position();
  }
}

core::Twist DwaController::act(const Observation& obs) {
  const core::Pose2 pose = obs.odom_pose;
  const core::Pose2 sensor{pose.transform({info_.lidar.mount_x, info_.lidar.mount_y}).x(),
                           pose.transform({info_.lidar.mount_x, info_.lidar.mount_y}).y(), pose.yaw};
  nav_.update(obs.time, *obs.scan, sensor, pose);

  if (mode_ == Mode::GaveUp) return {};
  if (mode_ == Mode::RecoveryRotate) {
    rotated_ += std::abs(core::wrapAngle(pose.yaw - last_yaw_));
    last_yaw_ = pose.yaw;
    const double next_yaw = pose.yaw + config_.recovery.rotation_speed * period();
    if (rotated_ < 2.0 * std::numbers::pi && footprintCost(pose.x, pose.y, next_yaw) >= 0.0)
      return {0.0, config_.recovery.rotation_speed};
    mode_ = Mode::Planning;  // the turn is done (or blocked): plan again with fresh costmaps
    last_valid_time_ = obs.time;
    nav_.replan(pose);
  }

  updateDistanceMaps(pose);
  const DwaTrajectory best = bestTrajectory(pose, obs.odom_twist);
  if (best.cost >= 0.0) {
    updateOscillationFlags(pose, best);
    if (best.vx < 0.0 && mode_ != Mode::Escaping) {
      mode_ = Mode::Escaping;
      escape_start_ = pose.position();
    }
    if (mode_ == Mode::Escaping && (pose.position() - escape_start_).norm() >= config_.escape_reset_dist) mode_ = Mode::Planning;
    last_valid_time_ = obs.time;
    recovery_index_ = 0;
    return {best.vx, best.vtheta};
  }
  if (mode_ == Mode::Escaping) mode_ = Mode::Planning;
  if (config_.recovery.enabled && obs.time - last_valid_time_ >= config_.recovery.controller_patience) {
    // move_base: conservative reset + rotate, then aggressive reset + rotate, then abort.
    if (recovery_index_ >= 2) {
      mode_ = Mode::GaveUp;
      return {};
    }
    const double keep = recovery_index_ == 0 ? config_.recovery.conservative_reset_distance
                                             : config_.recovery.aggressive_reset_distance;
    nav_.mutableGlobalCostmap().clearOutside(pose.position(), keep);
    nav_.mutableLocalCostmap().clearOutside(pose.position(), keep);
    ++recovery_index_;
    mode_ = Mode::RecoveryRotate;
    rotated_ = 0.0;
    last_yaw_ = pose.yaw;
  }
  return {};
}

}  // namespace barn::controllers
