#include "barn/controllers/dwa.hpp"

#include <algorithm>
#include <cmath>
#include <limits>
#include <optional>
#include <stdexcept>

#include "dwa_search.hpp"

namespace barn::controllers {


void validate(const DwaConfig& c, core::Errors& errors, const std::string& prefix) {
  core::validateFields(c, errors, prefix);
  errors.check(c.min_vel_x <= c.max_vel_x, prefix + ".min_vel_x", "must be <= max_vel_x");
  validate(c.recovery, errors, prefix + ".recovery");
  nav::validate(c.nav, errors, prefix + ".nav");
}

DwaController::DwaController(const DwaConfig& config)
    : config_(config), configured_(config), nav_(config.nav), move_base_(config.recovery),
      search_(std::make_unique<DwaSearch>(config_, nav_.paddedFootprint())) {}

DwaController::~DwaController() = default;

bool DwaController::escaping() const { return search_->escaping(); }

void DwaController::reset(const EpisodeInfo& info) {
  info_ = info;
  config_ = configured_;  // parameters set while running go back to the configured ones
  nav_.reset(info.goal);
  move_base_.reset();
  search_->reset();
}

const std::vector<std::string>& DwaController::settableParameters() {
  static const std::vector<std::string> kKeys = {"max_vel_x",   "max_vel_theta", "vx_samples",   "vtheta_samples",
                                                 "pdist_scale", "gdist_scale",   "occdist_scale"};
  return kKeys;
}

void DwaController::setParameter(std::string_view key, double value) {
  const std::string name(key);
  const auto in = [&](const std::vector<std::string>& keys) { return std::find(keys.begin(), keys.end(), name) != keys.end(); };
  if (!in(settableParameters())) {
    if (!in(nav::NavStack::settableParameters())) {
      std::string known;
      for (const auto* keys : {&settableParameters(), &nav::NavStack::settableParameters()})
        for (const std::string& k : *keys) known += (known.empty() ? "" : ", ") + k;
      throw std::invalid_argument(name + ": not a settable parameter (settable: " + known + ")");
    }
    nav_.setParameter(key, value);
    return;
  }
  if (!std::isfinite(value)) throw std::invalid_argument(name + ": must be a finite number");
  // Checked by validate() on a copy with the new value, so a value is refused exactly where the
  // config file's would be.
  DwaConfig candidate = config_;
  if (name == "vx_samples" || name == "vtheta_samples") {
    if (value != std::floor(value) || std::abs(value) > 1e6) throw std::invalid_argument(name + ": must be a whole number");
    (name == "vx_samples" ? candidate.vx_samples : candidate.vtheta_samples) = static_cast<int>(value);
  } else if (name == "max_vel_x") {
    candidate.max_vel_x = value;
  } else if (name == "max_vel_theta") {
    candidate.max_vel_theta = value;
  } else if (name == "pdist_scale") {
    candidate.pdist_scale = value;
  } else if (name == "gdist_scale") {
    candidate.gdist_scale = value;
  } else {
    candidate.occdist_scale = value;
  }
  core::Errors errors;
  validate(candidate, errors, "dwa");
  if (!errors.empty()) throw std::invalid_argument(errors.messages().front());
  config_ = candidate;
}

std::string_view DwaController::stateLabel() const {
  // move_base's CONTROLLING keeps the planner's name for the state label.
  switch (move_base_.mode()) {
    case MoveBase::Mode::Controlling: return search_->escaping() ? "escaping" : "planning";
    case MoveBase::Mode::WaitingForPlan: return "waiting";
    case MoveBase::Mode::RecoveryRotate: return "recovery";
    case MoveBase::Mode::Aborted: return "aborted";
  }
  return "";
}

core::Twist DwaController::act(const Observation& obs) {
  const core::Pose2 pose = obs.odom_pose;
  nav_.update(obs.time, *obs.scan, info_.lidar.sensorPose(obs.scan_odom_pose), pose);

  if (const auto command = move_base_.beforeController(obs, nav_)) return *command;
  const nav::Costmap& local = nav_.localCostmap();
  search_->updateDistanceMaps(local, nav_.hasPath() ? &nav_.path() : nullptr, pose);
  const DwaTrajectory best = search_->findBestPath(local, pose, obs.odom_twist);
  return move_base_.afterController(obs, nav_, best.cost >= 0.0 ? std::optional<core::Twist>(core::Twist{best.vx, best.vtheta})
                                                                 : std::nullopt);
}

}  // namespace barn::controllers
