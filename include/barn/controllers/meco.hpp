#pragma once
/// `meco`: the MECO Barners' (KU Leuven MECO group) 2023 BARN entry, 0.1829 (k = 4): free
/// space as a tree of rectangular corridors, driven through with geometric manoeuvres.
///
/// Four ROS nodes in the team's stack, one controller here, ticked at the controller's 100 Hz:
///  1. the sweeper/fitter (meco_fitter.hpp), every 0.5 s: the two best new corridors from the scan;
///  2. the manager (meco_manager.hpp), every 0.1 s: the corridor tree, the corridor to drive in
///     next, backtracking out of dead ends;
///  3. the navigator (MecoNavigator), every 0.1 s: keeps the list of corridors to drive through
///     and plans a manoeuvre (meco_motion.hpp) through the first two, to the goal once a corridor
///     holds it (its last segment at final_speed), or back out through a backtracking list at
///     backtrack_gain x the speed bounds, the reversed plan's speeds negated;
///  4. the controller, every 0.01 s: expands the latest manoeuvre into one command per tick (a
///     first segment shorter than stretch_duration at >= stretch_min_speed followed by one at
///     <= stretch_next_max_speed is stretched to stretch_duration first), and filters it:
///     cmd = filter_gain x new + (1 - filter_gain) x previous, then v = 0 when |w| >
///     turn_stop_rate and v < turn_stop_speed (filterCommand).
/// In one tick the nodes due run in that order, each seeing what the one before published.
///
/// Pose: the team's nodes read /pose_map, gmapping's map-frame pose; here the odometry (odom
/// frame: the start at the origin facing +y, the goal 10 m ahead, as the team's map frame).
/// Nothing of theirs reads gmapping's map itself, so no grid stands in for it.
///
/// Source: meco-group/Barn_challenge@66cef2c (MIT), corridors/scripts/; facts restated, no
/// code copied. configs/controllers/meco.yaml gives every default's source;
/// docs/systems/meco.md the method, what differs and the measurements.

#include <optional>
#include <span>
#include <string>
#include <string_view>
#include <vector>

#include "barn/controllers/controller.hpp"
#include "barn/controllers/meco_corridor.hpp"
#include "barn/controllers/meco_fitter.hpp"
#include "barn/controllers/meco_manager.hpp"
#include "barn/controllers/meco_motion.hpp"
#include "barn/core/config.hpp"
#include "barn/core/errors.hpp"

namespace barn::controllers {

struct MecoNavigatorConfig {
  double rate = 10.0;
  double robot_length = 0.43;
  double margin = 0.10;
  double max_speed = 0.5;
  double max_turn_rate = 0.3;
  double backtrack_gain = 0.75;
  double goal_offset = 0.3;
  double final_speed = 2.0;
  double semi_backtrack_fraction = 0.8;
  double min_radius = 1e-3;
  double inside_tolerance = 1e-3;

  template <class V> void visit(V& v) {
    v("rate", rate, {.unit = "Hz", .range = core::kPositive, .doc = "team: navigator_rate"});
    v("robot_length", robot_length, {.unit = "m", .range = core::kPositive, .doc = "team: a"});
    v("margin", margin, {.unit = "m", .range = core::kNonNegative, .doc = "team: m"});
    v("max_speed", max_speed,
      {.unit = "m/s", .range = core::kPositive, .doc = "team: v_max (v_min -0.5 bounds nothing the planner uses)"});
    v("max_turn_rate", max_turn_rate, {.unit = "rad/s", .range = core::kPositive, .doc = "team: omega_max"});
    v("backtrack_gain", backtrack_gain,
      {.range = core::kPositive, .doc = "team (submission): backtracking at 0.75 x the bounds"});
    v("goal_offset", goal_offset,
      {.unit = "m", .range = core::kNonNegative, .doc = "team: goal point 0.3 m short of a corridor's front edge"});
    v("final_speed", final_speed,
      {.unit = "m/s", .range = core::kPositive, .doc = "team: the last segment toward the goal"});
    v("semi_backtrack_fraction", semi_backtrack_fraction,
      {.range = core::kUnit, .doc = "team: reverse 0.8 of the way from the back edge to the corner"});
    v("min_radius", min_radius, {.unit = "m", .range = core::kPositive, .doc = "team: the alignment radius's floor"});
    v("inside_tolerance", inside_tolerance,
      {.unit = "m", .range = core::kNonNegative, .doc = "team: check_inside_one_point's tolerance"});
  }
};
void validate(const MecoNavigatorConfig& config, core::Errors& errors, const std::string& prefix);

struct MecoConfig {
  double rate = 100.0;
  double filter_gain = 0.05;
  double stretch_duration = 1.0;
  double stretch_min_speed = 0.4;
  double stretch_next_max_speed = 0.1;
  double turn_stop_rate = 0.2;
  double turn_stop_speed = 0.1;
  MecoFitterConfig fitter;
  MecoManagerConfig manager;
  MecoNavigatorConfig navigator;

  template <class V> void visit(V& v) {
    v("rate", rate, {.unit = "Hz", .range = core::kPositive, .doc = "team: controller_rate"});
    v("filter_gain", filter_gain, {.range = core::openClosed(0.0, 1.0), .doc = "team: cmd = 0.05 new + 0.95 previous"});
    v("stretch_duration", stretch_duration,
      {.unit = "s", .range = core::kNonNegative, .doc = "team: a shorter first segment is stretched to 1 s"});
    v("stretch_min_speed", stretch_min_speed, {.unit = "m/s", .doc = "team: ... when it runs at >= 0.4 m/s"});
    v("stretch_next_max_speed", stretch_next_max_speed, {.unit = "m/s", .doc = "team: ... and the next at <= 0.1 m/s"});
    v("turn_stop_rate", turn_stop_rate,
      {.unit = "rad/s", .range = core::kNonNegative, .doc = "team: v = 0 when |w| > 0.2 ..."});
    v("turn_stop_speed", turn_stop_speed, {.unit = "m/s", .doc = "team: ... and v < 0.1"});
    v("fitter", fitter);
    v("manager", manager);
    v("navigator", navigator);
  }
};
void validate(const MecoConfig& config, core::Errors& errors, const std::string& prefix);

/// The planner's parameters from the navigator's, the speed bounds scaled by `gain`.
MecoPlannerParams plannerParams(const MecoNavigatorConfig& config, double gain = 1.0);

/// The navigator (navigator.py): the list of corridors to drive through, from the manager's
/// messages, and a manoeuvre each cycle that needs one.
///  - Next: appended to the list (after a backtrack, the list restarts from the corridor the
///    backtrack returned to). Final: the list is that corridor alone; later messages are ignored.
///    Backtrack: the list is the backtracking route.
///  - Each cycle, driving forward: the first corridor is dropped once the robot is in the
///    second (this cycle still plans with both). Goal outside the first corridor: plan() through
///    the first two. Goal inside: once, plan() to the goal with the last segment at
///    final_speed; afterwards again only when the heading is off the goal's bearing by at least
///    atan((width / 2 - a / 2 - m) / distance).
///  - Backtracking: once per route, planSequence() through the route's corridors turned round,
///    from the robot turned round, to the front of the corridor returned to (moved m back), at
///    backtrack_gain x the bounds; the speeds negated.
class MecoNavigator {
 public:
  explicit MecoNavigator(const MecoNavigatorConfig& config) : config_(config) {}
  void reset();
  void receive(std::span<const MecoMessage> messages);
  /// One cycle: the manoeuvre to hand the controller, if any.
  std::optional<MecoManoeuvre> tick(const core::Pose2& pose, const Eigen::Vector2d& goal);

  const std::vector<MecoCorridor>& corridors() const { return corridors_; }
  bool backtracking() const { return backtracking_; }
  bool headingToGoal() const { return heading_to_goal_; }

 private:
  MecoNavigatorConfig config_;
  std::vector<MecoCorridor> corridors_;
  bool backtracking_ = false;
  bool backtrack_planned_ = false;
  bool goal_in_sight_ = false;
  bool heading_to_goal_ = false;
};

/// The controller's segment rule: a first segment shorter than stretch_duration, at
/// >= stretch_min_speed, followed by one at <= stretch_next_max_speed, lasts stretch_duration.
void stretchFirstSegment(std::vector<MecoSegment>& segments, const MecoConfig& config);

/// One command per tick at `rate`: each segment repeated floor(duration x rate) times (Python's
/// int()); segments with a NaN or negative duration are skipped.
std::vector<core::Twist> expandSegments(std::span<const MecoSegment> segments, double rate);

/// The output filter: filter_gain x `target` + (1 - filter_gain) x `previous`, then v = 0 when
/// |w| > turn_stop_rate and v < turn_stop_speed.
core::Twist filterCommand(const core::Twist& previous, const core::Twist& target, const MecoConfig& config);

class MecoController : public Controller {
 public:
  explicit MecoController(const MecoConfig& config);
  void reset(const EpisodeInfo& info) override;
  core::Twist act(const Observation& observation) override;
  double period() const override { return 1.0 / config_.rate; }
  std::string_view stateLabel() const override { return core::enumName(manager_.phase()); }

  const MecoManager& manager() const { return manager_; }
  const MecoNavigator& navigator() const { return navigator_; }

 private:
  MecoConfig config_;
  MecoManager manager_;
  MecoNavigator navigator_;
  EpisodeInfo info_;
  long fitter_every_ = 50;    // control ticks per fitter cycle
  long manager_every_ = 10;   // ... per manager cycle
  long navigator_every_ = 10; // ... per navigator cycle
  long tick_ = 0;
  std::vector<core::Twist> queue_;  // the manoeuvre, one command per tick
  std::size_t next_ = 0;            // the queue's next command
  core::Twist last_;                // the last command sent
};

}  // namespace barn::controllers
