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
#include "barn/controllers/move_base.hpp"
#include "barn/core/errors.hpp"
#include "barn/nav/nav_stack.hpp"

namespace barn::controllers {

/// move_base's patience and recoveries (controllers/move_base.hpp).
using DwaRecoveryConfig = MoveBaseRecoveryConfig;

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
  double occdist_scale = 0.1;         // never scaled by the resolution (upstream since 2018)
  // meter_scoring: the path and goal distances count in metres (x resolution) rather than
  // cells. Upstream decides this from a member it never assigns; BARN's config asks for it,
  // and per metre matches Gazebo's per-world times (docs/fidelity.md).
  bool meter_scoring = true;
  double scoring_window = 3.0;        // [m] half-size of the window the path and goal distances
                                      // are computed in (ROS: the whole 10 x 10 m local map)
  double escape_vel = -0.5;           // [m/s]
  double escape_reset_dist = 0.1;     // [m] escaping ends after backing this far ...
  double escape_reset_theta = 0.1;    // [rad] ... or turning this much
  double oscillation_reset_dist = 0.05;  // [m] moving this far from the last in-place turn
                                         //     forgets the stuck rotations
  double heading_lookahead = 0.325;   // [m] how far ahead a rotation's end heading is judged
  DwaRecoveryConfig recovery;
  nav::NavStackConfig nav = nav::NavStackConfig::moveBaseWithNavFn();  // docs/fidelity.md, "The global planner"

  template <class V> void visit(V& v) {
    v("rate", rate); v("max_vel_x", max_vel_x); v("min_vel_x", min_vel_x); v("max_vel_theta", max_vel_theta);
    v("min_in_place_vel_theta", min_in_place_vel_theta); v("acc_lim_x", acc_lim_x); v("acc_lim_theta", acc_lim_theta);
    v("sim_time", sim_time); v("sim_granularity", sim_granularity); v("angular_sim_granularity", angular_sim_granularity);
    v("vx_samples", vx_samples); v("vtheta_samples", vtheta_samples); v("pdist_scale", pdist_scale);
    v("gdist_scale", gdist_scale); v("occdist_scale", occdist_scale); v("meter_scoring", meter_scoring);
    v("scoring_window", scoring_window); v("escape_vel", escape_vel);
    v("escape_reset_dist", escape_reset_dist); v("escape_reset_theta", escape_reset_theta);
    v("oscillation_reset_dist", oscillation_reset_dist);
    v("heading_lookahead", heading_lookahead); v("recovery", recovery);
    v("nav", nav);
  }
};
void validate(const DwaConfig& config, core::Errors& errors, const std::string& prefix);

/// One scored roll-out.
struct DwaTrajectory {
  double vx = 0.0;      // [m/s] the sample's velocities (what is commanded)
  double vtheta = 0.0;  // [rad/s]
  double cost = -1.0;   // -1: the footprint hits or leaves the map; -2: no way on from a point
  core::Pose2 end;      // the last scored pose
};

class DwaController : public Controller {
 public:
  explicit DwaController(const DwaConfig& config);
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
  bool escaping() const { return escaping_; }

 private:
  /// One TrajectoryPlanner cycle for `pose` moving at `velocity` on the stack's current
  /// costmap and the distance maps of the last updateDistanceMaps(): forward arcs, in-place
  /// rotations, else the blind back-up; updates the oscillation and escape flags as upstream.
  /// cost < 0: no command (the robot stops).
  DwaTrajectory findBestPath(const core::Pose2& pose, const core::Twist& velocity);
  /// The velocity samples' window: one control period's acceleration around `velocity`.
  struct SampleWindow {
    double min_x = 0.0, max_x = 0.0, min_th = 0.0, max_th = 0.0;
    double dvx = 0.0, dvth = 0.0;  // steps between samples
  };
  SampleWindow sampleWindow(const core::Twist& velocity) const;
  // findBestPath's phases: each replaces `best` with a better legal trajectory of its kind.
  void chooseForwardArc(const core::Pose2& pose, const core::Twist& velocity, const SampleWindow& window,
                        DwaTrajectory& best);
  void chooseRotation(const core::Pose2& pose, const core::Twist& velocity, const SampleWindow& window,
                      DwaTrajectory& best);
  void clearOscillationIfMoved(const core::Pose2& pose);
  void endEscapeIfDone(const core::Pose2& pose);
  /// Recomputes the path and goal distance maps on the local costmap (after the path changed).
  void updateDistanceMaps(const core::Pose2& pose);

  /// The headings of every roll-out with the same step count and yaw-rate sample: the yaw
  /// sequence depends on nothing else within one findBestPath(), so its sines and cosines
  /// are computed once and shared (the arcs of one yaw rate at different speeds often take
  /// the same number of steps, and so do the in-place rotations).
  struct HeadingRun {
    int steps = 0;
    double vtheta = 0.0;
    std::size_t first = 0;  // into headings_
  };
  /// One roll-out step's yaw, with its cosine and sine.
  struct Heading {
    double theta = 0.0, cos = 1.0, sin = 0.0;
  };
  /// The points of one roll-out: positions here, headings in a HeadingRun.
  struct RolloutPoints {
    std::size_t first_position = 0;  // into positions_
    std::size_t first_heading = 0;   // into headings_
    int count = 0;
  };
  /// A roll-out's last pose.
  core::Pose2 endPose(const RolloutPoints& points) const;
  /// What a roll-out's points cost without its footprint outlines: the distances of its last
  /// point and the highest cost under its centre. `plausible` is false if a point leaves the
  /// map or cannot reach the path or the local goal (the roll-out is invalid then).
  struct CentreScore {
    bool plausible = false;
    int path_cells = 0;
    int goal_cells = 0;
    int occupancy = 0;
  };
  /// A forward arc waiting for its centre and footprint checks; `bound` is its cost at zero
  /// occupancy (a lower bound on its cost: the cost only grows with the occupancy).
  struct ArcCandidate {
    double vx = 0.0, vtheta = 0.0;
    int order = 0;  // its place in upstream's sampling order (ties keep the earlier)
    RolloutPoints points;
    double bound = 0.0;
  };
  /// One MapGrid wavefront over the scoring window (row-major with a one-cell border it never
  /// enters, so it needs no bounds checks), advanced lazily, only as far as the distances read
  /// from it need: a breadth-first search fixes a cell's distance when it first reaches it,
  /// so stopping there gives what the whole search would.
  struct Wavefront {
    std::vector<int> distance;  // [cells] the values below, or the distance of a reached cell
    std::vector<int> queue;     // reached cells; those from `head` on are not expanded yet
    std::size_t head = 0, tail = 0;
    int stride = 0;
    int obstacle = 0;           // a blocked cell reached; also the border
    int unreached = 1;          // obstacle + 1: an open cell not reached (yet)
    int blocked = 2;            // obstacle + 2: a blocked cell not reached (yet)

    /// Seeds the search (distance prepared with the values above).
    void start(std::span<const int> seeds);
    /// The distance of cell i, `unreached` if the search never gets there.
    int at(int i) {
      while (!settled(i) && head < tail) expandNext();
      return std::min(distance[static_cast<std::size_t>(i)], unreached);
    }
    /// The same where only a distance below `obstacle` matters: a blocked cell the search has
    /// not reached can only end at obstacle or unreached, so it gives unreached at once.
    int openAt(int i) { return distance[static_cast<std::size_t>(i)] == blocked ? unreached : at(i); }

   private:
    bool settled(int i) const {
      const int d = distance[static_cast<std::size_t>(i)];
      return d != unreached && d != blocked;
    }
    void expandNext() {
      // A blocked cell takes `obstacle` when reached and is not expanded; the border holds
      // `obstacle`, so the search never steps onto it.
      int* d = distance.data();
      const int i = queue[head++];
      const int next = d[i] + 1;
      const auto visit = [&](int j) {
        if (d[j] == unreached) {
          d[j] = next;
          queue[tail++] = j;
        } else if (d[j] == blocked) {
          d[j] = obstacle;
        }
      };
      visit(i - 1);
      visit(i + 1);
      visit(i - stride);
      visit(i + stride);
    }
  };
  /// MapGrid's path and goal distances on the scoring window; a cell outside it counts as
  /// never reached.
  struct DistanceGrid {
    int x0 = 0, y0 = 0;          // map cell of the window's first cell
    int width = 0, height = 0;   // [cells] the window (0: not computed yet)
    int stride = 0;              // width + 2
    Wavefront path;
    Wavefront goal;
    /// Index of map cell (x, y), or -1 outside the window.
    int index(int x, int y) const {
      const int lx = x - x0, ly = y - y0;
      if (lx < 0 || ly < 0 || lx >= width || ly >= height) return -1;
      return (ly + 1) * stride + lx + 1;
    }
  };

  DwaTrajectory rollOut(const core::Pose2& pose, const core::Twist& velocity, double vx, double vtheta);
  int rolloutSteps(double vx, double vtheta) const;
  RolloutPoints simulate(const core::Pose2& pose, const core::Twist& velocity, double vx, double vtheta);
  std::size_t headings(const core::Pose2& pose, const core::Twist& velocity, int steps, double vtheta);
  CentreScore scoreCentres(const RolloutPoints& points);
  /// A rollout point's path and goal distances (cells) at `cell`: false if the cell is outside
  /// the scoring window or either distance is an obstacle's or unreached (upstream's -2).
  bool openDistances(const nav::CellIndex& cell, int& path_cells, int& goal_cells);
  template <class CannotWin>
  int outlineOccupancy(const RolloutPoints& points, int occupancy, CannotWin cannot_win) const;
  double trajectoryCost(int path_cells, int goal_cells, int occupancy) const;
  int pathDistance(const nav::CellIndex& cell);
  int goalDistance(const nav::CellIndex& cell);
  bool footprintCorners(double x, double y, double cos_theta, double sin_theta, nav::CellIndex (&corners)[4]) const;
  int outlineCost(const nav::CellIndex (&corners)[4]) const;

  DwaConfig config_;      // in force: the configured values changed by setParameter()
  DwaConfig configured_;  // what reset() restores
  nav::NavStack nav_;
  EpisodeInfo info_;
  MoveBase move_base_;
  // TrajectoryPlanner's flags.
  bool escaping_ = false;
  core::Pose2 escape_pose_;
  bool rotating_left_ = false, rotating_right_ = false, stuck_left_ = false, stuck_right_ = false;
  Eigen::Vector2d last_rotation_position_ = Eigen::Vector2d::Zero();  // prev_x_, prev_y_
  std::vector<Eigen::Vector2d> footprint_;  // padded corners, robot frame (from the nav stack)
  // MapGrid distances on the local costmap [cells]: obstacle_distance_ for a blocked cell,
  // obstacle_distance_ + 1 for one never reached.
  int obstacle_distance_ = 0;
  int unreached() const { return obstacle_distance_ + 1; }
  DistanceGrid distances_;
  // Scratch, kept to reuse its memory from tick to tick.
  std::vector<int> path_seeds_;
  std::vector<HeadingRun> heading_runs_;
  std::vector<Heading> headings_;
  std::vector<Eigen::Vector2d> positions_;
  std::vector<ArcCandidate> arcs_;
};

}  // namespace barn::controllers
