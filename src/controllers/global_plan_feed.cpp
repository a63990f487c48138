#include "barn/controllers/global_plan_feed.hpp"

#include <charconv>
#include <stdexcept>

namespace barn::controllers {

namespace {

CostGrid gridOf(const nav::Costmap& map) {
  CostGrid grid;
  grid.origin = map.origin();
  grid.resolution = map.resolution();
  grid.width = map.widthCells();
  grid.height = map.heightCells();
  grid.costs = map.costs();  // brings the inflation up to date
  grid.version = map.version();
  return grid;
}

}  // namespace

void validate(const GlobalPlanConfig& config, core::Errors& errors, const std::string& prefix) {
  nav::validate(config.stack, errors, prefix);
}

GlobalPlanFeed::GlobalPlanFeed(const GlobalPlanConfig& config) : config_(config), stack_(config.stack) {}

void GlobalPlanFeed::reset(const EpisodeInfo& info) {
  lidar_ = info.lidar;
  stack_.reset(info.goal);
  plan_ = {};
  plans_seen_ = 0;
  local_costmap_ = global_costmap_ = {};
  changes_.clear();
}

void GlobalPlanFeed::update(Observation& obs) {
  changes_.clear();
  stack_.update(obs.time, *obs.scan, lidar_.sensorPose(obs.scan_odom_pose), obs.odom_pose);
  // move_base publishes each plan it finds; a failed plan leaves the last one in force.
  if (stack_.plansMade() != plans_seen_) {
    plans_seen_ = stack_.plansMade();
    if (stack_.lastPlanFound()) {
      plan_.poses.clear();
      const nav::Path& path = stack_.path();
      for (std::size_t i = 0; i < path.size(); ++i) plan_.poses.push_back({path[i].x(), path[i].y(), stack_.pathYaw()[i]});
      plan_.stamp = obs.time;
    }
  }
  obs.global_plan = &plan_;
  if (config_.send_local_costmap) {
    local_costmap_ = gridOf(stack_.localCostmap());
    obs.local_costmap = &local_costmap_;
  }
  if (config_.send_global_costmap) {
    global_costmap_ = gridOf(stack_.globalCostmap());
    obs.global_costmap = &global_costmap_;
  }
  obs.stack_parameters = this;
}

void GlobalPlanFeed::set(std::string_view key, double value) {
  stack_.setParameter(key, value);
  char text[32];
  const auto end = std::to_chars(text, text + sizeof(text), value).ptr;  // shortest exact form
  if (!changes_.empty()) changes_ += ';';
  changes_.append(key).append("=").append(text, end);
}

GlobalPlanFedController::GlobalPlanFedController(const GlobalPlanConfig& config, std::unique_ptr<Controller> inner)
    : feed_(config), inner_(std::move(inner)) {}

void GlobalPlanFedController::reset(const EpisodeInfo& info) {
  feed_.reset(info);
  inner_->reset(info);
}

core::Twist GlobalPlanFedController::act(const Observation& observation) {
  Observation fed = observation;
  feed_.update(fed);
  return inner_->act(fed);
}

}  // namespace barn::controllers
