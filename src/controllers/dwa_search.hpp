#pragma once
// TrajectoryPlanner's search in DWA mode (base_local_planner), the machinery of the `dwa`
// controller: the velocity window's samples rolled out on the local costmap and scored
// against MapGrid's path and goal distances, the in-place rotations, the blind back-up, and
// the oscillation and escape flags. Private to the controllers library; dwa.hpp says what it
// does, this header how.
//
// The forward arcs are searched with bounds (chooseForwardArc): each is bounded from below by
// its last point's distances, and its centre cells and footprint outlines (the expensive part)
// are walked only while it can still win. rollOut() scores one sample point by point, as
// upstream does; the tests check that the pruned search picks what scoring every sample with
// rollOut() picks.

#include <span>
#include <vector>

#include <Eigen/Core>

#include "barn/controllers/dwa.hpp"
#include "barn/nav/costmap.hpp"
#include "barn/nav/path_tools.hpp"

namespace barn::controllers {

/// One scored roll-out.
struct DwaTrajectory {
  double vx = 0.0;      // [m/s] the sample's velocities (what is commanded)
  double vtheta = 0.0;  // [rad/s]
  double cost = -1.0;   // -1: the footprint hits or leaves the map; -2: no way on from a point
  core::Pose2 end;      // the last scored pose
};

class DwaSearch {
 public:
  /// `config` is the controller's, read at every cycle (its values may change between
  /// cycles); `footprint` the padded footprint's corners in the robot frame.
  DwaSearch(const DwaConfig& config, std::vector<Eigen::Vector2d> footprint);
  /// A new episode: the flags cleared.
  void reset();
  /// Recomputes the path and goal distance maps on the local costmap `map` from `path` (null:
  /// no path) around `pose`.
  void updateDistanceMaps(const nav::Costmap& map, const nav::Path* path, const core::Pose2& pose);
  /// One TrajectoryPlanner cycle for `pose` moving at `velocity` on the stack's current
  /// costmap and the distance maps of the last updateDistanceMaps(): forward arcs, in-place
  /// rotations, else the blind back-up; updates the oscillation and escape flags as upstream.
  /// cost < 0: no command (the robot stops).
  DwaTrajectory findBestPath(const nav::Costmap& map, const core::Pose2& pose, const core::Twist& velocity);
  /// The velocity samples' window: one control period's acceleration around `velocity`.
  struct SampleWindow {
    double min_x = 0.0, max_x = 0.0, min_th = 0.0, max_th = 0.0;
    double dvx = 0.0, dvth = 0.0;  // steps between samples
  };
  SampleWindow sampleWindow(const core::Twist& velocity) const;
  /// One sample scored point by point, as TrajectoryPlanner::generateTrajectory scores it:
  /// the reference the pruned search must agree with.
  DwaTrajectory rollOut(const core::Pose2& pose, const core::Twist& velocity, double vx, double vtheta);
  /// MapGrid's goal distance of a cell [cells] (unreached outside the window).
  int goalDistance(const nav::CellIndex& cell);
  bool escaping() const { return escaping_; }
  bool stuckLeft() const { return stuck_left_; }
  bool stuckRight() const { return stuck_right_; }

 private:
  // findBestPath's phases: each replaces `best` with a better legal trajectory of its kind.
  void chooseForwardArc(const core::Pose2& pose, const core::Twist& velocity, const SampleWindow& window,
                        DwaTrajectory& best);
  void chooseRotation(const core::Pose2& pose, const core::Twist& velocity, const SampleWindow& window,
                      DwaTrajectory& best);
  void clearOscillationIfMoved(const core::Pose2& pose);
  void endEscapeIfDone(const core::Pose2& pose);

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
  bool footprintCorners(double x, double y, double cos_theta, double sin_theta, nav::CellIndex (&corners)[4]) const;
  int outlineCost(const nav::CellIndex (&corners)[4]) const;

  const DwaConfig& config_;  // the controller's, in force
  const nav::Costmap* map_ = nullptr;  // the local costmap of this cycle
  // TrajectoryPlanner's flags.
  bool escaping_ = false;
  core::Pose2 escape_pose_;
  bool rotating_left_ = false, rotating_right_ = false, stuck_left_ = false, stuck_right_ = false;
  Eigen::Vector2d last_rotation_position_ = Eigen::Vector2d::Zero();  // prev_x_, prev_y_
  std::vector<Eigen::Vector2d> footprint_;  // padded corners, robot frame
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
