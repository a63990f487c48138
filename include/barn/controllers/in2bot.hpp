#pragma once
/// `in2bot`: IN2BOT's BARN 2026 entry (simulation #1): a LiDAR grid (gmapping in their stack),
/// distance-field costs, A* replanned at 2 Hz when the path collides, and RRSL's VFH* / fuzzy
/// local planner steering at a point 0.8 m along the path, with IN2BOT's 2026 changes: no
/// heading smoothing, the fuzzy speed sets scaled by 1.25 (universe 0-0.9 m/s), and a turn in
/// place at +-1.0 rad/s when the target's bearing is more than 42 deg off the heading (after
/// the clear-path override and the safety bubble, which it overrides).
///
/// Each tick: add the scan to the grid when the robot has travelled 0.2 m or turned 0.05 rad
/// since the last one added (gmapping's update rule); at 2 Hz, replan when there is no path or
/// the path collides; then the local planner (no command before the first path).
///
/// Sources (royalbegger/AAA, MIT): local_planner/scripts/aaaVFH.py@ab22567 (local planner),
/// in2bot_map.hpp for the rest. No code copied.

#include <vector>

#include "barn/controllers/controller.hpp"
#include "barn/controllers/in2bot_map.hpp"
#include "barn/controllers/vfh_fuzzy.hpp"
#include "barn/core/config.hpp"
#include "barn/core/errors.hpp"

namespace barn::controllers {

/// IN2BOT's speed system: RRSL's with every output set scaled by 1.25 on a 0-0.9 m/s universe.
FuzzySystemConfig in2botSpeedFuzzy();

struct In2botConfig {
  double rate = 10.0;
  double lookahead = 0.8;
  double goal_lock_distance = 3.0;
  int nearest_window = 50;
  double nearest_reset = 2.0;
  double turn_in_place_deg = 42.0;
  double turn_in_place_rate = 1.0;
  In2botMapConfig map;
  In2botEsdfConfig esdf;
  In2botPlannerConfig planner;
  VfhConfig vfh = in2botVfh();

  static VfhConfig in2botVfh() {
    VfhConfig c;
    c.smoothing = false;              // team: the smoothing lines are commented out
    c.speed_fuzzy = in2botSpeedFuzzy();
    return c;
  }

  template <class V> void visit(V& v) {
    v("rate", rate, {.unit = "Hz", .range = core::kPositive, .doc = "team: rospy.Rate(10)"});
    v("lookahead", lookahead,
      {.unit = "m", .range = core::kNonNegative, .doc = "team: lookahead_distance, along the path from the nearest point"});
    v("goal_lock_distance", goal_lock_distance,
      {.unit = "m", .range = core::kNonNegative, .doc = "team: within this of the path's end, steer at the end"});
    v("nearest_window", nearest_window,
      {.unit = "points", .range = core::kNonNegative, .doc = "team: the nearest point is searched +-50 around the last"});
    v("nearest_reset", nearest_reset,
      {.unit = "m", .range = core::kNonNegative, .doc = "team: ... and over the whole path when that is farther"});
    v("turn_in_place_deg", turn_in_place_deg,
      {.unit = "deg", .range = core::openClosed(0.0, 180.0), .doc = "team: turn in place beyond this bearing to the target"});
    v("turn_in_place_rate", turn_in_place_rate, {.unit = "rad/s", .range = core::kNonNegative, .doc = "team"});
    v("map", map);
    v("esdf", esdf);
    v("planner", planner);
    v("vfh", vfh, {.doc = "RRSL's, less the smoothing, with the 1.25 speed sets"});
  }
};
void validate(const In2botConfig& config, core::Errors& errors, const std::string& prefix);

/// The team's target on the path (world points, cumulative arc lengths): the path's end
/// within goal_lock_distance of it; else the point `lookahead` further along the path than
/// the path point nearest the robot (searched within nearest_window points of `nearest`, over
/// the whole path when that nearest is more than nearest_reset away), or the end if the path
/// is shorter. Updates `nearest`.
Eigen::Vector2d lookaheadTarget(const std::vector<Eigen::Vector2d>& path, const std::vector<double>& arc_length,
                                const Eigen::Vector2d& robot, std::size_t& nearest, const In2botConfig& config);

/// The team's turn in place: when |bearing to the target - heading| (wrapped to [-180, 180))
/// exceeds `limit_deg`, the rate toward the target (+ left, - right; 0 deg off counts as
/// right); std::nullopt otherwise.
std::optional<double> turnInPlaceRate(const core::Pose2& pose, const Eigen::Vector2d& target, double limit_deg,
                                      double rate);

class In2botController : public Controller {
 public:
  explicit In2botController(const In2botConfig& config);
  void reset(const EpisodeInfo& info) override;
  core::Twist act(const Observation& observation) override;
  double period() const override { return 1.0 / config_.rate; }
  std::string_view stateLabel() const override { return core::enumName(action_); }
  void checkLidar(const core::LidarConfig& lidar) const override { checkVfhBeams(config_.vfh, lidar.beams); }

 private:
  void updateMap(const Observation& obs);
  void replan(const Observation& obs);

  In2botConfig config_;
  VfhFuzzy vfh_;
  ScanCountGrid grid_;
  EpisodeInfo info_;
  VfhAction action_ = VfhAction::WaitPath;
  bool integrated_ = false;             // a scan has been added to the grid
  core::Pose2 last_pose_;               // odom pose at the previous tick
  double travelled_ = 0.0;              // [m] since the last scan added
  double turned_ = 0.0;                 // [rad] since the last scan added
  double next_plan_ = 0.0;              // [s] the planner's next tick
  std::vector<GridCell> plan_;          // the planner's current path (empty: none or failed)
  std::vector<Eigen::Vector2d> path_;   // the last path published to the local planner
  std::vector<double> arc_length_;      // [m] cumulative along path_
  std::size_t nearest_ = 0;             // index of the path point nearest the robot
};

}  // namespace barn::controllers
