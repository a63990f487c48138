#include "barn/controllers/lics.hpp"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <filesystem>

namespace barn::controllers {

nav::NavStackConfig LicsConfig::licsNav() {
  nav::NavStackConfig c;  // footprint 0.42 x 0.33, padding 0.1, footprint clearing: the defaults
  for (nav::CostmapConfig* map : {&c.global_costmap, &c.local_costmap}) {
    map->obstacle_range = 4.5;   // the scan source's obstacle_range (overrides the top-level 2.5)
    map->raytrace_range = 5.0;   // the scan source's raytrace_range (overrides 3.0)
    map->clearing = true;
    map->inflation_radius = 0.30;
    map->cost_scaling_factor = 10.0;  // costmap_2d's default (their files set none)
  }
  c.global_update_rate = 10.0;  // BARN's global_costmap_params, kept by the team
  c.local_update_rate = 20.0;   // BARN's local_costmap_params
  c.planner.algorithm = nav::PlannerAlgorithm::GlobalPlanner;
  c.planner.rate = 20.0;  // move_base_params planner_frequency 20
  c.planner.global_planner.cost_factor = 3.0;  // base_global_planner_params (use_dijkstra: ROS default true)
  return c;
}

void validate(const LicsConfig& c, core::Errors& errors, const std::string& prefix) {
  core::validateFields(c, errors, prefix);
  errors.check(!c.policy.empty(), prefix + ".policy", "must name a policy file");
  errors.check(c.smoothing_window >= 1 && c.smoothing_window <= 1001 && c.smoothing_window % 2 == 1,
               prefix + ".smoothing_window", "must be odd, in [1, 1001]");
  errors.check(c.smoothing_order >= 0 && c.smoothing_order < c.smoothing_window, prefix + ".smoothing_order",
               "must be in [0, smoothing_window)");
  errors.check(c.min_speed <= c.max_speed, prefix + ".min_speed", "must be <= max_speed");
  errors.check(c.min_turn_rate <= c.max_turn_rate, prefix + ".min_turn_rate", "must be <= max_turn_rate");
  errors.check(c.front_first_beam >= 0 && c.front_first_beam <= c.front_last_beam, prefix + ".front_first_beam",
               "must be in [0, front_last_beam]");
  errors.check(c.max_inflation_radius >= c.min_inflation_radius, prefix + ".max_inflation_radius",
               "must be >= min_inflation_radius");
  errors.check(c.inflation_speed_threshold < c.max_speed, prefix + ".inflation_speed_threshold",
               "must be < max_speed (the formula divides by their difference)");
  errors.check(c.plan_phase >= 0.0 && std::isfinite(c.plan_phase), prefix + ".plan_phase", "must be >= 0 [s]");
  nav::validate(c.nav, errors, prefix + ".nav");
}

std::shared_ptr<const learning::TransformerPolicy> loadLicsPolicy(const std::string& path) {
  std::error_code ec;
  if (!std::filesystem::exists(path, ec))
    throw core::InputError(path +
                           ": no such policy file. barnbench does not ship the LiCS-KI weights; convert your copy of "
                           "the published transformer_99.pth (damanikjosh/the-barn-challenge, lics/models/) with\n"
                           "  /usr/bin/python3 tools/import_lics_weights.py transformer_99.pth --out " +
                           path + "\n(docs/systems/lics.md)");
  return std::make_shared<const learning::TransformerPolicy>(learning::TransformerPolicy::load(path));
}

double licsInflationRadius(double speed, const LicsConfig& c) {
  // robot.py: v = twist.linear.x / max_v, then (v - threshold_v) / (max_v - threshold_v): the
  // speed is divided by max_v twice.
  const double v = speed / c.max_speed;
  if (!(v > c.inflation_speed_threshold)) return c.min_inflation_radius;
  return c.min_inflation_radius + (v - c.inflation_speed_threshold) / (c.max_speed - c.inflation_speed_threshold) *
                                      (c.max_inflation_radius - c.min_inflation_radius);
}

double licsFrontMultiplier(const core::LaserScan& scan, double clip, const LicsConfig& c) {
  double nearest = clip;
  const auto last = std::min<std::size_t>(static_cast<std::size_t>(c.front_last_beam), scan.ranges.size() - 1);
  for (auto i = static_cast<std::size_t>(c.front_first_beam); i <= last && i < scan.ranges.size(); ++i) {
    const double r = scan.ranges[i];
    nearest = std::min(nearest, std::isnan(r) ? clip : std::clamp(r, 0.0, clip));
  }
  return nearest < c.slow_down_distance ? nearest / c.slow_down_distance : 1.0;
}

Eigen::Vector2d licsLocalGoal(const std::vector<Eigen::Vector2d>& plan, const LicsConfig& c) {
  if (plan.empty()) return Eigen::Vector2d::Zero();
  const Eigen::Vector2d origin = plan.front().norm() > c.plan_start_tolerance ? plan.front() : Eigen::Vector2d::Zero();
  Eigen::Vector2d target = plan.back();
  for (const Eigen::Vector2d& p : plan)
    if ((p - origin).norm() > c.local_goal_distance) {
      target = p;
      break;
    }
  const Eigen::Vector2d d = target - origin;
  const double n = d.norm();
  return n > 0.0 ? Eigen::Vector2d(d / n) : Eigen::Vector2d::Zero();
}

bool licsPlanWritesLast(double plan_time, double scan_stamp, double plan_phase) {
  return plan_time - plan_phase >= scan_stamp;
}

LicsController::LicsController(const LicsConfig& config, std::shared_ptr<const learning::TransformerPolicy> policy)
    : config_(config),
      policy_(std::move(policy)),
      nav_(config.nav),
      smoother_(config.smoothing_window, config.smoothing_order) {}

void LicsController::checkLidar(const core::LidarConfig& lidar) const {
  const int beams = policy_->info().shape.beams;
  if (lidar.beams != beams)
    throw core::InputError("lics: the policy '" + policy_->info().name + "' reads " + std::to_string(beams) +
                           " beams, the LiDAR has " + std::to_string(lidar.beams));
  if (config_.front_last_beam >= lidar.beams)
    throw core::InputError("lics: front_last_beam " + std::to_string(config_.front_last_beam) + " is past the LiDAR's " +
                           std::to_string(lidar.beams) + " beams");
}

void LicsController::reset(const EpisodeInfo& info) {
  info_ = info;
  nav_.reset(info.goal);
  local_goal_ = Eigen::Vector2d::Zero();  // robot.py's initial local goal, until the first plan
  plan_multiplier_ = 1.0;
  last_plan_time_ = 0.0;
  planned_ = false;
  multiplier_ = 1.0;
  parameter_changes_.clear();
}

core::Twist LicsController::act(const Observation& obs) {
  // 1. Odometry callback: the global inflation radius, applied at the costmap's next update.
  parameter_changes_.clear();
  if (config_.dynamic_inflation) {
    const double radius = licsInflationRadius(obs.odom_twist.linear, config_);
    nav_.setParameter("global_costmap.inflation_radius", radius);
    char text[64];
    std::snprintf(text, sizeof text, "global_costmap.inflation_radius=%.4f", radius);
    parameter_changes_ = text;
  }
  // 2. move_base: costmaps and the 20 Hz plan.
  const int plans_before = nav_.plansMade();
  nav_.update(obs.time, *obs.scan, info_.lidar.sensorPose(obs.scan_odom_pose), obs.odom_pose);
  // 3. Plan callback.
  if (nav_.plansMade() != plans_before) {
    planned_ = true;
    last_plan_time_ = obs.time;
    if (nav_.lastPlanFound()) {
      const nav::Path smoothed = smoother_.smoothPath(nav_.path());
      local_goal_ = licsLocalGoal(nav::pathInRobotFrame(smoothed, obs.odom_pose), config_);
      plan_multiplier_ = 1.0;
    } else {
      plan_multiplier_ = config_.empty_plan_multiplier;
    }
  }
  // 4. Scan callback, and the race between the two writers of the multiplier.
  const double clip = policy_->info().range_clip;
  multiplier_ = planned_ && licsPlanWritesLast(last_plan_time_, obs.scan->stamp, config_.plan_phase)
                    ? plan_multiplier_
                    : licsFrontMultiplier(*obs.scan, clip, config_);
  // The control tick.
  const Eigen::Vector2d out = policy_->act(*obs.scan, local_goal_);
  return {std::clamp(out.x() * config_.max_speed * multiplier_, config_.min_speed, config_.max_speed),
          std::clamp(out.y() * config_.max_turn_rate, config_.min_turn_rate, config_.max_turn_rate)};
}

}  // namespace barn::controllers
