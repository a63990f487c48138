#pragma once
/// `kulfm`: KUL+FM-style (2025 logic) free-space motion tubes, after the KU Leuven + Flanders
/// Make entry that won BARN 2023. The node that ran in 2023 is not public; the logic here is
/// that of the same author's 2025 re-implementation (romulortr/fsmt_ros@75febc5), rebuilt from
/// its description, on the 2023 entry's move_base stack (romulortr/barn-kul-fm@e23b647).
///
/// The global plan comes from the move_base-like stack (NavFn on a LiDAR costmap, the team's
/// settings: kulfmNav()). Every tick (20 Hz):
///  1. The plan, in the robot frame, gives the local goal: the plan point where the arc length
///     walked from the first point reaches the tube length (0.75 m); its orientation is the
///     direction from the point `orientation_points` (10) indices earlier; the "head" orientation
///     is the direction from point 0 to point `head_points` (10). NavFn's points are half a
///     cell (0.025 m) apart, so 10 indices are about 0.25 m of plan.
///  2. Each of the 362 forward tubes (motion_tubes.hpp) whose edge is free is compared with the
///     best so far on five keys in turn: (a) the goal bin, floor(d / 0.2 m) + 1 for the distance d
///     from the local goal to the tube's end box (0 inside it); a tube more than one bin worse
///     than the best so far, or beyond bin 6, is dropped; (b) outer whisker free, then front
///     whisker free, then inner whisker free (free is better); (c) the orientation bin,
///     floor(|local goal orientation - tube heading change| / 20 deg), a tube more than 90 deg
///     off being dropped; (d) the change of turn rate |w_now - v_now / R| (0 when not driving
///     forward); (e) the signed distance d. At each key a tube better than the best becomes the
///     best at once (later keys are not looked at), a worse one is dropped, a tie goes on to the
///     next key; a tie on every key goes to the later tube. The feasible ratio is the share of
///     the 362 tubes whose edge is free.
///  3. The state machine (nextKulfmState) and each state's command:
///     Normal        (v, v / R) of the chosen tube; v from the feasible ratio (min_speed below
///                   low_ratio, max_speed above high_ratio, else 0.4 min + 0.6 max), changed by
///                   at most max_acceleration / rate per tick from the last command.
///                   No tube free -> StopToRecover.
///     StopToRecover (0, 0) until |v| and |w| (odometry) are below stop_speed -> StartRecover.
///     StartRecover  (0, 0) for one tick: rotation ring clear -> Rotate (toward the head
///                   orientation); else a backward tube free -> MoveBackward; else -> Blind.
///     Rotate        (0, +-rotate_rate) until resumable -> StopToNormal.
///     MoveBackward  (-backward_speed, -backward_speed / R) on the backward tube in the middle of
///                   the widest run of free ones (by curvature) among those within
///                   backward_bin_slack bins (0.4 m) of the best goal bin. Resumable ->
///                   StopToNormal; else the ring clear -> StopToRecover (then Rotate); else no
///                   backward tube free -> StopToNormal.
///     Blind         (-backward_speed, 0) until resumable -> StopToNormal.
///     StopToNormal  (0, 0) until |v| or |w| is below resume_speed -> Normal.
///     "Resumable": feasible ratio >= resume_ratio and the chosen forward tube's goal bin <=
///     resume_goal_bin.
///
/// configs/controllers/kulfm.yaml says for every default whether it is the team's (with its
/// source) or our choice; docs/systems/kulfm.md is the full description.

#include <span>
#include <string>
#include <string_view>
#include <vector>

#include <Eigen/Core>

#include "barn/controllers/controller.hpp"
#include "barn/controllers/motion_tubes.hpp"
#include "barn/core/config.hpp"
#include "barn/core/errors.hpp"
#include "barn/core/rect.hpp"
#include "barn/nav/nav_stack.hpp"

namespace barn::controllers {

enum class KulfmState { Normal, StopToRecover, StartRecover, Rotate, MoveBackward, Blind, StopToNormal };
std::span<const std::string_view> enumNames(KulfmState);

struct KulfmConfig {
  // [Hz] 2025 code: a move_base local planner at controller_frequency 20 (its acceleration limit
  // assumes 20 Hz); the 2023 node's rate is not public
  double rate = 20.0;
  MotionTubeConfig tubes;
  int orientation_points = 10;
  int head_points = 10;
  double goal_bin = 0.2;
  int goal_bin_slack = 1;
  int max_goal_bin = 6;
  // 2025 code: the end box the goal distance is measured to is 2 x vehicle_width / 4 wide
  // (its corners at +-width / 4) and axle_to_rear + axle_to_front long
  double goal_box_width = 0.25;
  double orientation_bin_deg = 20.0;
  double max_orientation_deg = 90.0;
  // 2025 code defaults (min_speed = max_speed = 0.5); the 2023 launch passes the node no
  // parameters, and 0.5 m/s reaches BARN's k = 4 cap (docs/systems/kulfm.md)
  double min_speed = 0.5;
  double max_speed = 0.5;
  double low_ratio = 0.1;
  double high_ratio = 0.75;
  double min_speed_weight = 0.4;
  double max_acceleration = 1.0;
  double stop_speed = 0.025;
  double resume_speed = 0.05;
  double ring_radius = 0.4;
  double rotate_rate = 0.7853981633974483;
  double backward_speed = 0.5;
  double backward_goal_bin = 0.4;
  int backward_bin_slack = 2;
  double resume_ratio = 0.2;
  int resume_goal_bin = 1;
  nav::NavStackConfig nav = kulfmNav();

  template <class V> void visit(V& v) {
    v("rate", rate, {.range = core::kPositive});
    v("tubes", tubes, {.doc = "2025 code (see motion_tubes.hpp)"});
    v("orientation_points", orientation_points,
      {.range = core::kNonNegative, .doc = "2025 code: local goal orientation from the point 10 indices before it"});
    v("head_points", head_points,
      {.range = core::atLeast(1), .doc = "2025 code: head orientation from plan points 0 and 10"});
    v("goal_bin", goal_bin, {.unit = "m", .range = core::kPositive, .doc = "2025 code: goal distance bins"});
    v("goal_bin_slack", goal_bin_slack,
      {.range = core::kNonNegative, .doc = "2025 code: drop tubes more than 1 bin worse than the best so far"});
    v("max_goal_bin", max_goal_bin, {.range = core::kNonNegative, .doc = "2025 code: drop tubes beyond bin 6"});
    v("goal_box_width", goal_box_width, {.unit = "m", .range = core::kPositive});
    v("orientation_bin_deg", orientation_bin_deg,
      {.unit = "deg", .range = core::kPositive, .doc = "2025 code: pi / 9"});
    v("max_orientation_deg", max_orientation_deg,
      {.unit = "deg", .range = core::closed(0.0, 180.0), .doc = "2025 code: drop tubes ending more than pi / 2 off"});
    v("min_speed", min_speed, {.unit = "m/s", .range = core::kNonNegative});
    v("max_speed", max_speed, {.unit = "m/s", .range = core::kNonNegative, .doc = "2025 code default"});
    v("low_ratio", low_ratio, {.range = core::kUnit, .doc = "2025 code: feasible ratio below this: min_speed"});
    v("high_ratio", high_ratio, {.doc = "2025 code: above this: max_speed"});
    v("min_speed_weight", min_speed_weight,
      {.range = core::kUnit, .doc = "2025 code: in between, 0.4 min_speed + 0.6 max_speed"});
    v("max_acceleration", max_acceleration,
      {.unit = "m/s^2", .range = core::kPositive, .doc = "2025 code: 1 m/s^2 at 20 Hz (0.05 m/s per tick)"});
    v("stop_speed", stop_speed,
      {.unit = "m/s", .range = core::kPositive, .doc = ", [rad/s] 2025 code: StopToRecover waits for |v|, |w| below"});
    v("resume_speed", resume_speed,
      {.unit = "m/s", .range = core::kPositive, .doc = ", [rad/s] 2025 code: StopToNormal waits for |v| or |w| below"});
    v("ring_radius", ring_radius,
      {.unit = "m", .range = core::kPositive, .doc = "2025 code: the rotation ring about the robot centre"});
    v("rotate_rate", rotate_rate, {.unit = "rad/s", .range = core::kPositive, .doc = "2025 code: pi / 4"});
    v("backward_speed", backward_speed,
      {.unit = "m/s", .range = core::kNonNegative, .doc = "2025 code: MoveBackward and Blind reverse at 0.5"});
    v("backward_goal_bin", backward_goal_bin,
      {.unit = "m", .range = core::kPositive, .doc = "2025 code: goal bins of the backward tubes"});
    v("backward_bin_slack", backward_bin_slack,
      {.range = core::kNonNegative, .doc = "2025 code: backward tubes within 2 bins of the best"});
    v("resume_ratio", resume_ratio,
      {.range = core::kUnit, .doc = "2025 code: recoveries end at a feasible ratio >= 0.2 ..."});
    v("resume_goal_bin", resume_goal_bin,
      {.range = core::kNonNegative, .doc = "2025 code: ... with the chosen tube's goal bin <= 1"});
    v("nav", nav);
  }

  /// The team's move_base stack (romulortr/barn-kul-fm@e23b647, jackal_helper/configs/params/):
  /// NavFn replanning at 20 Hz; footprint 0.42 x 0.33 without padding (inscribed radius 0.165);
  /// inflation radius 0.4 with costmap_2d's default cost scaling 10 (their files set none);
  /// the scan marks up to 4.5 m and does not clear (`clearing: false`; its raytrace range 5.0 m
  /// is then unused); footprint clearing on (costmap_2d's default, their files do not set it);
  /// global costmap at BARN's 10 Hz, local costmap (read by nothing here) at their 1 Hz.
  static nav::NavStackConfig kulfmNav();
};
void validate(const KulfmConfig& config, core::Errors& errors, const std::string& prefix);

/// No goal bin (no tube chosen).
inline constexpr int kNoGoalBin = 10000;

/// The local goal and the orientations read off the plan (robot frame).
struct LocalGoal {
  Eigen::Vector2d position = Eigen::Vector2d::Zero();  // [m]
  double orientation = 0.0;  // [rad] direction from the point orientation_points earlier
  double head = 0.0;         // [rad] direction from point 0 to point head_points
};

/// The local goal on `plan` (robot frame, robot -> goal): the first point where the arc length
/// walked from point 0 reaches `length` (else the last point). Indices before 0 or past the end
/// are clamped: a plan shorter than the offsets (the 2025 code reads outside it) uses its ends.
LocalGoal localGoalOnPlan(const std::vector<Eigen::Vector2d>& plan, double length, int orientation_points,
                          int head_points);

/// The signed distance from `goal` (robot frame) to `box` (in the tube's end frame): the
/// distance to the box outside it, minus the distance to its nearest side inside it.
double endBoxDistance(const MotionTube& tube, const Eigen::Vector2d& goal, const core::Rect& box);

/// 0 for a signed distance <= 0 (inside the box), else floor(distance / bin) + 1.
int goalBin(double signed_distance, double bin);

/// The forward tube of step 2 of the header comment.
struct ForwardChoice {
  int tube = -1;               // index into the library; -1: no tube
  int free_tubes = 0;          // tubes whose edge is free
  double feasible_ratio = 0.0; // free_tubes / number of tubes
  int goal_bin = kNoGoalBin;   // the chosen tube's
};
ForwardChoice chooseForwardTube(const std::vector<MotionTube>& tubes, const core::LaserScan& scan, const LocalGoal& goal,
                                const core::Twist& odom_twist, const KulfmConfig& config);

/// The backward tube to reverse on (-1: none free): among the free tubes within
/// backward_bin_slack bins (of backward_goal_bin) of the best, ordered by signed curvature, the
/// one deepest inside the longest run of consecutive candidates (the largest min(run length up to
/// it, run length from it)); ties go to the smaller |curvature|.
int chooseBackwardTube(const std::vector<MotionTube>& tubes, const core::LaserScan& scan, const LocalGoal& goal,
                       const KulfmConfig& config);

/// The speed rule: min_speed below low_ratio, max_speed above high_ratio, else
/// min_speed_weight min_speed + (1 - min_speed_weight) max_speed.
double desiredSpeed(double feasible_ratio, const KulfmConfig& config);

/// `previous` moved toward `desired` by at most `max_step`.
double limitAcceleration(double previous, double desired, double max_step);

/// What the transitions look at; the controller fills what the current state's transitions read.
struct KulfmInputs {
  bool forward_tube = false;    // a forward tube was chosen
  double feasible_ratio = 0.0;  // [-]
  int goal_bin = kNoGoalBin;    // the chosen forward tube's
  bool ring_clear = false;      // the rotation ring is free (StartRecover, MoveBackward)
  bool backward_tube = false;   // a backward tube is free (StartRecover, MoveBackward)
  double speed = 0.0;           // [m/s] odometry
  double turn_rate = 0.0;       // [rad/s] odometry
};

/// The state machine's transitions (see the header comment), as one pure function.
KulfmState nextKulfmState(KulfmState state, const KulfmInputs& in, const KulfmConfig& config);

class KulfmController : public Controller {
 public:
  explicit KulfmController(const KulfmConfig& config);
  void reset(const EpisodeInfo& info) override;
  core::Twist act(const Observation& observation) override;
  double period() const override { return 1.0 / config_.rate; }
  std::string_view stateLabel() const override { return core::enumName(state_); }
  KulfmState state() const { return state_; }
  const nav::NavStack& navStack() const { return nav_; }
  const std::vector<MotionTube>& forwardTubes() const { return forward_; }
  const std::vector<MotionTube>& backwardTubes() const { return backward_; }

 private:
  /// (Re)builds the tube libraries for `lidar` unless they were built for the same geometry.
  void buildLibraries(const core::LidarConfig& lidar);

  KulfmConfig config_;
  nav::NavStack nav_;
  EpisodeInfo info_;
  // The libraries depend on the LiDAR's geometry only: built for the first episode, rebuilt
  // when an episode's LiDAR differs.
  bool built_ = false;
  core::LidarConfig built_for_;
  std::vector<MotionTube> forward_, backward_;
  SampleSet ring_;
  KulfmState state_ = KulfmState::Normal;
  double last_speed_ = 0.0;       // [m/s] the last command's
  double rotate_direction_ = 1.0; // +1 counter-clockwise, chosen on entering Rotate
  std::vector<Eigen::Vector2d> plan_;  // scratch: the plan in the robot frame
};

}  // namespace barn::controllers
