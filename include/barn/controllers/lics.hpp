#pragma once
/// `lics`: the LiCS-KI controller (KAIST, BARN Challenge 2024 winner) as the team's simulation
/// code ran it (damanikjosh/the-barn-challenge@9971a42: lics/scripts/run.py,
/// lics/scripts/env/robot.py, lics/config/config.yaml, jackal_helper's move_base launch and
/// params). Their ROS node's callbacks and move_base run here once per control tick (20 Hz):
///
///  1. Odometry: the global costmap's inflation radius from the odometry speed v [m/s]. The node
///     divides v by max_speed, then the formula divides by max_speed again:
///         r = min_r + (v / vmax - t) / (vmax - t) (max_r - min_r)   if v / vmax > t, else min_r
///     with min_r 0.3, max_r 1.0, vmax 1.5, t 0: r = 0.3 + 0.311 v (0.767 m at 1.5 m/s). It is
///     set through dynamic_reconfigure, which costmap_2d applies at the map's next update (10 Hz):
///     here nav::NavStack::setParameter before the stack's update.
///  2. move_base: the costmaps and GlobalPlanner (Dijkstra: their misspelt `use_djikstra` key
///     leaves use_dijkstra at its default true) with cost_factor 3, replanning at 20 Hz.
///  3. Plan: a found plan is smoothed (Savitzky-Golay, window 19, order 3, on x and y apart;
///     shorter plans raw), moved into the robot frame with the odometry of that moment, and gives
///     the local goal (licsLocalGoal); the speed multiplier is set to 1. A plan that found
///     nothing (ROS publishes an empty path) sets the multiplier to 0.3 and keeps the goal.
///  4. Scan: the multiplier is set to m = f / 2.5 when the nearest return f over beams 253-466
///     (about +-40 deg; ranges clipped to [0, 5] m) is below 2.5 m, else to 1.
///  Control tick: the transformer (learning::TransformerPolicy) on the clipped scan and the local
///  goal gives (v_hat, w_hat); v = clip(1.5 m v_hat, -0.5, 1.5), w = clip(1.2 w_hat, -1.2, 1.2),
///  with m the multiplier in force.
///
/// The race. Callbacks 3 and 4 both write the multiplier, and whichever ran last before the tick
/// decides it: the slow-down is lost on ticks where a plan (20 Hz) arrived after the latest scan
/// (50 Hz). barnbench models it deterministically: the plan callback is taken to finish
/// `plan_phase` seconds before the tick at which the stack makes the plan, the scan callback at
/// the scan's stamp, and the later one wins (a tie goes to the plan). With 20 Hz ticks and 50 Hz
/// scans the scan a tick reads is 0 or 10 ms old, alternately, so plan_phase 0 loses the
/// slow-down on every tick, 0 < plan_phase <= 0.01 s on every other tick, and plan_phase > 0.01 s
/// never (docs/systems/lics.md says which one the default is and why).
///
/// configs/controllers/lics.yaml says for every default whether it is the team's (with its
/// source) or our choice.

#include <memory>
#include <string>
#include <string_view>
#include <vector>

#include <Eigen/Core>

#include "barn/controllers/controller.hpp"
#include "barn/core/config.hpp"
#include "barn/core/errors.hpp"
#include "barn/learning/transformer_policy.hpp"
#include "barn/nav/nav_stack.hpp"
#include "barn/nav/savitzky_golay.hpp"

namespace barn::controllers {

struct LicsConfig {
  // The policy file (`barnbench-transformer-policy`), relative to the config file's folder;
  // tools/import_lics_weights.py writes it from the published transformer_99.pth.
  std::string policy = "configs/policies/lics_transformer_99.policy";
  double rate = 20.0;
  double local_goal_distance = 2.0;
  double plan_start_tolerance = 0.05;
  int smoothing_window = 19;
  int smoothing_order = 3;
  double max_speed = 1.5;
  double min_speed = -0.5;
  double max_turn_rate = 1.2;
  double min_turn_rate = -1.2;
  double slow_down_distance = 2.5;
  int front_first_beam = 253;
  int front_last_beam = 466;
  double empty_plan_multiplier = 0.3;
  bool dynamic_inflation = true;
  double min_inflation_radius = 0.3;
  double max_inflation_radius = 1.0;
  double inflation_speed_threshold = 0.0;
  double plan_phase = 0.02;
  nav::NavStackConfig nav = licsNav();

  template <class V> void visit(V& v) {
    v("policy", policy);
    v("rate", rate, {.unit = "Hz", .range = core::kPositive, .doc = "team: run.py CONTROL_FREQ 20"});
    v("local_goal_distance", local_goal_distance,
      {.unit = "m", .range = core::kPositive, .doc = "team: config.yaml los 2.0"});
    v("plan_start_tolerance", plan_start_tolerance,
      {.unit = "m", .range = core::kNonNegative, .doc = "team: robot.py, the plan's first point is the origin if farther"});
    v("smoothing_window", smoothing_window, {.doc = "team: robot.py savgol_filter(x, 19, 3)"});
    v("smoothing_order", smoothing_order, {.doc = "team"});
    v("max_speed", max_speed,
      {.unit = "m/s", .range = core::kPositive, .doc = "team: config.yaml max_v (v = v_hat x 1.5 x m)"});
    v("min_speed", min_speed, {.unit = "m/s", .doc = "team: config.yaml min_v"});
    v("max_turn_rate", max_turn_rate,
      {.unit = "rad/s", .range = core::kPositive, .doc = "team: config.yaml max_w (w = w_hat x 1.2)"});
    v("min_turn_rate", min_turn_rate, {.unit = "rad/s", .doc = "team: config.yaml min_w"});
    v("slow_down_distance", slow_down_distance,
      {.unit = "m", .range = core::kPositive, .doc = "team: config.yaml threshold_dist"});
    v("front_first_beam", front_first_beam, {.doc = "team: robot.py laser[253:467]"});
    v("front_last_beam", front_last_beam, {.doc = "team (inclusive)"});
    v("empty_plan_multiplier", empty_plan_multiplier,
      {.range = core::kNonNegative, .doc = "team: robot.py, an empty plan"});
    v("dynamic_inflation", dynamic_inflation,
      {.doc = "team: robot.py sets the global inflation radius from the speed"});
    v("min_inflation_radius", min_inflation_radius,
      {.unit = "m", .range = core::kNonNegative, .doc = "team: config.yaml"});
    v("max_inflation_radius", max_inflation_radius, {.unit = "m", .doc = "team: config.yaml"});
    v("inflation_speed_threshold", inflation_speed_threshold,
      {.doc = "team: config.yaml threshold_v (compared with v / max_speed)"});
    v("plan_phase", plan_phase,
      {.unit = "s", .doc = "our choice: the race model (header comment, docs/systems/lics.md)"});
    v("nav", nav);
  }

  /// The team's move_base (jackal_helper/launch/move_base.launch and configs/params at
  /// 9971a42): GlobalPlanner (Dijkstra, cost_factor 3) at 20 Hz; footprint 0.42 x 0.33 + 0.1
  /// padding (inscribed radius 0.265); the scan marks to 4.5 m and clears to 5.0 m; inflation
  /// 0.30 at costmap_2d's default scaling 10; global costmap at 10 Hz, local at 20 Hz (read by
  /// nothing here).
  static nav::NavStackConfig licsNav();
};
void validate(const LicsConfig& config, core::Errors& errors, const std::string& prefix);

/// The policy file at `path`, or an InputError that names it and, if it is missing, the command
/// that writes it from the published weights.
std::shared_ptr<const learning::TransformerPolicy> loadLicsPolicy(const std::string& path);

/// [m] the global inflation radius the odometry callback sets at odometry speed `speed` [m/s]
/// (header comment, step 1).
double licsInflationRadius(double speed, const LicsConfig& config);

/// [-] the scan callback's speed multiplier: nearest range over beams front_first_beam ...
/// front_last_beam (clipped to [0, clip], +inf and NaN read as clip), divided by
/// slow_down_distance if below it, else 1.
double licsFrontMultiplier(const core::LaserScan& scan, double clip, const LicsConfig& config);

/// The plan callback's local goal: a unit vector in the robot frame. `plan` is the smoothed plan
/// in the robot frame. The origin is the robot, or the plan's first point if that is farther than
/// plan_start_tolerance; the goal is the direction from the origin to the first point farther
/// than local_goal_distance from it (else the last point). (0, 0) for an empty plan, or if that
/// point is the origin itself (the original divides by zero there).
Eigen::Vector2d licsLocalGoal(const std::vector<Eigen::Vector2d>& plan_robot_frame, const LicsConfig& config);

/// The race (header comment): whether the plan callback wrote the multiplier last. `plan_time`
/// [s] is when the stack made the latest plan (the tick's time), `scan_stamp` [s] the latest
/// scan's.
bool licsPlanWritesLast(double plan_time, double scan_stamp, double plan_phase);

class LicsController : public Controller {
 public:
  LicsController(const LicsConfig& config, std::shared_ptr<const learning::TransformerPolicy> policy);
  void reset(const EpisodeInfo& info) override;
  core::Twist act(const Observation& observation) override;
  double period() const override { return 1.0 / config_.rate; }
  void checkLidar(const core::LidarConfig& lidar) const override;
  /// The global inflation radius set in the last act(), as `global_costmap.inflation_radius=r`.
  std::string_view parameterChanges() const override { return parameter_changes_; }

  const nav::NavStack& navStack() const { return nav_; }
  const Eigen::Vector2d& localGoal() const { return local_goal_; }  // robot frame at its plan
  double multiplier() const { return multiplier_; }                 // [-] in force at the last tick

 private:
  LicsConfig config_;
  std::shared_ptr<const learning::TransformerPolicy> policy_;
  nav::NavStack nav_;
  nav::SavitzkyGolay smoother_;
  EpisodeInfo info_;
  Eigen::Vector2d local_goal_ = Eigen::Vector2d::Zero();
  double plan_multiplier_ = 1.0;  // what the latest plan callback wrote
  double last_plan_time_ = 0.0;   // [s]
  bool planned_ = false;          // a plan callback has run this episode
  double multiplier_ = 1.0;
  std::string parameter_changes_;
};

}  // namespace barn::controllers
