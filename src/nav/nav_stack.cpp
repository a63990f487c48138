#include "barn/nav/nav_stack.hpp"

#include <algorithm>
#include <cmath>
#include <stdexcept>

#include "barn/core/rect.hpp"
#include "barn/nav/footprint.hpp"

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

namespace {
double inscribedRadiusOf(const core::Rect& rect) {
  const auto corners = rect.corners();
  return footprintRadii(corners).inscribed;
}
}  // namespace

double NavStackConfig::inscribedRadius(const CostmapConfig& map) const {
  return inscribedRadiusOf(footprint().grownBy(footprint_padding + map.inscribed_padding_offset));
}

double NavStackConfig::circumscribedRadius() const {
  const auto corners = paddedFootprint().corners();
  return footprintRadii(corners).circumscribed;
}

NavStackConfig NavStackConfig::moveBaseWithNavFn() {
  NavStackConfig c;
  c.planner.algorithm = PlannerAlgorithm::NavFn;
  return c;
}

std::span<const std::string_view> enumNames(CostmapView) {
  static constexpr std::string_view kNames[] = {"live", "published"};
  return kNames;
}

void validate(const NavStackConfig& c, core::Errors& errors, const std::string& prefix) {
  core::validateFields(c, errors, prefix);
  validate(c.global_costmap, errors, prefix + ".global_costmap");
  validate(c.local_costmap, errors, prefix + ".local_costmap");
  validate(c.planner, errors, prefix + ".planner");
  const double least_padding = -0.5 * std::min(c.footprint_length, c.footprint_width);
  errors.check(c.footprint_padding > least_padding, prefix + ".footprint_padding", "must not shrink the footprint to nothing");
  errors.check(c.footprint_padding + c.global_costmap.inscribed_padding_offset > least_padding,
               prefix + ".global_costmap.inscribed_padding_offset", "must not shrink the footprint to nothing");
  errors.check(c.footprint_padding + c.local_costmap.inscribed_padding_offset > least_padding,
               prefix + ".local_costmap.inscribed_padding_offset", "must not shrink the footprint to nothing");
}

NavStack::NavStack(const NavStackConfig& config)
    : config_(config),
      published_view_(config.local_costmap_view == CostmapView::Published),
      global_(config.global_costmap, config.inscribedRadius(config.global_costmap)),
      local_(config.local_costmap, config.inscribedRadius(config.local_costmap)),
      global_parameters_(CostmapParameters::of(config.global_costmap)),
      local_parameters_(CostmapParameters::of(config.local_costmap)),
      global_update_rate_(config.global_update_rate), local_update_rate_(config.local_update_rate),
      planner_config_(config.planner), planner_(config.planner) {}

void NavStack::reset(const Eigen::Vector2d& goal) {
  // Parameters changed while running go back to the configured ones.
  global_parameters_ = CostmapParameters::of(config_.global_costmap);
  local_parameters_ = CostmapParameters::of(config_.local_costmap);
  global_parameters_pending_ = local_parameters_pending_ = false;
  global_update_rate_ = config_.global_update_rate;
  local_update_rate_ = config_.local_update_rate;
  planner_config_ = config_.planner;
  global_ = Costmap(config_.global_costmap, config_.inscribedRadius(config_.global_costmap));
  local_ = Costmap(config_.local_costmap, config_.inscribedRadius(config_.local_costmap));
  local_updates_queued_ = 0;
  published_updates_ = 0;
  queued_window_origin_ = local_.origin();
  published_once_ = false;
  // A fresh planner too: its cache is keyed on the costmap's address and version, which the
  // new costmap can repeat.
  planner_ = GlobalPlanner(planner_config_);
  goal_ = goal;
  path_.clear();
  path_yaw_.clear();
  last_global_update_ = last_local_update_ = last_plan_ = last_scan_stamp_ = -1e9;
  plans_ = failed_plans_ = 0;
  last_plan_found_ = false;
}

std::vector<Eigen::Vector2d> NavStack::paddedFootprint() const {
  const auto corners = config_.paddedFootprint().corners();
  return {corners.begin(), corners.end()};
}

void NavStack::update(double time, const core::LaserScan& scan, const core::Pose2& sensor_pose,
                      const core::Pose2& robot_pose) {
  constexpr double kSlack = 1e-9;  // periods are multiples of the control period up to rounding
  const bool new_scan = scan.stamp != last_scan_stamp_;
  if (new_scan && time - last_global_update_ >= 1.0 / global_update_rate_ - kSlack) {
    if (global_parameters_pending_) global_parameters_.applyTo(global_);
    global_parameters_pending_ = false;
    global_.integrateScan(scan, sensor_pose, robot_pose.position());
    if (config_.footprint_clearing) global_.clearPolygon(footprintAt(robot_pose));
    global_.update();
    last_global_update_ = time;
  }
  if (local_updates_queued_ == local_updates_.size()) local_updates_.emplace_back();
  LocalUpdate& update = local_updates_[local_updates_queued_++];
  update.parameters.reset();
  if (local_parameters_pending_) update.parameters = local_parameters_;
  local_parameters_pending_ = false;
  update.has_scan = new_scan && time - last_local_update_ >= 1.0 / local_update_rate_ - kSlack;
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
  if (time - last_plan_ >= 1.0 / planner_config_.rate - kSlack) {
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
  if (update.parameters) update.parameters->applyTo(local_);
  if (!update.has_scan) {
    local_.recentre(update.robot_pose.position());
    return;
  }
  local_.integrateScan(update.scan, update.sensor_pose, update.robot_pose.position());
  if (config_.footprint_clearing) local_.clearPolygon(footprintAt(update.robot_pose));
}

void NavStack::applyLocalUpdates(std::size_t count, Fold fold) const {
  if (count > 0) {
    for (std::size_t i = 0; i < count; ++i) applyLocalUpdate(local_updates_[i]);
    // The rest move to the front; the entries keep their scan buffers for reuse.
    std::rotate(local_updates_.begin(), local_updates_.begin() + static_cast<std::ptrdiff_t>(count),
                local_updates_.begin() + static_cast<std::ptrdiff_t>(local_updates_queued_));
    local_updates_queued_ -= count;
    published_updates_ -= std::min(published_updates_, count);
  }
  // Also with nothing new applied: an obstacles-only read may have left changes unfolded.
  if (fold == Fold::Costs) local_.update();
}

void NavStack::clearCostmapsOutside(const Eigen::Vector2d& centre, double keep) {
  global_.clearOutside(centre, keep);
  global_.update();
  applyLocalUpdates(local_updates_queued_, Fold::Costs);
  local_.clearOutside(centre, keep);
  local_.update();
}

void NavStack::resetLocalCostmap() {
  applyLocalUpdates(local_updates_queued_, Fold::Costs);
  local_.reset();
  local_.update();
}

const std::vector<std::string>& NavStack::settableParameters() {
  static const std::vector<std::string> kKeys = {
      "global_costmap.inflation_radius", "global_costmap.cost_scaling_factor", "global_costmap.obstacle_range",
      "global_costmap.raytrace_range",   "local_costmap.inflation_radius",     "local_costmap.cost_scaling_factor",
      "local_costmap.obstacle_range",    "local_costmap.raytrace_range",       "global_update_rate",
      "local_update_rate",               "planner.rate",                       "planner.cost_factor",
      "planner.neutral_cost",            "planner.global_planner.cost_factor", "planner.global_planner.neutral_cost"};
  return kKeys;
}

void NavStack::setParameter(std::string_view key, double value) {
  const auto unknownKey = [&] {
    std::string known;
    for (const std::string& k : settableParameters()) known += (known.empty() ? "" : ", ") + k;
    throw std::invalid_argument(std::string(key) + ": not a settable parameter (settable: " + known + ")");
  };
  // Each value is checked by the validate() of its config, on a copy with the new value.
  const auto checked = [&](const auto& candidate, auto validator) {
    core::Errors errors;
    validator(candidate, errors);
    if (!std::isfinite(value)) errors.add(std::string(key), "must be a finite number");
    if (!errors.empty()) throw std::invalid_argument(errors.messages().front());
  };
  const auto costmapParameter = [&](std::string_view name, const CostmapConfig& config, CostmapParameters& in_force,
                                    bool& pending) {
    CostmapParameters p = in_force;
    if (name == "inflation_radius") p.inflation_radius = value;
    else if (name == "cost_scaling_factor") p.cost_scaling_factor = value;
    else if (name == "obstacle_range") p.obstacle_range = value;
    else if (name == "raytrace_range") p.raytrace_range = value;
    else return false;
    CostmapConfig candidate = config;
    candidate.inflation_radius = p.inflation_radius;
    candidate.cost_scaling_factor = p.cost_scaling_factor;
    candidate.obstacle_range = p.obstacle_range;
    candidate.raytrace_range = p.raytrace_range;
    const std::string map(key.substr(0, key.size() - name.size() - 1));
    checked(candidate, [&](const CostmapConfig& c, core::Errors& e) { validate(c, e, map); });
    in_force = p;
    pending = true;
    return true;
  };
  const auto after = [&](std::string_view prefix) -> std::optional<std::string_view> {
    if (key.substr(0, prefix.size()) != prefix) return std::nullopt;
    return key.substr(prefix.size());
  };
  if (const auto name = after("global_costmap.");
      name && costmapParameter(*name, config_.global_costmap, global_parameters_, global_parameters_pending_))
    return;
  if (const auto name = after("local_costmap.");
      name && costmapParameter(*name, config_.local_costmap, local_parameters_, local_parameters_pending_))
    return;
  if (key == "global_update_rate" || key == "local_update_rate") {
    checked(value, [&](double rate, core::Errors& e) { e.check(rate > 0.0, std::string(key), "must be > 0 [Hz]"); });
    (key == "global_update_rate" ? global_update_rate_ : local_update_rate_) = value;
    return;
  }
  if (const auto name = after("planner.")) {
    PlannerConfig candidate = planner_config_;
    RosGlobalPlannerConfig& ros = candidate.global_planner;
    const bool whole = value == std::floor(value);
    if (*name == "rate") candidate.rate = value;
    else if (*name == "cost_factor") candidate.cost_factor = value;
    else if (*name == "neutral_cost") candidate.neutral_cost = value;
    else if (*name == "global_planner.cost_factor") ros.cost_factor = value;
    else if (*name == "global_planner.neutral_cost" && whole && std::abs(value) < 1e6) ros.neutral_cost = static_cast<int>(value);
    else if (*name == "global_planner.neutral_cost") throw std::invalid_argument(std::string(key) + ": must be a whole number");
    else return unknownKey();
    checked(candidate, [](const PlannerConfig& c, core::Errors& e) { validate(c, e, "planner"); });
    // New costs need a new planner (its caches hold the old ones); the rate alone does not.
    if (*name != "rate") planner_ = GlobalPlanner(candidate);
    planner_config_ = candidate;
    return;
  }
  unknownKey();
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
