#pragma once
/// `almeria_tps`: MRPT-style TP-space reactive navigation with the public BARN Jackal PTG set,
/// inspired by the University of Almeria's 2023 BARN entry (third, 0.2439). The entry's own
/// pipeline (a particle-filter localisation and exploration on MRPT) is not public: this is
/// MRPT's reactive navigator (CReactiveNavigationSystem as mrpt_reactivenav2d runs it) rebuilt
/// from its source, with the PTG file the Almeria group wrote for BARN. It is not their entry.
///
/// The target. MRPT's reactive navigator evaluates a target within its PTG's reach: FullEval's
/// target factors saturate once the target lies more than ref_distance (3 m for the BARN
/// Jackal PTG) from every path's end, and the choice then rests on free space alone. For a
/// farther goal MRPT's CWaypointsNavigator feeds it waypoints (mrpt_navigation's
/// mrpt_tps_astar_planner hands mrpt_reactivenav2d a sequence). `target: plan_waypoints` (the
/// default, our choice) does that with barnbench's move_base-like global plan (NavFn on a LiDAR
/// costmap; the Almeria entry's own planner is not public): every new plan (planner rate 1 Hz)
/// becomes the waypoint sequence, one waypoint every waypoint_spacing along it and the goal
/// last. `target: goal` aims at the BARN goal alone, as mrpt_reactivenav2d does with a single
/// goal.
///
/// Every control period (0.1 s, mrpt_reactivenav2d's nav_period):
///  0. Waypoints (CWaypointsNavigator, plan_waypoints only; the goal alone is a sequence of
///     one). If the robot's last move (the segment from the previous tick's position to this
///     one) passes within waypoint_allowed_distance of the current waypoint
///     (target_allowed_distance for the last), it is reached: the next one becomes current,
///     and after the last navigation ends (Reached: zero from then on). Then every later waypoint (within max_distance_to_allow_skip_waypoint, if > 0)
///     that the previous tick's TP-obstacles showed reachable along its own path (free beyond
///     1.01 times its TP distance) counts one more sighting; the farthest with more than
///     min_timesteps_confirm_skip_waypoints sightings becomes current, those before it skipped.
///  1. The not-approaching alarm (CAbstractNavigator): if the least distance to the current
///     waypoint has not improved for not_approaching_timeout since it became current,
///     navigation is aborted (Aborted: zero from then on; MRPT's "way seems blocked").
///  2. Obstacles: the latest scan's returns, placed with the odometry at the scan, in the robot
///     frame at this tick.
///  3. The current waypoint in TP-space (ArcPtg::inverseMap). Not exact: the PTG is discarded, no
///     movement is possible this tick (OutOfDomain, zero command).
///  4. TP-obstacles (ArcPtg::tpObstacles), normalised by the PTG's ref_distance.
///  5. The holonomic method in TP-space, FullEval (fullEval below): a direction k and a speed
///     in [0, 1].
///  6. Speed: times the ramp of the chosen direction's free distance between
///     secure_distance_start (0) and secure_distance_end (1); then, for the last waypoint, no
///     more than its distance / target_slow_approaching_distance (the target slow-down).
///  7. Speed 0: no way (NoWay, zero command; MRPT's "robot.stop()", and it tries again next
///     period). Otherwise the command is path k's (v_k, w_k) times the speed, scaled down to the
///     robot limits (v and w together, keeping the curvature) and low-pass filtered
///     (speedfilter_tau; 0 = none).
///
/// With one PTG (the file's PTG_COUNT = 1) MRPT's motion decider
/// (CMultiObjMotionOpt_Scalarization) has one candidate, scored above 0 exactly when its speed
/// is; it only accepts or rejects the holonomic method's choice, as step 7 does. The PTG
/// continuation ("NOP" command) is not offered by differential-drive PTGs.
///
/// FullEval (CHolonomicFullEval, the seven-factor version of MRPT 1.5.x and 2.x that
/// mrpt_navigation's configuration is written for). Directions i = 0 ... N-1 are the PTG's
/// paths, at alpha_i; obstacles o_i are the normalised TP-obstacles; the target T (normalised)
/// lies at distance t along direction k_t. For each direction, unless o_i < too_close (and it
/// is not k_t with o_i > 1.02 t), seven factors, with d = min(o_i, 0.95 t) and the point
/// P = d (cos alpha_i, sin alpha_i):
///   [0] free space: o_i - too_close (near the target, |i - k_t| <= 1, t < 1 - too_close and
///       o_i > 1.05 t: max(t, o_i) / 1.05 t), at most the path's length / ref_distance;
///   [1] 1 / (1 + m^2), m the distance from the segment 0-P to T (from P/2-P when P ends farther
///       from T than t and the segment gets no nearer than 1.05 min(t, |T - P|));
///   [2] sqrt(1.01 - min(1, |T - P|));   [5] the same, never decimated;
///   [3] hysteresis: 1 within hysteresis_sector_count paths of the last choice, else
///       (1 - (|i - last| - count) / N)^2;
///   [4] clearance: the least distance from the segment 0-P to the TP-obstacle points
///       o_j (cos alpha_j, sin alpha_j) with o_j < 0.99, |j - i| <= round(0.1 N), at most 1;
///   [6] 1 / (1 + (4 |i - k_t| / N)^2);
/// and when t < 1 - too_close and o_i < 1.01 t (the target is beyond the free space), [1], [2]
/// and [6] are multiplied by 0.1. Factors marked in factor_normalize are rescaled to [0, 1]
/// over all directions. Phases in turn: a direction's phase score is the weighted geometric
/// mean of its phase's factors (logs of max(1e-6, s)), 0 if o_i < too_close or if its previous
/// phase score was below that phase's threshold; a phase's threshold is
/// T_p max + (1 - T_p) min of its scores. Last-phase scores below its threshold become 0. The
/// chosen direction is the best-scored one (among equal best scores in the first run of
/// scores >= 0.01 reaching the maximum, the last). Speed: 0 if there is none, or if its
/// o_k <= too_close; else min(1, |T| ref / target_slow_approaching_distance) (the risk ramp
/// up to max(too_close, obstacle_slow_down_distance / ref) is empty with these defaults).
///
/// Sources: MRPT/mrpt@690a469 (MRPT 1.5.9) libs/nav/src/holonomic/CHolonomicFullEval.cpp;
/// MRPT/mrpt@004d9da libs/nav/src/reactive/CAbstractPTGBasedReactive.cpp (steps 3-7);
/// @042ba57 libs/nav/src/reactive/CAbstractNavigator.cpp (step 1); the node:
/// mrpt-ros-pkg/mrpt_navigation@0116b49 mrpt_reactivenav2d/src/mrpt_reactivenav2d_node.cpp;
/// parameters: @4e17b37 mrpt_reactivenav2d/params/reactive2d_default.ini and the PTG file
/// (ptg.hpp). docs/systems/almeria_tps.md has the choices and the measured results.

#include <array>
#include <memory>
#include <span>
#include <string>
#include <string_view>
#include <vector>

#include <Eigen/Core>

#include "barn/controllers/controller.hpp"
#include "barn/controllers/ptg.hpp"
#include "barn/core/config.hpp"
#include "barn/core/errors.hpp"
#include "barn/nav/nav_stack.hpp"

namespace barn::controllers {

/// The number of FullEval factors (see the header comment).
inline constexpr std::size_t kFullEvalFactors = 7;

/// One FullEval phase: the factors it averages and its relative threshold.
struct FullEvalPhase {
  std::vector<double> factors;  // [-] factor indices 0 ... 6
  double threshold = 0.5;       // [-] in (0, 1): T max + (1 - T) min of the phase's scores
  template <class V> void visit(V& v) { v("factors", factors); v("threshold", threshold); }
};

/// FullEval's parameters. Defaults: mrpt_navigation's reactive2d_default.ini
/// (mrpt-ros-pkg/mrpt_navigation@4e17b37, section [CHolonomicFullEval]); MRPT's own
/// TOptions() defaults list five factor weights, which the seven-factor code rejects, so a
/// configuration file has always given them.
struct FullEvalConfig {
  std::vector<double> factor_weights = {0.25, 0.1, 1.0, 0.05, 0.5, 1.0, 1.0};
  std::vector<double> factor_normalize = {0, 0, 0, 0, 1, 1, 0};
  // [-] ini: PHASE1 [6] 0.5, PHASE2 [4] 0.7, PHASE3 [0 2] 0.7
  std::vector<FullEvalPhase> phases = {{{6}, 0.5}, {{4}, 0.7}, {{0, 2}, 0.7}};
  double too_close_obstacle = 0.15;
  double target_slow_approaching_distance = 0.10;
  double obstacle_slow_down_distance = 0.15;
  double hysteresis_sector_count = 5.0;

  template <class V> void visit(V& v) {
    v("factor_weights", factor_weights, {.doc = "ini: factorWeights"});
    v("factor_normalize", factor_normalize, {.doc = "ini: factorNormalizeOrNot (0/1)"});
    v("phases", phases);
    v("too_close_obstacle", too_close_obstacle,
      {.range = core::closedOpen(0.0, 1.0), .doc = "ini: TOO_CLOSE_OBSTACLE, normalised free distance"});
    v("target_slow_approaching_distance", target_slow_approaching_distance,
      {.unit = "m", .range = core::kPositive, .doc = "ini: TARGET_SLOW_APPROACHING_DISTANCE"});
    v("obstacle_slow_down_distance", obstacle_slow_down_distance,
      {.unit = "m", .range = core::kNonNegative, .doc = "ini: OBSTACLE_SLOW_DOWN_DISTANCE"});
    v("hysteresis_sector_count", hysteresis_sector_count,
      {.unit = "paths", .range = core::kNonNegative, .doc = "ini: HYSTERESIS_SECTOR_COUNT"});
  }
};
void validate(const FullEvalConfig& config, core::Errors& errors, const std::string& prefix);

/// What FullEval sees: one value per direction (path) and the target, in normalised TP-space.
struct TpSpaceInput {
  std::span<const double> obstacles;  // [-] free distance per direction / ref_distance
  std::span<const double> unlooped;   // [-] path length per direction / ref_distance
  Eigen::Vector2d target = Eigen::Vector2d::Zero();  // [-] (cos alpha_k, sin alpha_k) d / ref_distance
  double ref_distance = 1.0;          // [m]
  bool slow_down_at_target = true;    // the target is the final one (not a waypoint)
};

/// FullEval's decision.
struct FullEvalChoice {
  int direction = -1;       // [-] the chosen path; -1: no way
  double speed = 0.0;       // [-] in [0, 1]
  double evaluation = 0.0;  // [-] the chosen direction's last-phase score
};

/// MRPT's CHolonomicFullEval (see the header comment). Remembers the last chosen direction.
class FullEval {
 public:
  explicit FullEval(const FullEvalConfig& config) : config_(config) {}
  void reset() { last_selected_ = -1; }
  FullEvalChoice navigate(const TpSpaceInput& input);
  /// The last call's factor scores (after normalisation), one row of seven per direction.
  const std::vector<std::array<double, kFullEvalFactors>>& factors() const { return factors_; }
  /// The last call's phase scores, one vector per phase (the last one after thresholding).
  const std::vector<std::vector<double>>& phaseScores() const { return phases_; }
  int lastSelected() const { return last_selected_; }

 private:
  FullEvalConfig config_;
  int last_selected_ = -1;  // -1: none yet
  std::vector<std::array<double, kFullEvalFactors>> factors_;
  std::vector<std::vector<double>> phases_;
};

/// MRPT's secure-distance ramp: 0 up to `start`, 1 from `end`, linear between.
double secureDistanceScale(double free_distance, double start, double end);

/// CVehicleVelCmd_DiffDriven's limits: scales v and w together (keeping the curvature) so that
/// |v| <= max_v and |w| <= max_w; returns the scale applied.
double limitToRobot(core::Twist& cmd, double max_v, double max_w);

enum class AlmeriaTpsState { Navigating, NoWay, OutOfDomain, Reached, Aborted };
std::span<const std::string_view> enumNames(AlmeriaTpsState);

/// What the reactive navigator aims at (see the header comment).
enum class AlmeriaTarget { PlanWaypoints, Goal };
std::span<const std::string_view> enumNames(AlmeriaTarget);

/// `plan` (odom frame, robot -> goal) as waypoints: the first plan point at or past each
/// multiple of `spacing` of arc length, then `goal` (replacing a last waypoint nearer than
/// spacing / 2 to it).
std::vector<Eigen::Vector2d> planWaypoints(const std::vector<Eigen::Vector2d>& plan, const Eigen::Vector2d& goal,
                                           double spacing);

struct AlmeriaTpsConfig {
  AlmeriaTarget target = AlmeriaTarget::PlanWaypoints;
  double waypoint_spacing = 0.5;
  // Mrpt_tps_astar_planner node: mid_waypoints_allowed_distance (the last waypoint, the goal,
  // has target_allowed_distance)
  double waypoint_allowed_distance = 0.5;
  int min_timesteps_confirm_skip_waypoints = 1;
  double max_distance_to_allow_skip_waypoint = -1.0;
  double nav_period = 0.1;
  // Mrpt_reactivenav2d node: target_allowed_distance default (and the TPS-A* planner node's
  // final_waypoint_allowed_distance)
  double target_allowed_distance = 0.40;
  double not_approaching_timeout = 30.0;
  double secure_distance_start = 0.05;
  double secure_distance_end = 0.15;
  double robot_max_v = 1.2;
  double robot_max_w_deg = 60.0;
  double speedfilter_tau = 0.0;
  PtgConfig ptg;
  FullEvalConfig full_eval;
  nav::NavStackConfig nav = almeriaNav();

  template <class V> void visit(V& v) {
    v("target", target, {.doc = "our choice (see the header comment)"});
    v("waypoint_spacing", waypoint_spacing,
      {.unit = "m", .range = core::kPositive, .doc = "our choice: waypoints along the plan"});
    v("waypoint_allowed_distance", waypoint_allowed_distance, {.unit = "m", .range = core::kNonNegative});
    v("min_timesteps_confirm_skip_waypoints", min_timesteps_confirm_skip_waypoints,
      {.unit = "ticks", .range = core::kNonNegative, .doc = "ini: [CWaypointsNavigator]"});
    v("max_distance_to_allow_skip_waypoint", max_distance_to_allow_skip_waypoint,
      {.unit = "m", .doc = "ini: <= 0 unlimited"});
    v("nav_period", nav_period,
      {.unit = "s", .range = core::kPositive, .doc = "mrpt_reactivenav2d node: nav_period default"});
    v("target_allowed_distance", target_allowed_distance, {.unit = "m", .range = core::kNonNegative});
    v("not_approaching_timeout", not_approaching_timeout,
      {.unit = "s", .range = core::kPositive, .doc = "ini: alarm_seems_not_approaching_target_timeout"});
    v("secure_distance_start", secure_distance_start,
      {.range = core::kNonNegative, .doc = "ini: secure_distance_start (normalised)"});
    v("secure_distance_end", secure_distance_end, {.doc = "ini: secure_distance_end (normalised)"});
    v("robot_max_v", robot_max_v,
      {.unit = "m/s", .range = core::kPositive, .doc = "PTG file: ROBOT_MAX_V (robotMax_V_mps)"});
    v("robot_max_w_deg", robot_max_w_deg,
      {.unit = "deg/s", .range = core::kPositive, .doc = "PTG file: ROBOT_MAX_W (robotMax_W_degps)"});
    v("speedfilter_tau", speedfilter_tau,
      {.unit = "s", .range = core::kNonNegative, .doc = "MRPT default (the ini leaves it commented out)"});
    v("ptg", ptg, {.doc = "the BARN Jackal PTG (ptg.hpp)"});
    v("full_eval", full_eval, {.doc = "reactive2d_default.ini's FullEval"});
    v("nav", nav, {.doc = "the global plan of plan_waypoints"});
  }

  /// Our choice: BARN's move_base stack with ROS NavFn (NavStackConfig::moveBaseWithNavFn),
  /// replanning at 1 Hz: each plan is a new waypoint sequence, and MRPT's skip rule needs a
  /// sequence to last a few control periods.
  static nav::NavStackConfig almeriaNav();
};
void validate(const AlmeriaTpsConfig& config, core::Errors& errors, const std::string& prefix);

class AlmeriaTpsController : public Controller {
 public:
  /// `ptg` is shared, read-only, by every episode's controller (its grid takes a while to build);
  /// null: build one from config.ptg.
  explicit AlmeriaTpsController(const AlmeriaTpsConfig& config, std::shared_ptr<const ArcPtg> ptg = nullptr);
  void reset(const EpisodeInfo& info) override;
  core::Twist act(const Observation& observation) override;
  double period() const override { return config_.nav_period; }
  std::string_view stateLabel() const override { return core::enumName(state_); }
  AlmeriaTpsState state() const { return state_; }
  const ArcPtg& ptg() const { return *ptg_; }
  /// The waypoint sequence and the current one's index (-1 before the first tick).
  const std::vector<Eigen::Vector2d>& waypoints() const { return waypoints_; }
  int currentWaypoint() const { return current_; }
  /// The last tick's TP-obstacles (normalised) and FullEval's choice.
  const std::vector<double>& tpObstacles() const { return tp_obstacles_; }
  const FullEvalChoice& lastChoice() const { return choice_; }

 private:
  core::Twist stop(AlmeriaTpsState state);
  /// Step 0 of the header comment; false once the last waypoint is reached.
  bool stepWaypoints(const Observation& obs);
  /// Whether the previous tick's TP-obstacles show a free path to `local` (robot frame).
  bool reachable(const Eigen::Vector2d& local) const;

  AlmeriaTpsConfig config_;
  std::shared_ptr<const ArcPtg> ptg_;
  FullEval full_eval_;
  nav::NavStack nav_;
  EpisodeInfo info_;
  AlmeriaTpsState state_ = AlmeriaTpsState::Navigating;
  bool have_previous_ = false;
  Eigen::Vector2d previous_position_ = Eigen::Vector2d::Zero();  // [m] odom frame, last tick
  std::vector<Eigen::Vector2d> waypoints_;  // [m] odom frame, the goal last
  std::vector<int> sightings_;         // per waypoint: ticks seen reachable
  int reached_ = 0;                    // waypoints before this one are reached or skipped
  int current_ = -1;                   // the current waypoint; -1: not started
  int plans_taken_ = 0;                // nav_.plansMade() when the sequence was last replaced
  bool have_tp_ = false;               // tp_obstacles_ hold the previous tick's
  double min_target_distance_ = 0.0;   // [m] least distance to the current waypoint so far
  double min_target_time_ = 0.0;       // [s] when it was reached
  core::Twist last_command_;           // for the low-pass filter
  FullEvalChoice choice_;
  std::vector<Eigen::Vector2d> points_;  // scratch: obstacle points, robot frame
  std::vector<double> tp_obstacles_;
  std::vector<double> unlooped_;         // path lengths / ref_distance
};

}  // namespace barn::controllers
