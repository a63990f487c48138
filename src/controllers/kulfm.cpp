#include "barn/controllers/kulfm.hpp"

#include <algorithm>
#include <cmath>
#include <numbers>
#include <stdexcept>

namespace barn::controllers {

namespace {
constexpr double kDeg = std::numbers::pi / 180.0;

bool sameGeometry(const core::LidarConfig& a, const core::LidarConfig& b) {
  return a.beams == b.beams && a.angle_min == b.angle_min && a.angle_max == b.angle_max && a.range_min == b.range_min &&
         a.range_max == b.range_max && a.mount_x == b.mount_x && a.mount_y == b.mount_y;
}

core::Rect endBox(const KulfmConfig& c) {
  return {-c.tubes.axle_to_rear, c.tubes.axle_to_front, -c.goal_box_width / 2, c.goal_box_width / 2};
}
}  // namespace

std::span<const std::string_view> enumNames(KulfmState) {
  static constexpr std::string_view kNames[] = {"Normal",       "StopToRecover", "StartRecover", "Rotate",
                                                "MoveBackward", "Blind",         "StopToNormal"};
  return kNames;
}

nav::NavStackConfig KulfmConfig::kulfmNav() {
  nav::NavStackConfig c = nav::NavStackConfig::moveBaseWithNavFn();  // NavFn at planner_frequency 20
  c.footprint_padding = 0.0;
  c.footprint_clearing = true;
  for (nav::CostmapConfig* map : {&c.global_costmap, &c.local_costmap}) {
    map->obstacle_range = 4.5;
    map->raytrace_range = 5.0;
    map->clearing = false;
    map->inflation_radius = 0.4;
    map->cost_scaling_factor = 10.0;
  }
  c.global_update_rate = 10.0;
  c.local_update_rate = 1.0;
  return c;
}

void validate(const KulfmConfig& c, core::Errors& errors, const std::string& prefix) {
  core::validateFields(c, errors, prefix);
  validate(c.tubes, errors, prefix + ".tubes");
  errors.check(c.high_ratio >= c.low_ratio && c.high_ratio <= 1.0, prefix + ".high_ratio", "must be in [low_ratio, 1]");
  nav::validate(c.nav, errors, prefix + ".nav");
}

LocalGoal localGoalOnPlan(const std::vector<Eigen::Vector2d>& plan, double length, int orientation_points,
                          int head_points) {
  LocalGoal goal;
  if (plan.empty()) return goal;
  const auto direction = [&](std::size_t from, std::size_t to) {
    const Eigen::Vector2d d = plan[to] - plan[from];
    return std::atan2(d.y(), d.x());
  };
  std::size_t k = 0;
  double walked = 0.0;
  while (walked < length && k + 1 < plan.size()) {
    walked += (plan[k + 1] - plan[k]).norm();
    ++k;
  }
  goal.position = plan[k];
  goal.orientation = direction(k >= static_cast<std::size_t>(orientation_points) ? k - static_cast<std::size_t>(orientation_points) : 0, k);
  goal.head = direction(0, std::min(plan.size() - 1, static_cast<std::size_t>(head_points)));
  return goal;
}

double endBoxDistance(const MotionTube& tube, const Eigen::Vector2d& goal, const core::Rect& box) {
  const Eigen::Vector2d q = core::PoseFrame(tube.end).toLocal(goal);
  if (!box.contains(q)) return std::sqrt(box.squaredDistance(q));
  return -std::min({q.x() - box.min_x, box.max_x - q.x(), q.y() - box.min_y, box.max_y - q.y()});
}

int goalBin(double signed_distance, double bin) {
  if (signed_distance <= 0.0) return 0;
  return static_cast<int>(std::min(signed_distance / bin, static_cast<double>(kNoGoalBin - 1))) + 1;
}

ForwardChoice chooseForwardTube(const std::vector<MotionTube>& tubes, const core::LaserScan& scan, const LocalGoal& goal,
                                const core::Twist& odom_twist, const KulfmConfig& c) {
  // The keys of the best tube so far (step 2 of kulfm.hpp's header comment).
  struct Keys {
    int bin = kNoGoalBin;
    int outer = -1, front = -1, inner = -1;  // 1 free, 0 not
    int orientation = kNoGoalBin;
    double change = 1e9;
    double distance = 1e9;
  };
  ForwardChoice choice;
  Keys best;
  const core::Rect box = endBox(c);
  const double max_orientation = c.max_orientation_deg * kDeg;
  for (std::size_t i = 0; i < tubes.size(); ++i) {
    const MotionTube& tube = tubes[i];
    if (!isFree(tube.edge, scan)) continue;
    ++choice.free_tubes;
    Keys k;
    k.distance = endBoxDistance(tube, goal.position, box);
    k.bin = goalBin(k.distance, c.goal_bin);
    if (k.bin > c.max_goal_bin || (choice.tube >= 0 && k.bin > best.bin + c.goal_bin_slack)) continue;
    bool better = choice.tube < 0 || k.bin < best.bin;
    // A key where the best is better drops the tube unless it already won on an earlier key;
    // one where the tube is better makes it win.
    const auto drops = [&better](auto mine, auto theirs, bool higher_is_better) {
      const bool worse = higher_is_better ? mine < theirs : mine > theirs;
      const bool beats = higher_is_better ? mine > theirs : mine < theirs;
      if (worse && !better) return true;
      if (beats) better = true;
      return false;
    };
    k.outer = isFree(tube.outer, scan) ? 1 : 0;
    if (drops(k.outer, best.outer, true)) continue;
    k.front = isFree(tube.front, scan) ? 1 : 0;
    if (drops(k.front, best.front, true)) continue;
    k.inner = isFree(tube.inner, scan) ? 1 : 0;
    if (drops(k.inner, best.inner, true)) continue;
    const double off = std::abs(core::wrapAngle(goal.orientation - tube.heading_change));
    if (off > max_orientation) continue;
    k.orientation = static_cast<int>(off / (c.orientation_bin_deg * kDeg));
    if (drops(k.orientation, best.orientation, false)) continue;
    k.change = odom_twist.linear > 0.0 ? std::abs(odom_twist.angular - odom_twist.linear / tube.radius) : 0.0;
    if (drops(k.change, best.change, false)) continue;
    if (!better && k.distance > best.distance) continue;
    best = k;
    choice.tube = static_cast<int>(i);
  }
  choice.feasible_ratio = tubes.empty() ? 0.0 : static_cast<double>(choice.free_tubes) / static_cast<double>(tubes.size());
  choice.goal_bin = choice.tube >= 0 ? best.bin : kNoGoalBin;
  return choice;
}

int chooseBackwardTube(const std::vector<MotionTube>& tubes, const core::LaserScan& scan, const LocalGoal& goal,
                       const KulfmConfig& c) {
  const core::Rect box = endBox(c);
  const std::size_t n = tubes.size();
  std::vector<int> bins(n, -1);  // -1: not free
  int best_bin = kNoGoalBin;
  for (std::size_t i = 0; i < n; ++i) {
    if (!isFree(tubes[i].edge, scan)) continue;
    bins[i] = goalBin(endBoxDistance(tubes[i], goal.position, box), c.backward_goal_bin);
    best_bin = std::min(best_bin, bins[i]);
  }
  // The candidates in order of signed curvature (hard right ... straight ... hard left).
  std::vector<std::size_t> order(n);
  for (std::size_t i = 0; i < n; ++i) order[i] = i;
  std::stable_sort(order.begin(), order.end(),
                   [&](std::size_t a, std::size_t b) { return 1.0 / tubes[a].radius < 1.0 / tubes[b].radius; });
  std::vector<int> up(n, 0), down(n, 0);  // run lengths of candidates ending / starting at each place
  const auto candidate = [&](std::size_t place) {
    const int bin = bins[order[place]];
    return bin >= 0 && bin <= best_bin + c.backward_bin_slack;
  };
  for (std::size_t p = 0; p < n; ++p) up[p] = candidate(p) ? (p > 0 ? up[p - 1] : 0) + 1 : 0;
  for (std::size_t p = n; p-- > 0;) down[p] = candidate(p) ? (p + 1 < n ? down[p + 1] : 0) + 1 : 0;
  int chosen = -1, chosen_depth = 0;
  for (std::size_t p = 0; p < n; ++p) {
    const int depth = std::min(up[p], down[p]);
    if (depth == 0) continue;
    const std::size_t t = order[p];
    if (depth > chosen_depth ||
        (depth == chosen_depth && std::abs(1.0 / tubes[t].radius) < std::abs(1.0 / tubes[static_cast<std::size_t>(chosen)].radius))) {
      chosen = static_cast<int>(t);
      chosen_depth = depth;
    }
  }
  return chosen;
}

double desiredSpeed(double feasible_ratio, const KulfmConfig& c) {
  if (feasible_ratio < c.low_ratio) return c.min_speed;
  if (feasible_ratio > c.high_ratio) return c.max_speed;
  return c.min_speed_weight * c.min_speed + (1.0 - c.min_speed_weight) * c.max_speed;
}

double limitAcceleration(double previous, double desired, double max_step) {
  return previous + std::clamp(desired - previous, -max_step, max_step);
}

KulfmState nextKulfmState(KulfmState state, const KulfmInputs& in, const KulfmConfig& c) {
  const bool resumable = in.feasible_ratio >= c.resume_ratio && in.goal_bin <= c.resume_goal_bin;
  switch (state) {
    case KulfmState::Normal:
      return in.forward_tube ? KulfmState::Normal : KulfmState::StopToRecover;
    case KulfmState::StopToRecover:
      return std::abs(in.speed) < c.stop_speed && std::abs(in.turn_rate) < c.stop_speed ? KulfmState::StartRecover
                                                                                        : KulfmState::StopToRecover;
    case KulfmState::StartRecover:
      if (in.ring_clear) return KulfmState::Rotate;
      return in.backward_tube ? KulfmState::MoveBackward : KulfmState::Blind;
    case KulfmState::Rotate:
      return resumable ? KulfmState::StopToNormal : KulfmState::Rotate;
    case KulfmState::MoveBackward:
      if (resumable) return KulfmState::StopToNormal;
      if (in.ring_clear) return KulfmState::StopToRecover;
      return in.backward_tube ? KulfmState::MoveBackward : KulfmState::StopToNormal;
    case KulfmState::Blind:
      return resumable ? KulfmState::StopToNormal : KulfmState::Blind;
    case KulfmState::StopToNormal:
      // The 2025 code's condition: either speed small (not both).
      return std::abs(in.speed) < c.resume_speed || std::abs(in.turn_rate) < c.resume_speed ? KulfmState::Normal
                                                                                           : KulfmState::StopToNormal;
  }
  return state;
}

KulfmController::KulfmController(const KulfmConfig& config) : config_(config), nav_(config.nav) {}

void KulfmController::buildLibraries(const core::LidarConfig& lidar) {
  if (built_ && sameGeometry(built_for_, lidar)) return;
  forward_ = buildTubeLibrary(config_.tubes.length, config_.tubes, lidar);
  backward_ = buildTubeLibrary(-config_.tubes.backward_length, config_.tubes, lidar);
  ring_ = rotationRing(config_.ring_radius, lidar);
  built_for_ = lidar;
  built_ = true;
}

void KulfmController::reset(const EpisodeInfo& info) {
  info_ = info;
  nav_.reset(info.goal);
  buildLibraries(info.lidar);
  state_ = KulfmState::Normal;
  last_speed_ = 0.0;
  rotate_direction_ = 1.0;
  plan_.clear();
}

core::Twist KulfmController::act(const Observation& obs) {
  const core::LaserScan& scan = *obs.scan;
  if (scan.ranges.size() != static_cast<std::size_t>(info_.lidar.beams))
    throw std::runtime_error("kulfm: the scan has " + std::to_string(scan.ranges.size()) + " beams, the LiDAR " +
                             std::to_string(info_.lidar.beams));
  nav_.update(obs.time, scan, info_.lidar.sensorPose(obs.scan_odom_pose), obs.odom_pose);
  if (!nav_.hasPath()) {  // the node waits for move_base's first plan
    last_speed_ = 0.0;
    return {};
  }
  const core::PoseFrame frame(obs.odom_pose);
  plan_.clear();
  for (const auto& p : nav_.path()) plan_.push_back(frame.toLocal(p));
  const LocalGoal goal = localGoalOnPlan(plan_, config_.tubes.length, config_.orientation_points, config_.head_points);

  const ForwardChoice forward = chooseForwardTube(forward_, scan, goal, obs.odom_twist, config_);
  KulfmInputs in;
  in.forward_tube = forward.tube >= 0;
  in.feasible_ratio = forward.feasible_ratio;
  in.goal_bin = forward.goal_bin;
  in.speed = obs.odom_twist.linear;
  in.turn_rate = obs.odom_twist.angular;
  // The ring and the backward tubes are read only where a transition looks at them.
  int backward = -1;
  if (state_ == KulfmState::StartRecover || state_ == KulfmState::MoveBackward) {
    in.ring_clear = isFree(ring_, scan);
    backward = chooseBackwardTube(backward_, scan, goal, config_);
    in.backward_tube = backward >= 0;
  }
  const KulfmState next = nextKulfmState(state_, in, config_);
  if (next == KulfmState::Rotate && state_ != KulfmState::Rotate) rotate_direction_ = goal.head >= 0.0 ? 1.0 : -1.0;
  state_ = next;

  core::Twist command;
  switch (state_) {
    case KulfmState::Normal:
      if (forward.tube >= 0) {
        command.linear = limitAcceleration(last_speed_, desiredSpeed(forward.feasible_ratio, config_),
                                           config_.max_acceleration / config_.rate);
        command.angular = command.linear / forward_[static_cast<std::size_t>(forward.tube)].radius;
      }
      break;
    case KulfmState::StopToRecover:
    case KulfmState::StartRecover:
    case KulfmState::StopToNormal:
      break;
    case KulfmState::Rotate:
      command.angular = rotate_direction_ * config_.rotate_rate;
      break;
    case KulfmState::MoveBackward:
      command.linear = -config_.backward_speed;
      command.angular = command.linear / backward_[static_cast<std::size_t>(backward)].radius;
      break;
    case KulfmState::Blind:
      command.linear = -config_.backward_speed;
      break;
  }
  last_speed_ = command.linear;
  return command;
}

}  // namespace barn::controllers
