#include "barn/controllers/dwa.hpp"

#include <algorithm>
#include <cmath>
#include <deque>
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
  errors.check(c.escape_vel < 0.0, prefix + ".escape_vel", "must be < 0 (backwards)");
  errors.check(c.footprint_length > 0.0 && c.footprint_width > 0.0, prefix + ".footprint_length", "the footprint must be > 0");
  errors.check(c.recovery.controller_patience > 0.0, prefix + ".recovery.controller_patience", "must be > 0");
  errors.check(c.recovery.rotation_speed > 0.0, prefix + ".recovery.rotation_speed", "must be > 0");
  nav::validate(c.nav, errors, prefix + ".nav");
}

DwaController::DwaController(const DwaConfig& config) : config_(config), nav_(config.nav) {
  const double hx = config.footprint_length / 2 + config.footprint_padding;
  const double hy = config.footprint_width / 2 + config.footprint_padding;
  footprint_ = {{hx, hy}, {-hx, hy}, {-hx, -hy}, {hx, -hy}};
}

void DwaController::reset(const EpisodeInfo& info) {
  info_ = info;
  nav_.reset(info.goal);
  mode_ = Mode::Planning;
  last_valid_time_ = 0.0;
  recovery_index_ = 0;
  rotated_ = 0.0;
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
  const std::uint8_t centre_cost = map.cost(centre.x, centre.y);
  if (centre_cost >= nav::kInscribedCost) return -1.0;  // lethal, inscribed or unknown
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
  // MapGrid: 4-connected wavefronts over the local costmap from the global path (pruned to
  // what lies ahead of the robot) and from the local goal (its last point inside the map).
  const nav::Costmap& map = nav_.localCostmap();
  const int w = map.widthCells(), h = map.heightCells();
  const auto blocked = [&](int x, int y) { return map.cost(x, y) >= nav::kInscribedCost; };
  const auto wavefront = [&](std::vector<int>& distance, const std::vector<nav::CellIndex>& seeds) {
    distance.assign(static_cast<std::size_t>(w) * static_cast<std::size_t>(h), kUnreachable);
    std::deque<nav::CellIndex> queue;
    for (const auto& cell : seeds) {
      int& d = distance[static_cast<std::size_t>(cell.y * w + cell.x)];
      if (d == 0 || blocked(cell.x, cell.y)) continue;
      d = 0;
      queue.push_back(cell);
    }
    constexpr int kSteps[4][2] = {{1, 0}, {-1, 0}, {0, 1}, {0, -1}};
    while (!queue.empty()) {
      const nav::CellIndex cell = queue.front();
      queue.pop_front();
      const int next = distance[static_cast<std::size_t>(cell.y * w + cell.x)] + 1;
      for (const auto& step : kSteps) {
        const int nx = cell.x + step[0], ny = cell.y + step[1];
        if (nx < 0 || ny < 0 || nx >= w || ny >= h || blocked(nx, ny)) continue;
        int& d = distance[static_cast<std::size_t>(ny * w + nx)];
        if (d <= next) continue;
        d = next;
        queue.push_back({nx, ny});
      }
    }
  };
  std::vector<nav::CellIndex> path_cells;
  nav::CellIndex goal_cell{-1, -1};
  if (nav_.hasPath()) {
    const nav::Path& path = nav_.path();
    for (std::size_t i = nav::closestIndex(path, pose.position()); i < path.size(); ++i) {
      nav::CellIndex cell;
      if (!map.toCell(path[i], cell)) break;  // the part of the path inside the local map
      path_cells.push_back(cell);
      goal_cell = cell;
    }
  }
  wavefront(path_distance_, path_cells);
  wavefront(goal_distance_, goal_cell.x >= 0 ? std::vector<nav::CellIndex>{goal_cell} : std::vector<nav::CellIndex>{});
}

double DwaController::scoreTrajectory(const core::Pose2& pose, double vx, double vtheta) const {
  const int steps = std::max(1, static_cast<int>(std::max(std::ceil(std::abs(vx) * config_.sim_time / config_.sim_granularity),
                                                          std::ceil(std::abs(vtheta) * config_.sim_time / config_.angular_sim_granularity))));
  const double dt = config_.sim_time / steps;
  const nav::Costmap& map = nav_.localCostmap();
  double x = pose.x, y = pose.y, theta = pose.yaw;
  double occupancy = 0.0;
  nav::CellIndex last{-1, -1};
  for (int i = 0; i < steps; ++i) {
    const double cost = footprintCost(x, y, theta);
    if (cost < 0.0) return -1.0;
    occupancy = std::max(occupancy, cost);
    if (!map.toCell({x, y}, last)) return -1.0;
    x += vx * std::cos(theta) * dt;
    y += vx * std::sin(theta) * dt;
    theta += vtheta * dt;
  }
  const std::size_t at = static_cast<std::size_t>(last.y * map.widthCells() + last.x);
  const int path_cells = path_distance_.empty() ? kUnreachable : path_distance_[at];
  const int goal_cells = goal_distance_.empty() ? kUnreachable : goal_distance_[at];
  if (path_cells == kUnreachable || goal_cells == kUnreachable) return -2.0;
  // meter_scoring: distances in cells times the resolution.
  const double res = map.resolution();
  return config_.pdist_scale * res * path_cells + config_.gdist_scale * res * goal_cells + config_.occdist_scale * occupancy;
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
  // In place: only rotations fast enough to overcome friction (min_in_place_vel_theta).
  DwaTrajectory turn;
  for (int j = 0; j < config_.vtheta_samples; ++j) {
    double vth = min_th + j * dvth;
    if (std::abs(vth) < config_.min_in_place_vel_theta) vth = std::copysign(config_.min_in_place_vel_theta, vth == 0.0 ? 1.0 : vth);
    const double cost = scoreTrajectory(pose, 0.0, vth);
    if (cost >= 0.0 && (turn.cost < 0.0 || cost < turn.cost)) turn = {0.0, vth, cost};
  }
  if (turn.cost >= 0.0 && (best.cost < 0.0 || turn.cost <= best.cost)) best = turn;
  if (best.cost >= 0.0) return best;
  // Nothing forward or in place: try backing out.
  const double escape_cost = scoreTrajectory(pose, config_.escape_vel, 0.0);
  if (escape_cost >= 0.0) return {config_.escape_vel, 0.0, escape_cost};
  return {};
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
