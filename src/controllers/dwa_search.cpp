#include "dwa_search.hpp"

#include <algorithm>
#include <cmath>
#include <limits>

#include "barn/nav/grid_line.hpp"

namespace barn::controllers {

namespace {

// Moves `value` toward `target` by at most `step` (the roll-out's acceleration limit).
double approach(double value, double target, double step) {
  return value < target ? std::min(target, value + step) : std::max(target, value - step);
}

// The highest cost on the cells of the segment from a to b (both on the map), as
// CostmapModel::lineCost walks them.
int highestCostOnSegment(const std::uint8_t* costs, int width, nav::CellIndex a, nav::CellIndex b) {
  int worst = 0;
  nav::walkLineFlat(a.x, a.y, b.x, b.y, std::max(std::abs(b.x - a.x), std::abs(b.y - a.y)), width,
                    [&](std::ptrdiff_t at) { worst = std::max(worst, static_cast<int>(costs[at])); });
  return worst;
}

}  // namespace

DwaSearch::DwaSearch(const DwaConfig& config, std::vector<Eigen::Vector2d> footprint)
    : config_(config), footprint_(std::move(footprint)) {}

void DwaSearch::reset() {
  escaping_ = false;
  rotating_left_ = rotating_right_ = stuck_left_ = stuck_right_ = false;
  last_rotation_position_ = Eigen::Vector2d::Zero();  // upstream starts prev_x_, prev_y_ at 0
}

bool DwaSearch::footprintCorners(double x, double y, double cos_theta, double sin_theta,
                                     nav::CellIndex (&corners)[4]) const {
  const nav::Costmap& map = *map_;
  for (int k = 0; k < 4; ++k) {
    const Eigen::Vector2d& p = footprint_[static_cast<std::size_t>(k)];
    if (!map.toCell(x + cos_theta * p.x() - sin_theta * p.y(), y + sin_theta * p.x() + cos_theta * p.y(), corners[k]))
      return false;
  }
  return true;
}

int DwaSearch::outlineCost(const nav::CellIndex (&corners)[4]) const {
  // CostmapModel::footprintCost: only the padded outline is walked; -1 if it crosses a lethal
  // or unknown cell, the highest cost on it otherwise (inscribed, 253, is legal). Lethal and
  // unknown are the two highest costs, so the highest cost on the outline tells both; the
  // walk never stops early, which keeps its loop free of branches on the costs.
  const nav::Costmap& map = *map_;
  const std::uint8_t* costs = map.costs();
  const int width = map.widthCells();
  int worst = 0;
  for (int k = 0; k < 4; ++k)
    worst = std::max(worst, highestCostOnSegment(costs, width, corners[k], corners[(k + 1) % 4]));
  return worst >= nav::kLethalCost ? -1 : worst;
}

void DwaSearch::Wavefront::start(std::span<const int> seeds) {
  queue.resize(distance.size());
  head = tail = 0;
  for (int i : seeds) {
    int& d = distance[static_cast<std::size_t>(i)];
    if (d == 0) continue;
    d = 0;  // a seed counts whatever its cost
    queue[tail++] = i;
  }
}

void DwaSearch::updateDistanceMaps(const nav::Costmap& local_costmap, const nav::Path* path_in, const core::Pose2& pose) {
  map_ = &local_costmap;
  // MapGrid: 4-connected breadth-first wavefronts on the local costmap from the global path
  // (its first run of points inside the map, starting at the point nearest the robot, up to
  // the first point beyond the window) and from the local goal (that run's last point).
  // Inscribed, lethal and unknown cells get obstacle_distance_ when reached and are not
  // expanded, except, in the path map, cells under the robot's padded footprint.
  // The wavefronts cover +-scoring_window around the robot (ROS: the whole local map).
  const nav::Costmap& map = *map_;
  const int w = map.widthCells(), h = map.heightCells();
  obstacle_distance_ = static_cast<int>(static_cast<std::size_t>(w) * static_cast<std::size_t>(h));
  nav::CellIndex robot;
  map.toCell(pose.position(), robot);
  const int reach = static_cast<int>(std::ceil(config_.scoring_window / map.resolution()));
  const int wx0 = std::max(0, robot.x - reach), wx1 = std::min(w - 1, robot.x + reach);
  const int wy0 = std::max(0, robot.y - reach), wy1 = std::min(h - 1, robot.y + reach);
  DistanceGrid& grid = distances_;
  grid.x0 = wx0;
  grid.y0 = wy0;
  grid.width = std::max(0, wx1 - wx0 + 1);
  grid.height = std::max(0, wy1 - wy0 + 1);
  grid.stride = grid.width + 2;

  // Both maps start alike: open cells unreached, blocked ones marked to take
  // obstacle_distance_ when reached, the border at obstacle_distance_. Each cell is written
  // once (the vectors keep their memory from tick to tick).
  const std::size_t cells = static_cast<std::size_t>(grid.stride) * static_cast<std::size_t>(grid.height + 2);
  for (Wavefront* wave : {&grid.path, &grid.goal}) {
    wave->stride = grid.stride;
    wave->obstacle = obstacle_distance_;
    wave->unreached = obstacle_distance_ + 1;
    wave->blocked = obstacle_distance_ + 2;
    wave->distance.resize(cells);
  }
  const int border = obstacle_distance_, open = obstacle_distance_ + 1, blocked = obstacle_distance_ + 2;
  const std::size_t stride = static_cast<std::size_t>(grid.stride);
  int* path_cells = grid.path.distance.data();
  int* goal_cells = grid.goal.distance.data();
  std::fill_n(path_cells, stride, border);
  std::fill_n(goal_cells, stride, border);
  std::fill_n(path_cells + cells - stride, stride, border);
  std::fill_n(goal_cells + cells - stride, stride, border);
  const std::uint8_t* costs = map.costs();
  for (int y = 0; y < grid.height; ++y) {
    const std::uint8_t* row = costs + static_cast<std::size_t>(wy0 + y) * static_cast<std::size_t>(w) + static_cast<std::size_t>(wx0);
    const std::size_t first = static_cast<std::size_t>(y + 1) * stride;
    int* path_row = path_cells + first;
    int* goal_row = goal_cells + first;
    path_row[0] = goal_row[0] = border;
    for (int x = 0; x < grid.width; ++x) path_row[x + 1] = goal_row[x + 1] = row[x] >= nav::kInscribedCost ? blocked : open;
    path_row[grid.width + 1] = goal_row[grid.width + 1] = border;
  }
  // The path map passes the blocked cells under the robot.
  std::vector<Eigen::Vector2d> outline;
  for (const Eigen::Vector2d& corner : footprint_) outline.push_back(pose.transform(corner));
  for (const nav::CellIndex& cell : map.polygonCells(outline)) {
    const int i = grid.index(cell.x, cell.y);
    if (i >= 0) grid.path.distance[static_cast<std::size_t>(i)] = grid.path.unreached;
  }

  path_seeds_.clear();
  int goal_cell = -1;
  if (path_in && !path_in->empty()) {
    // The path densified to one point per cell length, so every cell it crosses is a seed.
    const nav::Path& path = *path_in;
    const double res = map.resolution();
    const auto seed = [&](const Eigen::Vector2d& p) {
      nav::CellIndex cell;
      if (!map.toCell(p, cell)) return false;
      const int at = grid.index(cell.x, cell.y);
      if (at < 0 || map.cost(cell.x, cell.y) == nav::kUnknownCost) return false;
      if (path_seeds_.empty() || path_seeds_.back() != at) path_seeds_.push_back(at);
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
  // The searches run as far as the distances read from them need (Wavefront::at).
  grid.path.start(path_seeds_);
  grid.goal.start(goal_cell >= 0 ? std::span<const int>(&goal_cell, 1) : std::span<const int>());
}

int DwaSearch::pathDistance(const nav::CellIndex& cell) {
  const int i = distances_.index(cell.x, cell.y);
  return i < 0 ? unreached() : distances_.path.at(i);
}

int DwaSearch::goalDistance(const nav::CellIndex& cell) {
  const int i = distances_.index(cell.x, cell.y);
  return i < 0 ? unreached() : distances_.goal.at(i);
}

int DwaSearch::rolloutSteps(double vx, double vtheta) const {
  // TrajectoryPlanner::generateTrajectory: steps of sim_granularity metres (or of
  // angular_sim_granularity per rad/s of yaw rate).
  return std::max(1, static_cast<int>(std::max(std::abs(vx) * config_.sim_time / config_.sim_granularity,
                                               std::abs(vtheta) / config_.angular_sim_granularity) + 0.5));
}

std::size_t DwaSearch::headings(const core::Pose2& pose, const core::Twist& velocity, int steps, double vtheta) {
  for (const HeadingRun& run : heading_runs_)
    if (run.steps == steps && run.vtheta == vtheta) return run.first;
  const std::size_t first = headings_.size();
  heading_runs_.push_back({steps, vtheta, first});
  headings_.resize(first + static_cast<std::size_t>(steps));  // the memory is kept from tick to tick
  Heading* out = headings_.data() + first;
  // The yaw rate approaches the sample at the acceleration limit.
  const double dt = config_.sim_time / steps;
  const double omega_step = config_.acc_lim_theta * dt;
  double theta = pose.yaw, omega = velocity.angular;
  int i = 0;
  for (; i < steps && omega != vtheta; ++i) {
    out[i] = {theta, std::cos(theta), std::sin(theta)};
    omega = approach(omega, vtheta, omega_step);
    theta += omega * dt;
  }
  // At the sample's yaw rate every step turns by the same angle: the heading's cosine and sine
  // follow by that rotation (sincos was a tenth of DWA's time).
  if (i < steps) {
    const double turn_cos = std::cos(vtheta * dt), turn_sin = std::sin(vtheta * dt);
    double c = std::cos(theta), s = std::sin(theta);
    for (; i < steps; ++i) {
      out[i] = {theta, c, s};
      theta += vtheta * dt;
      const double next_c = c * turn_cos - s * turn_sin;
      s = s * turn_cos + c * turn_sin;
      c = next_c;
    }
  }
  return first;
}

DwaSearch::RolloutPoints DwaSearch::simulate(const core::Pose2& pose, const core::Twist& velocity, double vx,
                                                     double vtheta) {
  // The poses of TrajectoryPlanner::generateTrajectory: the velocity approaches the sample at
  // the acceleration limits, and each step moves along the heading it starts from.
  const int steps = rolloutSteps(vx, vtheta);
  const double dt = config_.sim_time / steps;
  const double v_step = config_.acc_lim_x * dt;
  const RolloutPoints points{positions_.size(), headings(pose, velocity, steps, vtheta), steps};
  const Heading* heading = headings_.data() + points.first_heading;
  positions_.resize(points.first_position + static_cast<std::size_t>(steps));
  Eigen::Vector2d* out = positions_.data() + points.first_position;
  double x = pose.x, y = pose.y, v = velocity.linear;
  for (int i = 0; i < steps; ++i) {
    out[i] = {x, y};
    v = approach(v, vx, v_step);
    x += v * heading[i].cos * dt;
    y += v * heading[i].sin * dt;
  }
  return points;
}

DwaSearch::CentreScore DwaSearch::scoreCentres(const RolloutPoints& points) {
  // Only whether each distance is below obstacle_distance_ matters before the last point, so
  // the wavefronts advance no further than that needs (Wavefront::openAt), the goal one not
  // at all once the path is out of reach.
  const nav::Costmap& map = *map_;
  const std::uint8_t* costs = map.costs();
  CentreScore score;
  nav::CellIndex previous{-1, -1};
  for (int i = 0; i < points.count; ++i) {
    const Eigen::Vector2d& p = positions_[points.first_position + static_cast<std::size_t>(i)];
    nav::CellIndex cell;
    if (!map.toCell(p.x(), p.y(), cell)) return score;
    if (cell == previous) continue;  // a point in the same cell as the last reads the same
    previous = cell;
    const int cost = costs[static_cast<std::size_t>(cell.y) * static_cast<std::size_t>(map.widthCells()) + static_cast<std::size_t>(cell.x)];
    score.occupancy = std::max(score.occupancy, cost);
    if (!openDistances(cell, score.path_cells, score.goal_cells)) return score;
  }
  score.plausible = true;
  return score;
}

bool DwaSearch::openDistances(const nav::CellIndex& cell, int& path_cells, int& goal_cells) {
  const int at = distances_.index(cell.x, cell.y);
  if (at < 0) return false;  // outside the window: never reached
  path_cells = distances_.path.openAt(at);
  if (path_cells >= obstacle_distance_) return false;  // the goal wavefront need not advance
  goal_cells = distances_.goal.openAt(at);
  return goal_cells < obstacle_distance_;
}

template <class CannotWin>
int DwaSearch::outlineOccupancy(const RolloutPoints& points, int occupancy, CannotWin cannot_win) const {
  // Raises `occupancy` by the footprint outline of every point: -1 if one crosses a lethal or
  // unknown cell or leaves the map, or once cannot_win(occupancy) (the cost only grows).
  // Consecutive points often put the corners in the same cells, hence on the same outline.
  nav::CellIndex previous[4];
  bool have_previous = false;
  for (int i = 0; i < points.count; ++i) {
    const Eigen::Vector2d& p = positions_[points.first_position + static_cast<std::size_t>(i)];
    const std::size_t h = points.first_heading + static_cast<std::size_t>(i);
    nav::CellIndex corners[4];
    if (!footprintCorners(p.x(), p.y(), headings_[h].cos, headings_[h].sin, corners)) return -1;
    if (have_previous && std::equal(corners, corners + 4, previous)) continue;
    const int outline = outlineCost(corners);
    if (outline < 0) return -1;
    std::copy(corners, corners + 4, previous);
    have_previous = true;
    if (outline > occupancy) {
      occupancy = outline;
      if (cannot_win(occupancy)) return -1;
    }
  }
  return occupancy;
}

double DwaSearch::trajectoryCost(int path_cells, int goal_cells, int occupancy) const {
  // The path and goal weights count per metre under meter_scoring; the occupancy weight is
  // never scaled. Every term is non-negative, so the cost never falls as the occupancy rises.
  const double distance_unit = config_.meter_scoring ? map_->resolution() : 1.0;
  return distance_unit * (config_.pdist_scale * path_cells + config_.gdist_scale * goal_cells) +
         config_.occdist_scale * occupancy;
}

DwaTrajectory DwaSearch::rollOut(const core::Pose2& pose, const core::Twist& velocity, double vx, double vtheta) {
  // TrajectoryPlanner::generateTrajectory's scoring, point by point: -1 at the first point
  // off the map or whose footprint hits, -2 at the first from which the path or the local
  // goal cannot be reached; else the distances of the last point count.
  const nav::Costmap& map = *map_;
  const RolloutPoints points = simulate(pose, velocity, vx, vtheta);
  DwaTrajectory trajectory{vx, vtheta, -1.0, pose};
  int occupancy = 0, path_cells = 0, goal_cells = 0;
  for (int i = 0; i < points.count; ++i) {
    const Eigen::Vector2d& p = positions_[points.first_position + static_cast<std::size_t>(i)];
    const std::size_t h = points.first_heading + static_cast<std::size_t>(i);
    nav::CellIndex cell, corners[4];
    if (!map.toCell(p.x(), p.y(), cell)) return trajectory;
    if (!footprintCorners(p.x(), p.y(), headings_[h].cos, headings_[h].sin, corners)) return trajectory;
    const int outline = outlineCost(corners);
    if (outline < 0) return trajectory;
    occupancy = std::max({occupancy, outline, static_cast<int>(map.cost(cell.x, cell.y))});
    path_cells = pathDistance(cell);
    goal_cells = goalDistance(cell);
    if (path_cells >= obstacle_distance_ || goal_cells >= obstacle_distance_) {
      trajectory.cost = -2.0;
      return trajectory;
    }
    trajectory.end = {p.x(), p.y(), headings_[h].theta};
  }
  trajectory.cost = trajectoryCost(path_cells, goal_cells, occupancy);
  return trajectory;
}

DwaSearch::SampleWindow DwaSearch::sampleWindow(const core::Twist& velocity) const {
  // The window spans one control period (dwa mode); samples by repeated addition, as upstream.
  const double period = 1.0 / config_.rate;
  SampleWindow w;
  w.max_x = std::max(std::min(config_.max_vel_x, velocity.linear + config_.acc_lim_x * period), config_.min_vel_x);
  w.min_x = std::max(config_.min_vel_x, velocity.linear - config_.acc_lim_x * period);
  w.max_th = std::min(config_.max_vel_theta, velocity.angular + config_.acc_lim_theta * period);
  w.min_th = std::max(-config_.max_vel_theta, velocity.angular - config_.acc_lim_theta * period);
  w.dvx = (w.max_x - w.min_x) / (config_.vx_samples - 1);
  w.dvth = (w.max_th - w.min_th) / (config_.vtheta_samples - 1);
  return w;
}

core::Pose2 DwaSearch::endPose(const RolloutPoints& points) const {
  const std::size_t last = static_cast<std::size_t>(points.count - 1);
  const Eigen::Vector2d& p = positions_[points.first_position + last];
  return core::Pose2{p.x(), p.y(), headings_[points.first_heading + last].theta};
}

void DwaSearch::chooseForwardArc(const core::Pose2& pose, const core::Twist& velocity, const SampleWindow& w,
                                     DwaTrajectory& best) {
  // The straight sample first, then vtheta_samples - 1 turn rates from the bottom of the
  // window (its top is never tried); ties keep the earlier one, so the winner is the lowest
  // (cost, order). An arc's cost is its last point's path and goal distances plus the
  // occupancy along it, so those two distances alone bound it from below: every arc is bounded
  // so, and the centre cells and footprint outlines along it (the expensive part) are walked
  // from the most promising arc on, only for arcs that can still win.
  arcs_.clear();
  const nav::Costmap& map = *map_;
  int order = 0;
  double vx = w.min_x;
  for (int i = 0; i < config_.vx_samples; ++i, vx += w.dvx) {
    const auto consider = [&](double vth) {
      ArcCandidate arc{vx, vth, order++, simulate(pose, velocity, vx, vth), 0.0};
      // A last point off the map, outside the window or without a way to the path or the
      // local goal fails the centre walk too.
      const core::Pose2 end = endPose(arc.points);
      nav::CellIndex cell;
      int path_cells = 0, goal_cells = 0;
      if (!map.toCell(end.x, end.y, cell) || !openDistances(cell, path_cells, goal_cells)) return;
      arc.bound = trajectoryCost(path_cells, goal_cells, 0);
      arcs_.push_back(arc);
    };
    consider(0.0);
    double vth = w.min_th;
    for (int j = 0; j < config_.vtheta_samples - 1; ++j, vth += w.dvth) consider(vth);
  }
  std::sort(arcs_.begin(), arcs_.end(), [](const ArcCandidate& a, const ArcCandidate& b) {
    return a.bound < b.bound || (a.bound == b.bound && a.order < b.order);
  });
  int best_order = -1;
  for (const ArcCandidate& arc : arcs_) {
    const auto cannotWin = [&](double cost) {
      return best.cost >= 0.0 && (cost > best.cost || (cost == best.cost && arc.order > best_order));
    };
    // Sorted by (bound, order): once one cannot win, none after it can.
    if (cannotWin(arc.bound)) break;
    const CentreScore centre = scoreCentres(arc.points);
    if (!centre.plausible) continue;
    if (cannotWin(trajectoryCost(centre.path_cells, centre.goal_cells, centre.occupancy))) continue;
    const int occupancy = outlineOccupancy(arc.points, centre.occupancy, [&](int occ) {
      return cannotWin(trajectoryCost(centre.path_cells, centre.goal_cells, occ));
    });
    if (occupancy < 0) continue;
    const double cost = trajectoryCost(centre.path_cells, centre.goal_cells, occupancy);
    if (cannotWin(cost)) continue;
    best = {arc.vx, arc.vtheta, cost, endPose(arc.points)};
    best_order = arc.order;
  }
}

void DwaSearch::chooseRotation(const core::Pose2& pose, const core::Twist& velocity, const SampleWindow& w,
                                   DwaTrajectory& best) {
  // A rotation replaces the best arc if it costs no more and the point heading_lookahead ahead
  // of its end is nearer the local goal than the rotations taken so far. stuck_right (turned
  // clockwise on two cycles without moving) locks out counter-clockwise turns, stuck_left
  // clockwise ones. The cheap conditions come first.
  const nav::Costmap& map = *map_;
  double heading_distance = std::numeric_limits<double>::max();
  double sample = w.min_th;
  for (int j = 0; j < config_.vtheta_samples; ++j, sample += w.dvth) {
    const double vth = sample > 0 ? std::max(sample, config_.min_in_place_vel_theta)
                                  : std::min(sample, -config_.min_in_place_vel_theta);
    if (!(std::abs(sample) > w.dvth)) continue;
    if (!((sample < 0 && !stuck_left_) || (sample > 0 && !stuck_right_))) continue;
    const RolloutPoints points = simulate(pose, velocity, 0.0, vth);
    const CentreScore centre = scoreCentres(points);
    if (!centre.plausible) continue;
    const auto cannotWin = [&](double cost) { return best.cost >= 0.0 && cost > best.cost; };
    if (cannotWin(trajectoryCost(centre.path_cells, centre.goal_cells, centre.occupancy))) continue;
    const core::Pose2 end = endPose(points);
    nav::CellIndex ahead;
    const Eigen::Vector2d look = end.position() + config_.heading_lookahead * Eigen::Vector2d(std::cos(end.yaw), std::sin(end.yaw));
    if (!map.toCell(look, ahead)) continue;
    const double ahead_distance = goalDistance(ahead);
    if (!(ahead_distance < heading_distance)) continue;
    const int occupancy = outlineOccupancy(points, centre.occupancy, [&](int occ) {
      return cannotWin(trajectoryCost(centre.path_cells, centre.goal_cells, occ));
    });
    if (occupancy < 0) continue;
    const double cost = trajectoryCost(centre.path_cells, centre.goal_cells, occupancy);
    if (cannotWin(cost)) continue;
    best = {0.0, vth, cost, end};
    heading_distance = ahead_distance;
  }
}

void DwaSearch::clearOscillationIfMoved(const core::Pose2& pose) {
  if ((pose.position() - last_rotation_position_).norm() > config_.oscillation_reset_dist)
    rotating_left_ = rotating_right_ = stuck_left_ = stuck_right_ = false;
}

void DwaSearch::endEscapeIfDone(const core::Pose2& pose) {
  if ((pose.position() - escape_pose_.position()).norm() > config_.escape_reset_dist ||
      std::abs(core::wrapAngle(pose.yaw - escape_pose_.yaw)) > config_.escape_reset_theta)
    escaping_ = false;
}

DwaTrajectory DwaSearch::findBestPath(const nav::Costmap& map, const core::Pose2& pose, const core::Twist& velocity) {
  map_ = &map;
  const SampleWindow window = sampleWindow(velocity);
  heading_runs_.clear();
  headings_.clear();
  positions_.clear();

  DwaTrajectory best;
  if (!escaping_) chooseForwardArc(pose, velocity, window, best);
  chooseRotation(pose, velocity, window, best);
  if (best.cost >= 0.0) {
    // Oscillation flags: two cycles turning one way in place lock out the other way until the
    // robot has moved away from where it last turned in place.
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
    clearOscillationIfMoved(pose);
    endEscapeIfDone(pose);
    return best;
  }
  // Nothing forward or in place is legal: back up at escape_vel whatever the map says behind
  // ("backing up slowly is allowed even when the map shows it blocked"); only a back-up with
  // no way on from its points (-2) leaves the robot standing.
  DwaTrajectory escape = rollOut(pose, velocity, config_.escape_vel, 0.0);
  clearOscillationIfMoved(pose);
  if (!escaping_ && escape.cost > -2.0) {
    escaping_ = true;
    escape_pose_ = pose;
  }
  endEscapeIfDone(pose);
  if (escape.cost == -1.0) escape.cost = 1.0;
  return escape;
}

}  // namespace barn::controllers
