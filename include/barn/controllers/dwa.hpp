#pragma once
/// `dwa` and `dwa_fast`: the BARN baseline, base_local_planner's TrajectoryPlanner in DWA
/// mode on a move_base-like stack (nav::NavStack), with move_base's recovery.
///
/// Each control tick samples vx_samples x vtheta_samples constant (v, w) pairs in the dynamic
/// window (current velocity +- acceleration x control period, within the limits), rolls each
/// out for sim_time, and scores it
///   pdist_scale * (distance of its end to the global path)
/// + gdist_scale * (distance of its end to the local goal)
/// + occdist_scale * (highest costmap cost under the footprint along it),
/// all times the costmap resolution (meter_scoring), distances counted in cells along the
/// local costmap (4-connected wavefronts, as MapGrid). A
/// trajectory whose footprint touches a lethal cell is invalid. If no forward trajectory is
/// valid, an in-place rotation is tried, then escaping backwards at escape_vel. If nothing is
/// valid for controller_patience seconds, move_base's recovery runs: clear the costmaps beyond
/// 3 m and rotate in place a full turn, then clear beyond ~1.8 m and rotate again; after that
/// the robot gives up (stops), as move_base aborts.

#include "barn/controllers/controller.hpp"
#include "barn/core/errors.hpp"
#include "barn/nav/nav_stack.hpp"

namespace barn::controllers {

struct DwaRecoveryConfig {
  bool enabled = true;
  double controller_patience = 15.0;       // [s] without a valid command before recovering
  double conservative_reset_distance = 3.0;  // [m] first clearing keeps obstacles within this
  double aggressive_reset_distance = 1.84;   // [m] 4 x the circumscribed radius (0.46)
  double rotation_speed = 1.0;             // [rad/s] clearing rotation (rotate_recovery)
  template <class V> void visit(V& v) {
    v("enabled", enabled); v("controller_patience", controller_patience);
    v("conservative_reset_distance", conservative_reset_distance);
    v("aggressive_reset_distance", aggressive_reset_distance); v("rotation_speed", rotation_speed);
  }
};

struct DwaConfig {
  double rate = 20.0;                 // [Hz] controller_frequency
  double max_vel_x = 0.5;             // [m/s] (fast_dwa: 1.0)
  double min_vel_x = 0.1;             // [m/s]
  double max_vel_theta = 1.57;        // [rad/s]
  double min_in_place_vel_theta = 0.314;  // [rad/s]
  double acc_lim_x = 10.0;            // [m/s^2]
  double acc_lim_theta = 20.0;        // [rad/s^2]
  double sim_time = 2.0;              // [s] roll-out horizon
  double sim_granularity = 0.02;      // [m] step of the roll-out
  double angular_sim_granularity = 0.02;  // [rad]
  int vx_samples = 6;                 // (fast_dwa: 12)
  int vtheta_samples = 20;
  double pdist_scale = 0.75;
  double gdist_scale = 1.0;
  double occdist_scale = 0.1;
  double scoring_window = 3.0;        // [m] half-size of the window the path and goal distances
                                      // are computed in (ROS: the whole 10 x 10 m local map)
  double escape_vel = -0.5;           // [m/s]
  double escape_reset_dist = 0.1;     // [m]
  double oscillation_reset_dist = 0.05;  // [m] moving this far forgets the stuck rotations
  double heading_lookahead = 0.325;   // [m] how far ahead a rotation's end heading is judged
  DwaRecoveryConfig recovery;
  nav::NavStackConfig nav;

  template <class V> void visit(V& v) {
    v("rate", rate); v("max_vel_x", max_vel_x); v("min_vel_x", min_vel_x); v("max_vel_theta", max_vel_theta);
    v("min_in_place_vel_theta", min_in_place_vel_theta); v("acc_lim_x", acc_lim_x); v("acc_lim_theta", acc_lim_theta);
    v("sim_time", sim_time); v("sim_granularity", sim_granularity); v("angular_sim_granularity", angular_sim_granularity);
    v("vx_samples", vx_samples); v("vtheta_samples", vtheta_samples); v("pdist_scale", pdist_scale);
    v("gdist_scale", gdist_scale); v("occdist_scale", occdist_scale);
    v("scoring_window", scoring_window); v("escape_vel", escape_vel);
    v("escape_reset_dist", escape_reset_dist); v("oscillation_reset_dist", oscillation_reset_dist);
    v("heading_lookahead", heading_lookahead); v("recovery", recovery);
    v("nav", nav);
  }
};
void validate(const DwaConfig& config, core::Errors& errors, const std::string& prefix);

/// One scored roll-out.
struct DwaTrajectory {
  double vx = 0.0;      // [m/s]
  double vtheta = 0.0;  // [rad/s]
  double cost = -1.0;   // < 0: invalid
};

class DwaController : public Controller {
 public:
  explicit DwaController(const DwaConfig& config);
  void reset(const EpisodeInfo& info) override;
  core::Twist act(const Observation& observation) override;
  double period() const override { return 1.0 / config_.rate; }
  std::string_view stateLabel() const override;

  /// The best command for `pose` moving at `velocity` on the stack's current costmap and path
  /// (no recovery logic). Exposed for tests.
  DwaTrajectory bestTrajectory(const core::Pose2& pose, const core::Twist& velocity);
  nav::NavStack& navStack() { return nav_; }
  /// Recomputes the path and goal distance maps on the local costmap (after the path changed).
  void updateDistanceMaps(const core::Pose2& pose);

 private:
  enum class Mode { Planning, Escaping, RecoveryRotate, GaveUp };

  double scoreTrajectory(const core::Pose2& pose, double vx, double vtheta) const;
  void updateOscillationFlags(const core::Pose2& pose, const DwaTrajectory& chosen);
  double footprintCost(double x, double y, double theta) const;

  DwaConfig config_;
  nav::NavStack nav_;
  EpisodeInfo info_;
  Mode mode_ = Mode::Planning;
  double last_valid_time_ = 0.0;
  int recovery_index_ = 0;  // recoveries since the last valid command
  Eigen::Vector2d escape_start_ = Eigen::Vector2d::Zero();
  double rotated_ = 0.0;          // [rad] accumulated in the current recovery rotation
  bool rotating_left_ = false, rotating_right_ = false, stuck_left_ = false, stuck_right_ = false;
  Eigen::Vector2d oscillation_origin_ = Eigen::Vector2d::Zero();
  double last_yaw_ = 0.0;
  std::vector<Eigen::Vector2d> footprint_;  // padded corners, robot frame (from the nav stack)
  // Wavefront distances on the local costmap [cells]; kUnreachable where blocked.
  std::vector<int> path_distance_;
  std::vector<int> goal_distance_;
  std::vector<char> blocked_;  // scratch: inscribed, lethal or unknown cells of the local map
  std::vector<int> queue_;     // scratch: wavefront queue
};

}  // namespace barn::controllers
