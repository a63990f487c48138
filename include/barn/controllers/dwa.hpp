#pragma once
/// `dwa` and `dwa_fast`: the BARN baseline, base_local_planner's TrajectoryPlanner in DWA
/// mode on a move_base-like stack (nav::NavStack) with ROS NavFn as the global planner, as
/// BARN's move_base ran it, and move_base's recovery.
///
/// Each control tick samples vx_samples x vtheta_samples (v, w) pairs in the dynamic window
/// (current velocity +- acceleration x control period, within the limits), rolls each out for
/// sim_time (accelerating toward the sample at the limits), and scores it
///   pdist_scale * (distance of its last point to the global path)
/// + gdist_scale * (distance of its last point to the local goal)
/// + occdist_scale * (highest costmap cost under the footprint outline along it),
/// distances counted in cells (x resolution with meter_scoring) along the local costmap
/// (4-connected wavefronts, as MapGrid; cells under the robot are passable for the path map).
/// A roll-out whose footprint outline touches a lethal cell is invalid (-1); one that passes a
/// point from which the path or local goal cannot be reached is invalid (-2). Then in-place
/// rotations may replace the best arc (toward the local goal, with the stuck_left/right guard
/// against oscillation). If nothing is valid the robot backs up blindly at escape_vel, even
/// when the map says the back-up hits (-1), and only "no way on" (-2) stops it; it escapes
/// (rotations and back-up only) until it has moved escape_reset_dist or turned
/// escape_reset_theta. A cycle without a valid command stops the robot until the global
/// planner finds a path again (move_base's PLANNING state). If no command is valid for
/// controller_patience seconds, or no plan is found for planner_patience seconds while waiting,
/// move_base's recoveries run (MoveBase, move_base.hpp); after them the robot gives up, as
/// move_base aborts.

#include <span>
#include <string>
#include <string_view>
#include <vector>

#include "barn/controllers/controller.hpp"
#include "barn/core/config.hpp"
#include "barn/controllers/move_base.hpp"
#include "barn/core/errors.hpp"
#include "barn/nav/nav_stack.hpp"

namespace barn::controllers {

/// move_base's patience and recoveries (controllers/move_base.hpp).
using DwaRecoveryConfig = MoveBaseRecoveryConfig;

/// Each field's unit, range and meaning are in visit(); the values are BARN's move_base
/// parameters where configs/controllers/dwa.yaml lists them, base_local_planner's otherwise.
struct DwaConfig {
  double rate = 20.0;
  double max_vel_x = 0.5;             // fast_dwa: 1.0
  double min_vel_x = 0.1;
  double max_vel_theta = 1.57;
  double min_in_place_vel_theta = 0.314;
  double acc_lim_x = 10.0;
  double acc_lim_theta = 20.0;
  double sim_time = 2.0;
  double sim_granularity = 0.02;
  double angular_sim_granularity = 0.02;
  int vx_samples = 6;                 // fast_dwa: 12
  int vtheta_samples = 20;
  double pdist_scale = 0.75;
  double gdist_scale = 1.0;
  double occdist_scale = 0.1;         // never scaled by the resolution (upstream since 2018)
  // meter_scoring: the path and goal distances count in metres (x resolution) rather than
  // cells. Upstream decides this from a member it never assigns; BARN's config asks for it,
  // and per metre matches Gazebo's per-world times (docs/fidelity.md).
  bool meter_scoring = true;
  double scoring_window = 3.0;        // our choice (ROS: the whole 10 x 10 m local map)
  double escape_vel = -0.5;
  double escape_reset_dist = 0.1;
  double escape_reset_theta = 0.1;
  double oscillation_reset_dist = 0.05;
  double heading_lookahead = 0.325;
  DwaRecoveryConfig recovery;
  nav::NavStackConfig nav = nav::NavStackConfig::moveBaseWithNavFn();  // docs/fidelity.md, "The global planner"

  template <class V> void visit(V& v) {
    using core::kPositive, core::kNonNegative;
    v("rate", rate, {.unit = "Hz", .range = kPositive, .doc = "controller_frequency"});
    v("max_vel_x", max_vel_x, {.unit = "m/s", .range = kPositive, .doc = "fastest forward speed"});
    v("min_vel_x", min_vel_x, {.unit = "m/s", .range = kNonNegative, .doc = "slowest forward speed sampled (<= max_vel_x)"});
    v("max_vel_theta", max_vel_theta, {.unit = "rad/s", .range = kPositive, .doc = "fastest turn (the window is symmetric)"});
    v("min_in_place_vel_theta", min_in_place_vel_theta,
      {.unit = "rad/s", .range = kNonNegative, .doc = "slowest in-place rotation"});
    v("acc_lim_x", acc_lim_x, {.unit = "m/s^2", .range = kPositive, .doc = "acceleration limit"});
    v("acc_lim_theta", acc_lim_theta, {.unit = "rad/s^2", .range = kPositive, .doc = "angular acceleration limit"});
    v("sim_time", sim_time, {.unit = "s", .range = kPositive, .doc = "roll-out horizon"});
    v("sim_granularity", sim_granularity, {.unit = "m", .range = kPositive, .doc = "step of the roll-out"});
    v("angular_sim_granularity", angular_sim_granularity, {.unit = "rad", .range = kPositive, .doc = "angular step of the roll-out"});
    v("vx_samples", vx_samples, {.range = core::atLeast(2), .doc = "forward speeds sampled"});
    v("vtheta_samples", vtheta_samples, {.range = core::atLeast(2), .doc = "turn rates sampled"});
    v("pdist_scale", pdist_scale, {.range = kNonNegative, .doc = "weight of the distance to the global path"});
    v("gdist_scale", gdist_scale, {.range = kNonNegative, .doc = "weight of the distance to the local goal"});
    v("occdist_scale", occdist_scale, {.range = kNonNegative, .doc = "weight of the highest cost under the footprint"});
    v("meter_scoring", meter_scoring, {.doc = "path and goal distances in metres rather than cells"});
    v("scoring_window", scoring_window,
      {.unit = "m", .range = kPositive, .doc = "half-size of the window the path and goal distances are computed in"});
    v("escape_vel", escape_vel, {.unit = "m/s", .range = core::below(0.0), .doc = "back-up speed when nothing is valid (backwards)"});
    v("escape_reset_dist", escape_reset_dist, {.unit = "m", .range = kPositive, .doc = "escaping ends after backing this far ..."});
    v("escape_reset_theta", escape_reset_theta, {.unit = "rad", .range = kPositive, .doc = "... or turning this much"});
    v("oscillation_reset_dist", oscillation_reset_dist,
      {.unit = "m", .doc = "moving this far from the last in-place turn forgets the stuck rotations"});
    v("heading_lookahead", heading_lookahead, {.unit = "m", .doc = "how far ahead a rotation's end heading is judged"});
    v("recovery", recovery);
    v("nav", nav);
  }
};
void validate(const DwaConfig& config, core::Errors& errors, const std::string& prefix);

class DwaSearch;

class DwaController : public Controller {
 public:
  explicit DwaController(const DwaConfig& config);
  ~DwaController() override;
  void reset(const EpisodeInfo& info) override;
  core::Twist act(const Observation& observation) override;
  double period() const override { return 1.0 / config_.rate; }
  std::string_view stateLabel() const override;

  const nav::NavStack& navStack() const { return nav_; }
  /// The parameters in force (the configured ones, changed by setParameter()).
  const DwaConfig& parameters() const { return config_; }

  /// Changes a parameter while running, as dynamic_reconfigure does on move_base's
  /// TrajectoryPlannerROS (its reconfigure takes every value from the next cycle on). The
  /// planner's keys: max_vel_x, max_vel_theta (the window is symmetric: min_vel_theta is its
  /// negative), vx_samples and vtheta_samples (whole numbers: the sampling grid of the next
  /// act()), pdist_scale, gdist_scale and occdist_scale. Any other key goes to the stack
  /// (nav::NavStack::setParameter: e.g. `global_costmap.inflation_radius`, applied at that
  /// map's next update, as costmap_2d applies a reconfigure). reset() restores the configured
  /// values. Throws std::invalid_argument naming the key for a key neither takes or a value
  /// the config's validate() refuses.
  void setParameter(std::string_view key, double value);
  /// The planner's keys setParameter() takes (the stack's: nav::NavStack::settableParameters()).
  static const std::vector<std::string>& settableParameters();
  /// TrajectoryPlanner's escape flag: set by a blind back-up, cleared after escape_reset_dist
  /// or escape_reset_theta.
  bool escaping() const;

 private:
  DwaConfig config_;      // in force: the configured values changed by setParameter()
  DwaConfig configured_;  // what reset() restores
  nav::NavStack nav_;
  EpisodeInfo info_;
  MoveBase move_base_;
  std::unique_ptr<DwaSearch> search_;  // TrajectoryPlanner: reads config_
};

}  // namespace barn::controllers
