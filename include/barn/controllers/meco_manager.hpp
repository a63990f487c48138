#pragma once
/// The MECO corridor manager (`meco`, their corridor_manager.py, 10 Hz): the tree of corridors
/// the robot has found, which one it drives in, when it moves on to a child, and when it backs
/// out of a dead end. Everything in the odom frame.
///
/// A new corridor from the fitter (receive()) is, on the next tick:
///  - the root, if there is none yet (and published: the robot drives in it);
///  - ignored, if the robot is not in the current corridor (the root excepted) when the
///    corridor was fitted;
///  - if it contains the goal: added as a child of the current corridor, and published as the
///    final corridor; the manager then stops;
///  - else added as a child of the current corridor unless it is "stuck" (reaches less than
///    `stuck_threshold` (0.4 m) beyond the current corridor, corridorImprovement) or similar to
///    a corridor backed out of (its front corners within `orphan_distance` (2 m), summed).
///    Adding (addChild) is refused when the corridor is not significantly different from the
///    current corridor's parent; a child reaching higher than the current corridor's largest
///    corner y + `quality_margin` (0.2 m) gets quality 1, else 0.1. The children are then kept
///    ordered by their largest corner y and thinned of similar ones.
/// Then, when the robot is within `end_distance` (0.5 m) of the current corridor's front edge,
/// or the current corridor has a child of quality >= `quality_threshold` (0.5): at the end,
/// after waiting `end_wait` (0.5 s), else at once, a child becomes the current corridor (the
/// first of quality >= 0.5, else the first) and is published. With no child to take, after
/// `backtrack_wait` (1.5 s) the manager backs out (backtrack()): the current corridor and the
/// ancestors it leaves go to the orphanage, corridors similar to an orphan leave the tree, and
/// the list of corridors to drive back through is published; it then waits until the robot is
/// inside the corridor it returns to.
///
/// "Significantly different" (significantlyDifferent): the two corridors' front corners are
/// farther apart than a distance (summed over front-right and front-left) and their headings
/// differ by more than an angle (children: 1 m and 22.5 deg; the parent's parent: 1 m and 0).
///
/// Source: meco-group/Barn_challenge@66cef2c corridors/scripts/corridor_manager.py,
/// corridor_world.py, corridor_helpers.py (MIT; facts restated, no code copied).

#include <span>
#include <string>
#include <string_view>
#include <vector>

#include <Eigen/Core>

#include "barn/controllers/meco_corridor.hpp"
#include "barn/core/config.hpp"
#include "barn/core/errors.hpp"

namespace barn::controllers {

struct MecoManagerConfig {
  double rate = 10.0;
  double quality_threshold = 0.5;
  double quality_margin = 0.2;
  double stuck_threshold = 0.4;
  double orphan_distance = 2.0;
  double parent_distance = 1.0;
  double similar_distance = 1.0;
  double similar_angle_deg = 22.5;
  double end_distance = 0.5;
  double end_wait = 0.5;
  double backtrack_wait = 1.5;
  double min_backtrack_distance = 1.5;
  double inside_tolerance = 1e-3;

  template <class V> void visit(V& v) {
    v("rate", rate, {.unit = "Hz", .range = core::kPositive, .doc = "team: manager_rate"});
    v("quality_threshold", quality_threshold,
      {.range = core::kNonNegative, .doc = "team: select a child of quality >= 0.5"});
    v("quality_margin", quality_margin, {.unit = "m", .doc = "team: add_child_corridor(margin=.2)"});
    v("stuck_threshold", stuck_threshold,
      {.unit = "m", .range = core::kNonNegative, .doc = "team: check_stuck's default threshold"});
    v("orphan_distance", orphan_distance,
      {.unit = "m", .range = core::kNonNegative, .doc = "team: distance_threshold=2.0 against the orphanage"});
    v("parent_distance", parent_distance,
      {.unit = "m", .range = core::kNonNegative, .doc = "team: add_child_corridor's check against the parent's parent"});
    v("similar_distance", similar_distance,
      {.unit = "m", .range = core::kNonNegative, .doc = "team: check_significantly_different's default"});
    v("similar_angle_deg", similar_angle_deg,
      {.unit = "deg", .range = core::closed(0.0, 180.0), .doc = "team: its default pi / 8"});
    v("end_distance", end_distance,
      {.unit = "m", .range = core::kPositive, .doc = "team: check_end_of_corridor_reached(..., 0.5)"});
    v("end_wait", end_wait, {.unit = "s", .range = core::kNonNegative, .doc = "team: end_reached_waiting_time"});
    v("backtrack_wait", backtrack_wait,
      {.unit = "s", .range = core::kNonNegative, .doc = "team: backtrack_waiting_time"});
    v("min_backtrack_distance", min_backtrack_distance,
      {.unit = "m", .range = core::kNonNegative, .doc = "team: minimal_backtrack_distance"});
    v("inside_tolerance", inside_tolerance,
      {.unit = "m", .range = core::kNonNegative, .doc = "team: check_inside_one_point's tolerance"});
  }
};
void validate(const MecoManagerConfig& config, core::Errors& errors, const std::string& prefix);

/// How far `child` reaches beyond `parent` [m] (check_stuck's improvement, >= 0): from the
/// child's growth centre along the child's heading, its front edge's distance less the
/// distance to where that heading leaves the parent (through its front, or through the side it
/// turns toward once the heading passes that side's front corner).
double corridorImprovement(const MecoCorridor& parent, const MecoCorridor& child);

/// check_significantly_different: the front-right and front-left corners are farther apart than
/// `distance` (summed) and the headings differ by more than `angle` [rad] (wrapped).
bool significantlyDifferent(const MecoCorridor& a, const MecoCorridor& b, double distance, double angle);

/// What the manager tells the navigator.
enum class MecoMessageKind {
  Next,       // drive into this corridor next (one corridor)
  Final,      // this corridor holds the goal (one corridor)
  Backtrack,  // back out through these corridors: the dead end first, the one to return to last
};
std::span<const std::string_view> enumNames(MecoMessageKind);

struct MecoMessage {
  MecoMessageKind kind = MecoMessageKind::Next;
  std::vector<MecoCorridor> corridors;
};

/// Where the manager is: no corridor yet; driving the current corridor; waiting at its end;
/// waiting to back out; backing out; done (the goal is in a corridor).
enum class MecoPhase { Starting, Exploring, WaitingAtEnd, WaitingToBacktrack, Backtracking, GoalInSight };
std::span<const std::string_view> enumNames(MecoPhase);

class MecoManager {
 public:
  /// A corridor in the tree. Nodes are never erased: a node that leaves the tree keeps its
  /// index, with no parent and no parent listing it.
  struct Node {
    MecoCorridor corridor;
    int parent = -1;
    std::vector<int> children;   // best (largest corner y) first
    double quality = 0.0;        // [-] 1 or 0.1, set when it was added as a child
    bool fully_explored = false; // the robot reached its end while it was the current corridor
  };

  explicit MecoManager(const MecoManagerConfig& config) : config_(config) {}
  void reset();
  /// The fitter's corridors (odom frame, their growth centre where the robot stood), for the
  /// next tick.
  void receive(std::span<const MecoCorridor> corridors);
  /// One manager cycle at `time` [s] with the robot at `robot` and the goal at `goal` (odom
  /// frame): the messages it publishes, in order.
  std::vector<MecoMessage> tick(double time, const Eigen::Vector2d& robot, const Eigen::Vector2d& goal);

  MecoPhase phase() const;
  const std::vector<Node>& nodes() const { return nodes_; }
  int root() const { return root_; }
  int current() const { return current_; }
  const std::vector<MecoCorridor>& orphanage() const { return orphans_; }

  /// add_child_corridor: adds `corridor` as a child of `parent` unless `force` is false, `parent`
  /// has a parent and the corridor is not significantly different from that one (parent_distance,
  /// angle 0); its quality from `margin`. Returns the new node or -1.
  int addChild(int parent, const MecoCorridor& corridor, bool force, double margin);
  /// Orders `node`'s children by their largest corner y, best first (stable).
  void sortChildren(int node);
  /// Drops each child not significantly different from an earlier one (similar_distance,
  /// similar_angle_deg), from the last.
  void removeSimilarChildren(int node);
  /// get_back_track_point: moves `current_` to the corridor to return to and returns the
  /// corridors to back out through; empty if the current corridor has no parent.
  std::vector<MecoCorridor> backtrack();

 private:
  void processNew(const MecoCorridor& corridor, const Eigen::Vector2d& goal, std::vector<MecoMessage>& out);
  /// select_child_corridor: the child to move on to, or -1.
  int selectChild(int node) const;
  bool hasQualityChild(int node) const;
  void detach(int node);
  /// clear_backtrack_like_corridors: from `node` down, drops children similar to an orphan.
  void clearOrphanLike(int node);
  bool similarToOrphan(const MecoCorridor& corridor, double angle) const;

  MecoManagerConfig config_;
  std::vector<Node> nodes_;
  std::vector<MecoCorridor> orphans_;
  std::vector<MecoCorridor> pending_;   // received since the last tick
  int root_ = -1;
  int current_ = -1;
  bool goal_in_sight_ = false;
  bool backtracking_ = false;
  bool waiting_at_end_ = false;
  double end_since_ = 0.0;              // [s]
  bool waiting_to_backtrack_ = false;
  double backtrack_since_ = 0.0;        // [s]
};

}  // namespace barn::controllers
