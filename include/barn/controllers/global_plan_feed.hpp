#pragma once
/// `global_plan`: move_base's global plan, and on request its costmaps, for a controller that
/// is only a local planner, as a Nav2 controller plugin is handed its plan by setPlan.
///
/// A `global_plan` block beside `type` in any controller config runs barnbench's move_base-like
/// stack (nav::NavStack) beside the controller, in simulated time: at every control tick the
/// stack folds in the tick's scan at its costmaps' update rates and replans at the planner's
/// rate, exactly as it does inside the built-in controllers, and the observation carries the
/// plan (Observation::global_plan) and the requested costmaps. The controller may change the
/// stack's settable parameters while it runs (Observation::stack_parameters), as a ROS node
/// calls dynamic_reconfigure on move_base.

#include <memory>
#include <string>
#include <string_view>

#include "barn/controllers/controller.hpp"
#include "barn/core/config.hpp"
#include "barn/core/errors.hpp"
#include "barn/nav/nav_stack.hpp"

namespace barn::controllers {

struct GlobalPlanConfig {
  // The stack: costmaps, footprint and planner, with the keys of nav::NavStackConfig. The
  // defaults are BARN's move_base as its DWA and E-Band baselines ran it (NavFn at 20 Hz).
  nav::NavStackConfig stack = nav::NavStackConfig::moveBaseWithNavFn();
  bool send_local_costmap = false;
  bool send_global_costmap = false;

  template <class V> void visit(V& v) {
    stack.visit(v);
    v("send_local_costmap", send_local_costmap, {.doc = "the observation carries the local costmap"});
    v("send_global_costmap", send_global_costmap, {.doc = "... and/or the global one"});
  }
};

void validate(const GlobalPlanConfig& config, core::Errors& errors, const std::string& prefix);

/// The stack beside one controller, one episode at a time.
class GlobalPlanFeed : public StackParameters {
 public:
  explicit GlobalPlanFeed(const GlobalPlanConfig& config);

  /// New episode: empty costmaps, no plan, the configured parameters.
  void reset(const EpisodeInfo& info);
  /// Folds in the observation's scan and odometry, replans when due, and points the
  /// observation's plan, costmap and parameter fields at this feed (valid until the next
  /// update). Clears the record of parameter changes.
  void update(Observation& observation);
  /// StackParameters: nav::NavStack::setParameter, recorded for parameterChanges().
  void set(std::string_view key, double value) override;
  /// The parameters set since the last update(), as `key=value;...`.
  std::string_view changes() const { return changes_; }
  const nav::NavStack& stack() const { return stack_; }

 private:
  GlobalPlanConfig config_;
  nav::NavStack stack_;
  core::LidarConfig lidar_;
  GlobalPlan plan_;
  int plans_seen_ = 0;  // stack_.plansMade() when plan_ was last taken
  CostGrid local_costmap_;
  CostGrid global_costmap_;
  std::string changes_;
};

/// A controller given move_base's plan: the feed updates each observation before `inner`
/// acts on it.
class GlobalPlanFedController : public Controller {
 public:
  GlobalPlanFedController(const GlobalPlanConfig& config, std::unique_ptr<Controller> inner);
  void reset(const EpisodeInfo& info) override;
  core::Twist act(const Observation& observation) override;
  double period() const override { return inner_->period(); }
  std::string_view stateLabel() const override { return inner_->stateLabel(); }
  void checkLidar(const core::LidarConfig& lidar) const override { inner_->checkLidar(lidar); }
  std::uint64_t trainedPlant() const override { return inner_->trainedPlant(); }
  std::string_view parameterChanges() const override { return feed_.changes(); }

 private:
  GlobalPlanFeed feed_;
  std::unique_ptr<Controller> inner_;
};

}  // namespace barn::controllers
