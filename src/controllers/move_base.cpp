#include "barn/controllers/move_base.hpp"

#include <algorithm>
#include <cmath>
#include <numbers>

#include "barn/nav/grid_line.hpp"

namespace barn::controllers {

void validate(const MoveBaseRecoveryConfig& r, core::Errors& errors, const std::string& prefix) {
  errors.check(r.controller_patience > 0.0, prefix + ".controller_patience", "must be > 0");
  errors.check(r.planner_patience > 0.0, prefix + ".planner_patience", "must be > 0");
  errors.check(r.max_rotation_speed > 0.0, prefix + ".max_rotation_speed", "must be > 0");
  errors.check(r.min_rotation_speed > 0.0 && r.min_rotation_speed <= r.max_rotation_speed,
               prefix + ".min_rotation_speed", "must be in (0, max_rotation_speed]");
  errors.check(r.rotation_acceleration > 0.0, prefix + ".rotation_acceleration", "must be > 0");
  errors.check(r.rotation_tolerance > 0.0, prefix + ".rotation_tolerance", "must be > 0");
  errors.check(r.sweep_step > 0.0, prefix + ".sweep_step", "must be > 0");
}

bool footprintOutlineHits(const nav::Costmap& map, const std::vector<Eigen::Vector2d>& footprint, double x, double y,
                          double yaw) {
  const double c = std::cos(yaw), s = std::sin(yaw);
  std::vector<nav::CellIndex> corners(footprint.size());
  for (std::size_t k = 0; k < footprint.size(); ++k) {
    const Eigen::Vector2d& p = footprint[k];
    if (!map.toCell(x + c * p.x() - s * p.y(), y + s * p.x() + c * p.y(), corners[k])) return true;
  }
  // Only the outline is walked; lethal and unknown are the two highest costs.
  for (std::size_t k = 0; k < corners.size(); ++k) {
    const nav::CellIndex a = corners[k], b = corners[(k + 1) % corners.size()];
    const bool clear = nav::walkLine(a.x, a.y, b.x, b.y, [&](int cx, int cy) { return map.cost(cx, cy) < nav::kLethalCost; });
    if (!clear) return true;
  }
  return false;
}

void MoveBase::reset() {
  mode_ = Mode::Controlling;
  last_valid_time_ = 0.0;
  recovery_index_ = 0;
  recovery_trigger_ = RecoveryTrigger::Controller;
  waiting_since_ = 0.0;
  rotated_ = 0.0;
  last_yaw_ = 0.0;
}

bool MoveBase::sweepClear(const nav::NavStack& nav, const core::Pose2& pose, double sweep) const {
  const nav::Costmap& map = nav.localCostmap();
  const std::vector<Eigen::Vector2d> footprint = nav.paddedFootprint();
  for (double turned = 0.0; turned <= sweep; turned += config_.sweep_step)
    if (footprintOutlineHits(map, footprint, pose.x, pose.y, pose.yaw + turned)) return false;
  return true;
}

core::Twist MoveBase::recover(const Observation& obs, nav::NavStack& nav) {
  // move_base runs its recoveries in order, each after a failing controller cycle, until
  // one lets the controller find a command again; after the last it aborts the goal.
  const core::Pose2& pose = obs.odom_pose;
  const MoveBaseRecoveryConfig& r = config_;
  if (mode_ == Mode::RecoveryRotate) {
    rotated_ += std::abs(core::wrapAngle(pose.yaw - last_yaw_));
    last_yaw_ = pose.yaw;
    const double remaining = 2.0 * std::numbers::pi - rotated_;
    if (remaining > r.rotation_tolerance && sweepClear(nav, pose, remaining)) {
      const double speed = std::clamp(std::sqrt(2.0 * r.rotation_acceleration * remaining), r.min_rotation_speed,
                                      r.max_rotation_speed);
      return {0.0, speed};
    }
    waitForPlan(obs.time);  // the turn is done (or would hit): plan again
    return {};
  }
  if (recovery_index_ >= 4) {
    mode_ = Mode::Aborted;
    return {};
  }
  const int step = recovery_index_++;
  if (step % 2 == 0) {
    if (r.clear_costmaps) {
      const double keep = step == 0 ? r.conservative_reset_distance : r.aggressive_reset_distance;
      nav.clearCostmapsOutside(pose.position(), keep);
    }
    waitForPlan(obs.time);
    return {};
  }
  mode_ = Mode::RecoveryRotate;
  rotated_ = 0.0;
  last_yaw_ = pose.yaw;
  return recover(obs, nav);
}

std::optional<core::Twist> MoveBase::beforeController(const Observation& obs, nav::NavStack& nav) {
  if (mode_ == Mode::Aborted) return core::Twist{};
  if (mode_ == Mode::RecoveryRotate) {
    const core::Twist turn = recover(obs, nav);
    if (mode_ == Mode::RecoveryRotate) return turn;
  }
  if (mode_ == Mode::WaitingForPlan) {
    // The plan of this cycle (NavStack::update) stands for the one move_base's planner thread
    // makes between two control cycles once woken.
    if (!nav.lastPlanFound()) {
      if (config_.enabled && obs.time - waiting_since_ > config_.planner_patience) {
        recovery_trigger_ = RecoveryTrigger::Planner;
        return recover(obs, nav);
      }
      return core::Twist{};
    }
    mode_ = Mode::Controlling;
  }
  // A new plan handed to the controller ends recoveries the planner started.
  if (recovery_trigger_ == RecoveryTrigger::Planner && nav.lastPlanFound()) recovery_index_ = 0;
  return std::nullopt;
}

core::Twist MoveBase::afterController(const Observation& obs, nav::NavStack& nav,
                                      const std::optional<core::Twist>& command) {
  if (command) {
    last_valid_time_ = obs.time;
    if (recovery_trigger_ == RecoveryTrigger::Controller) recovery_index_ = 0;
    return *command;
  }
  // A failed cycle publishes zero; after controller_patience, the recoveries; else it waits
  // for the planner.
  if (config_.enabled && obs.time - last_valid_time_ >= config_.controller_patience) {
    recovery_trigger_ = RecoveryTrigger::Controller;
    return recover(obs, nav);
  }
  waitForPlan(obs.time);
  return {};
}

void MoveBase::waitForPlan(double time) {
  mode_ = Mode::WaitingForPlan;
  waiting_since_ = time;
}

}  // namespace barn::controllers
