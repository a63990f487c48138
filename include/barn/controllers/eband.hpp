#pragma once
/// `eband`: the BARN E-Band baseline, move_base with eband_local_planner (utexas-bwi, 0.4.0) at
/// its package defaults (BARN sets none of its parameters) on the DWA baseline's stack: ROS
/// NavFn replanning at 20 Hz and the same costmaps (nav::NavStack), move_base's patience and
/// recoveries (MoveBase).
///
/// The elastic band is a chain of bubbles: a pose and the free radius around it, read off the
/// local costmap by inverting the inflation, r = -ln(cost / 252) / costmap_weight (free space
/// 0.553 m; the inflation ring 0.035 m or less; inscribed or lethal 0). Two bubbles overlap
/// when their centres are closer than 0.7 of their radii's sum.
///  - Each new global plan (windowed to the first pose beyond half the local costmap, 4.99 m)
///    becomes a band, one bubble per pose; refinement (recursive halving of the index
///    interval) deletes the bubbles their neighbours make redundant and fills each gap with
///    midpoint bubbles, failing if one would be in collision (r <= 0.01). If the plan cannot
///    become a band, the local costmap is reset and the plan tried once more; failing again,
///    move_base aborts the goal.
///  - Every cycle the robot pose joins the band at the front (to the farthest bubble it
///    overlaps, dropping the passed ones), plan poses entering the window join at the back,
///    and the band is optimised: radii refreshed (a bubble in collision fails the cycle),
///    refined, then three sweeps (1 .. n-2 .. 1, ends fixed) moving each bubble by its radius
///    times the force on it: the internal contraction force (sum of the unit vectors to its
///    neighbours, yaw scaled by the circumscribed radius), the external repulsion (central
///    difference of the radius across the bubble's rim, gain 2), their sum without its
///    component along the band. A move into collision is rejected; a move whose force
///    reverses significantly is replaced by a recursive halving search for the equilibrium
///    (depth 4); a move that disconnects the bubble from a neighbour is rejected unless the
///    gap can be filled. Each sweep is followed by a refinement.
///  - The command (differential drive): rotate in place at k_prop x bearing (max 1 rad/s)
///    while the bearing of the next bubble exceeds atan2(0.7 r1, d1); otherwise drive at
///    2 x 0.7 x (robot bubble radius) x 0.75 m/s x cos(bearing) (0.375 m/s within 0.75 m of the
///    band's end), clamped to [0.1, 0.75] m/s, turning at k_prop x bearing: 0.58 m/s in the
///    open, and 0.1 m/s with the robot's centre in the inflation ring. No acceleration limit: the
///    differential-drive branch has none (its acceleration, damping and virtual-mass
///    parameters belong to the holonomic branch and are not listed). At the band's end (within
///    0.06 m of the goal) it turns to the goal's yaw and reports the goal reached.
/// A cycle that fails (robot centre inscribed, the band broken, optimisation in collision)
/// publishes zero and makes move_base wait for the next plan, its patience and recoveries
/// counting as for DWA.

#include <optional>
#include <string>
#include <string_view>
#include <vector>

#include <Eigen/Core>

#include "barn/controllers/controller.hpp"
#include "barn/controllers/move_base.hpp"
#include "barn/core/config.hpp"
#include "barn/core/errors.hpp"
#include "barn/nav/nav_stack.hpp"

namespace barn::controllers {

/// eband_local_planner's parameters (cfg/EBandPlanner.cfg defaults, ROS names) used by its
/// differential-drive branch, move_base's cycle and recoveries, and the stack.
struct EbandConfig {
  double rate = 20.0;
  // The band (EBandPlanner).
  double eband_min_relative_overlap = 0.7;
  double eband_tiny_bubble_distance = 0.01;
  double eband_tiny_bubble_expansion = 0.01;
  double eband_internal_force_gain = 1.0;
  double eband_external_force_gain = 2.0;
  int num_iterations_eband_optimization = 3;
  int eband_equilibrium_approx_max_recursion_depth = 4;
  double eband_equilibrium_relative_overshoot = 0.75;
  double eband_significant_force_lower_bound = 0.15;
  double costmap_weight = 10.0;
  // The trajectory controller (EBandTrajectoryCtrl, differential_drive true).
  double max_vel_lin = 0.75;
  double max_vel_th = 1.0;
  double min_vel_lin = 0.1;
  double min_vel_th = 0.0;
  double min_in_place_vel_th = 0.0;
  double k_prop = 4.0;
  double bubble_velocity_multiplier = 2.0;
  double rotation_threshold_multiplier = 1.0;
  bool disallow_hysteresis = false;
  double xy_goal_tolerance = 0.1;
  double yaw_goal_tolerance = 0.05;
  MoveBaseRecoveryConfig recovery;
  nav::NavStackConfig nav = nav::NavStackConfig::moveBaseWithNavFn();

  template <class V> void visit(V& v) {
    v("rate", rate,
      {.unit = "Hz", .range = core::kPositive, .doc = "move_base controller_frequency (eband's Ctrl_Rate is holonomic-only)"});
    v("eband_min_relative_overlap", eband_min_relative_overlap,
      {.range = core::kPositive, .doc = "bubbles overlap below this x their radii's sum"});
    v("eband_tiny_bubble_distance", eband_tiny_bubble_distance,
      {.unit = "m", .range = core::kPositive, .doc = "shorter neighbour distances give no internal force"});
    v("eband_tiny_bubble_expansion", eband_tiny_bubble_expansion,
      {.unit = "m", .range = core::kPositive, .doc = "a bubble this small counts as in collision"});
    v("eband_internal_force_gain", eband_internal_force_gain, {.range = core::kNonNegative});
    v("eband_external_force_gain", eband_external_force_gain, {.range = core::kNonNegative});
    v("num_iterations_eband_optimization", num_iterations_eband_optimization, {.range = core::kNonNegative});
    v("eband_equilibrium_approx_max_recursion_depth", eband_equilibrium_approx_max_recursion_depth,
      {.range = core::kNonNegative});
    v("eband_equilibrium_relative_overshoot", eband_equilibrium_relative_overshoot, {.range = core::kNonNegative});
    v("eband_significant_force_lower_bound", eband_significant_force_lower_bound, {.range = core::kNonNegative});
    v("costmap_weight", costmap_weight,
      {.unit = "1/m", .range = core::kPositive, .doc = "the inflation's decay, to invert it"});
    v("max_vel_lin", max_vel_lin, {.unit = "m/s", .range = core::kPositive});
    v("max_vel_th", max_vel_th, {.unit = "rad/s", .range = core::kPositive});
    v("min_vel_lin", min_vel_lin, {.unit = "m/s"});
    v("min_vel_th", min_vel_th, {.unit = "rad/s"});
    v("min_in_place_vel_th", min_in_place_vel_th, {.unit = "rad/s"});
    v("k_prop", k_prop, {.unit = "1/s", .range = core::kPositive, .doc = "yaw rate per rad of bearing"});
    v("bubble_velocity_multiplier", bubble_velocity_multiplier, {.range = core::kPositive});
    v("rotation_threshold_multiplier", rotation_threshold_multiplier, {.range = core::kPositive});
    v("disallow_hysteresis", disallow_hysteresis);
    v("xy_goal_tolerance", xy_goal_tolerance, {.unit = "m", .range = core::kPositive});
    v("yaw_goal_tolerance", yaw_goal_tolerance, {.unit = "rad", .range = core::kPositive});
    v("recovery", recovery);
    v("nav", nav, {.doc = "move_base_eband.launch"});
  }
};
void validate(const EbandConfig& config, core::Errors& errors, const std::string& prefix);

/// One bubble of the band: a pose and its free radius ("expansion").
struct EbandBubble {
  core::Pose2 center;
  double expansion = 0.0;  // [m]
};

/// EBandPlanner: the band, its construction from plan poses, refinement and optimisation on
/// a costmap (the local costmap, set before use).
class ElasticBand {
 public:
  /// `circumscribed_radius`: the padded footprint's largest vertex distance (yaw to length).
  ElasticBand(const EbandConfig& config, double circumscribed_radius);

  void setCostmap(const nav::Costmap& costmap) { costmap_ = &costmap; }
  void clear() { band_.clear(); }
  const std::vector<EbandBubble>& bubbles() const { return band_; }

  /// calcObstacleKinematicDistance: the free radius at the pose's cell (yaw ignored); 0 at
  /// inscribed or lethal cost, as free (cost 1) off the map or at unknown.
  double obstacleDistance(const core::Pose2& pose) const { return distance_by_cost_[costAt(pose)]; }
  bool overlap(const EbandBubble& a, const EbandBubble& b) const;

  /// setPlan: the poses as bubbles (false if one is in collision), refined. The band is
  /// replaced only on success.
  bool setPlan(const std::vector<core::Pose2>& poses);
  /// addFrames: poses joined at the front (the robot) or the back (plan poses entering the
  /// window), to the farthest (front) or first (back) bubble the nearest new one overlaps,
  /// else through a filled gap (false if it cannot be filled).
  bool addFrames(const std::vector<core::Pose2>& poses, bool at_front);
  /// optimizeBand on a copy, kept only on success.
  bool optimize();

  // The building blocks, on any band (exposed for tests).
  bool convertPlanToBand(const std::vector<core::Pose2>& poses, std::vector<EbandBubble>& band) const;
  bool refineBand(std::vector<EbandBubble>& band) const;
  bool optimizeBand(std::vector<EbandBubble>& band) const;
  /// Internal + external force on `bubble` standing at index i of `band` (its neighbours
  /// i - 1 and i + 1), without the component along the band. (x, y, R_c yaw).
  Eigen::Vector3d forcesAt(std::size_t i, const std::vector<EbandBubble>& band, const EbandBubble& bubble) const;
  Eigen::Vector3d internalForce(std::size_t i, const std::vector<EbandBubble>& band, const EbandBubble& bubble) const;
  Eigen::Vector3d externalForce(const EbandBubble& bubble) const;

 private:
  int costAt(const core::Pose2& pose) const;
  /// (dx, dy, R_c wrap(dyaw)) from `from` to `to`.
  Eigen::Vector3d difference(const core::Pose2& from, const core::Pose2& to) const;
  bool removeAndFill(std::vector<EbandBubble>& band, std::size_t start, std::size_t& end) const;
  bool fillGap(std::vector<EbandBubble>& band, std::size_t start, std::size_t& end) const;
  void modifyBandArtificialForce(std::vector<EbandBubble>& band) const;
  void applyForces(std::size_t i, std::vector<EbandBubble>& band, const Eigen::Vector3d& force) const;
  bool moveApproximateEquilibrium(std::size_t i, const std::vector<EbandBubble>& band, EbandBubble& bubble,
                                  const Eigen::Vector3d& bubble_force, const Eigen::Vector3d& step, int depth) const;
  /// The overshoot test of applyForces and the equilibrium search: `after` opposes `before`
  /// and is significant (see eband.cpp for upstream's norm of `before`).
  bool reversesSignificantly(const Eigen::Vector3d& after, const Eigen::Vector3d& before) const;

  EbandConfig config_;
  double circumscribed_radius_;
  const nav::Costmap* costmap_ = nullptr;
  double distance_by_cost_[256] = {};
  std::vector<EbandBubble> band_;
};

class EbandController : public Controller {
 public:
  explicit EbandController(const EbandConfig& config);
  void reset(const EpisodeInfo& info) override;
  core::Twist act(const Observation& observation) override;
  double period() const override { return 1.0 / config_.rate; }
  std::string_view stateLabel() const override;

  /// The trajectory controller's output for a band whose first bubble is the robot.
  struct Command {
    core::Twist twist;
    bool turning_in_place = false;
    bool goal_reached = false;
  };
  /// getTwistDifferentialDrive (updates the final-turn hysteresis). Exposed for tests.
  Command commandFor(const std::vector<EbandBubble>& band);

  ElasticBand& band() { return band_; }
  nav::NavStack& navStack() { return nav_; }
  /// How often the local costmap was reset because a plan could not become a band.
  int costmapResets() const { return costmap_resets_; }

 private:
  /// EBandPlannerROS::setPlan for the stack's latest plan; false: move_base aborts.
  bool setPlan(const core::Pose2& robot);
  /// EBandPlannerROS::computeVelocityCommands; nothing when the cycle fails.
  std::optional<core::Twist> computeVelocityCommands(const core::Pose2& robot);
  /// eband's transformGlobalPlan: the plan's poses from the first within half the local
  /// costmap's size of the robot (searching from `start_count` poses before the end) up to
  /// the first beyond it, included; the counts (from the plan's end) of its first and last.
  std::vector<core::Pose2> windowPlan(const core::Pose2& robot, int& start_count, int& end_count) const;

  EbandConfig config_;
  nav::NavStack nav_;
  MoveBase move_base_;
  ElasticBand band_;
  EpisodeInfo info_;
  std::vector<core::Pose2> plan_;  // the global plan last handed over
  int plan_start_count_ = 0;       // window, counted from the plan's end
  int plan_end_count_ = 0;
  int plans_seen_ = 0;             // NavStack::plansMade() at the last hand-over
  bool in_final_goal_turn_ = false;
  bool goal_reached_ = false;
  bool turning_ = false;           // the last command was an in-place rotation
  int costmap_resets_ = 0;
};

}  // namespace barn::controllers
