#include "barn/nav/nav_stack.hpp"

#include <algorithm>

#include "barn/core/rect.hpp"

namespace barn::nav {

CostmapConfig NavStackConfig::defaultGlobalCostmap() {
  CostmapConfig c;
  // BARN's corridor is 4.2 m wide around the start's x (odom x in [-2.4, 2.2] for either
  // protocol) and the goal is 10 m ahead; 6 x 15 m covers it with margin. (BARN's own global
  // costmap is 40 x 40 m: the cells behind the walls only cost planning time.)
  c.width = 6.0;
  c.height = 15.0;
  c.origin_x = -3.0;
  c.origin_y = -3.0;
  c.rolling = false;
  return c;
}

CostmapConfig NavStackConfig::defaultLocalCostmap() {
  CostmapConfig c;
  c.width = 10.0;
  c.height = 10.0;
  c.rolling = true;
  return c;
}

NavStackConfig NavStackConfig::moveBaseWithNavFn() {
  NavStackConfig c;
  c.planner.algorithm = PlannerAlgorithm::NavFn;
  return c;
}

void validate(const NavStackConfig& c, core::Errors& errors, const std::string& prefix) {
  validate(c.global_costmap, errors, prefix + ".global_costmap");
  validate(c.local_costmap, errors, prefix + ".local_costmap");
  validate(c.planner, errors, prefix + ".planner");
  errors.check(c.footprint_length > 0.0, prefix + ".footprint_length", "must be > 0");
  errors.check(c.footprint_width > 0.0, prefix + ".footprint_width", "must be > 0");
  errors.check(c.footprint_padding > -0.5 * std::min(c.footprint_length, c.footprint_width), prefix + ".footprint_padding",
               "must not shrink the footprint to nothing");
  errors.check(c.global_update_rate > 0.0, prefix + ".global_update_rate", "must be > 0");
  errors.check(c.local_update_rate > 0.0, prefix + ".local_update_rate", "must be > 0");
  errors.check(c.local_costmap_view == "live" || c.local_costmap_view == "published", prefix + ".local_costmap_view",
               "must be live or published, got '" + c.local_costmap_view + "'");
}

NavStack::NavStack(const NavStackConfig& config)
    : config_(config),
      published_view_(config.local_costmap_view == "published"),
      global_(config.global_costmap), local_(config.local_costmap), planner_(config.planner) {}

void NavStack::reset(const Eigen::Vector2d& goal) {
  global_ = Costmap(config_.global_costmap);
  local_ = Costmap(config_.local_costmap);
  local_updates_queued_ = 0;
  published_updates_ = 0;
  queued_window_origin_ = local_.origin();
  published_once_ = false;
  // A fresh planner too: its cache is keyed on the costmap's address and version, which the
  // new costmap can repeat.
  planner_ = GlobalPlanner(config_.planner);
  goal_ = goal;
  path_.clear();
  path_yaw_.clear();
  last_global_update_ = last_local_update_ = last_plan_ = last_scan_stamp_ = -1e9;
  plans_ = failed_plans_ = 0;
  last_plan_found_ = false;
}

std::vector<Eigen::Vector2d> NavStack::paddedFootprint() const {
  const auto corners =
      core::Rect::centred(config_.footprint_length, config_.footprint_width).grownBy(config_.footprint_padding).corners();
  return {corners.begin(), corners.end()};
}

void NavStack::update(double time, const core::LaserScan& scan, const core::Pose2& sensor_pose,
                      const core::Pose2& robot_pose) {
  constexpr double kSlack = 1e-9;  // periods are multiples of the control period up to rounding
  const bool new_scan = scan.stamp != last_scan_stamp_;
  if (new_scan && time - last_global_update_ >= 1.0 / config_.global_update_rate - kSlack) {
    global_.integrateScan(scan, sensor_pose, robot_pose.position());
    if (config_.footprint_clearing) global_.clearPolygon(footprintAt(robot_pose));
    last_global_update_ = time;
  }
  if (local_updates_queued_ == local_updates_.size()) local_updates_.emplace_back();
  LocalUpdate& update = local_updates_[local_updates_queued_++];
  update.has_scan = new_scan && time - last_local_update_ >= 1.0 / config_.local_update_rate - kSlack;
  update.robot_pose = robot_pose;
  const Eigen::Vector2d window_origin = local_.windowOriginFor(queued_window_origin_, robot_pose.position());
  if (!published_once_ || window_origin != queued_window_origin_) published_updates_ = local_updates_queued_;
  published_once_ = true;
  queued_window_origin_ = window_origin;
  if (update.has_scan) {
    update.scan.stamp = scan.stamp;
    update.scan.angle_min = scan.angle_min;
    update.scan.angle_increment = scan.angle_increment;
    update.scan.range_min = scan.range_min;
    update.scan.range_max = scan.range_max;
    update.scan.ranges.assign(scan.ranges.begin(), scan.ranges.end());
    update.sensor_pose = sensor_pose;
    last_local_update_ = time;
  }
  last_scan_stamp_ = scan.stamp;
  if (time - last_plan_ >= 1.0 / config_.planner.rate - kSlack) {
    replan(robot_pose);
    last_plan_ = time;
  }
}

std::vector<Eigen::Vector2d> NavStack::footprintAt(const core::Pose2& robot_pose) const {
  std::vector<Eigen::Vector2d> footprint;
  for (const auto& corner : paddedFootprint()) footprint.push_back(robot_pose.transform(corner));
  return footprint;
}

void NavStack::applyLocalUpdate(const LocalUpdate& update) const {
  if (!update.has_scan) {
    local_.recentre(update.robot_pose.position());
    return;
  }
  local_.integrateScan(update.scan, update.sensor_pose, update.robot_pose.position());
  if (config_.footprint_clearing) local_.clearPolygon(footprintAt(update.robot_pose));
}

void NavStack::applyLocalUpdates(std::size_t count) const {
  if (count == 0) return;
  for (std::size_t i = 0; i < count; ++i) applyLocalUpdate(local_updates_[i]);
  // The rest move to the front; the entries keep their scan buffers for reuse.
  std::rotate(local_updates_.begin(), local_updates_.begin() + static_cast<std::ptrdiff_t>(count),
              local_updates_.begin() + static_cast<std::ptrdiff_t>(local_updates_queued_));
  local_updates_queued_ -= count;
  published_updates_ -= std::min(published_updates_, count);
}

void NavStack::clearCostmapsOutside(const Eigen::Vector2d& centre, double keep) {
  global_.clearOutside(centre, keep);
  applyLocalUpdates(local_updates_queued_);
  local_.clearOutside(centre, keep);
}

void NavStack::resetLocalCostmap() {
  applyLocalUpdates(local_updates_queued_);
  local_.reset();
}

void NavStack::replan(const core::Pose2& robot_pose) {
  // The goal pose's orientation is the identity (yaw 0): our choice, BARN sends a position.
  Plan plan = planner_.plan(global_, robot_pose.position(), goal_, robot_pose.yaw, 0.0);
  ++plans_;
  last_plan_found_ = plan.found;
  // While the robot is moving, move_base keeps following the last path when the planner
  // fails; a controller that is waiting for a plan (DWA) asks lastPlanFound().
  if (plan.found) {
    path_ = std::move(plan.path);
    path_yaw_ = std::move(plan.yaw);
  }
  else ++failed_plans_;
}

}  // namespace barn::nav
