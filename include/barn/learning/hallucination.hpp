#pragma once
/// LfLH step 2: obstacles hallucinated around recorded motions, and the scans they produce.
///
/// Method (a geometric stand-in for the original's learned hallucination model).
/// For a record at pose P, in P's frame:
///  1. The swept footprint S is the union of the robot's planning footprint (0.508 x 0.430 m,
///     core::RobotConfig::footprint_*) at the poses of the next `horizon` seconds, with poses
///     interpolated so that no footprint point moves more than `sweep_step` between two of
///     them. The planning footprint contains the collision shape (0.458 x 0.416 m), so an
///     obstacle clear of it is clear in the simulator too, and it is what the navigation stack
///     plans with; hugging the smaller collision shape would teach gaps no planner would use.
///  2. Hugging obstacles (the most constrained configuration that keeps the motion collision
///     free): each starts on the path at a random pose of the horizon and is pushed out along
///     the path normal (left or right, +- direction_jitter) until its gap to S is exactly the
///     clearance c ~ U[clearance_min, clearance_max]. The push is sphere tracing: the distance
///     to S is 1-Lipschitz, so stepping by the clearance still missing never passes the first
///     position where the gap reaches c.
///  2b. Blocking obstacles (blocking_min..blocking_max, default none): placed by the same push,
///     but forward (+- blocking_jitter) instead of sideways. Half start at a pose of the sweep
///     (biased to its end) and go along that pose's heading, so a wall stands just past where
///     the motion ends (a slow motion gets a close wall); half go straight ahead of the robot,
///     so on a turning motion they stand where driving straight would collide. Without them
///     the space ahead is almost always free and the policy learns not to slow for walls.
///     They count as hugging obstacles (`Demonstration::hugging`, `clearances`).
///  2c. Constraining placement (`candidates` > 0, instead of 2 and 2b as drawn): the published
///     hallucination learnt to place obstacles that make the recorded motion the one to take.
///     Here `candidates` obstacles are drawn as in 2 or 2b (even odds), each at its clearance
///     from S, and kept greedily (at most constraining_max): each time the candidate whose
///     overlap rules out the most alternative motions (constant (v, w) arcs over the same
///     horizon, planning footprint) that no kept obstacle rules out yet; it stops when no
///     candidate rules out another. So a slow motion gets the wall that stops the fast ones, a
///     turn the obstacles that block going straight and turning the other way, a straight run
///     the walls that close off both sides.
///  3. Distractors as in the original renderer: centres within `distractor_distance` at
///     bearings in +-135 deg, rejected if they come within clearance_min of S or enter the
///     velocity sector (radius |v| sector_time, +-sector_half_angle around the heading) at any
///     of 10 evenly spaced poses of the horizon.
///  4. The scan is cast by the simulator's own LidarCaster (same beams, 0.055 m mount offset,
///     Gaussian noise, range rules), for the robot at P.
///
/// Ellipses. The caster handles circles; an ellipse with semi-axes a >= b is represented by its
/// maximal inscribed disks centred on its medial axis (|x| <= (a^2 - b^2) / a, radius
/// b sqrt(1 - x^2 / (a^2 - b^2))), whose union is the ellipse in the limit. We take the disks
/// spaced by the vertex disk's radius b^2 / a, so the union lies inside the ellipse and its
/// boundary dips at most ~b^2 / (8 a) between two disks. The disks *are* the obstacle for
/// clearance and for the scan alike, so both are exact for the shape the policy sees. (An exact
/// ray-ellipse renderer would have been a second caster to keep in step with the simulator's.)
///
/// Clearance guarantee. Between two swept poses a footprint point moves at most sweep_step, so
/// every point of the continuous sweep lies within sweep_step / 2 of S; obstacles are placed
/// with their gap to S at c + sweep_step / 2, so their gap to the continuous sweep is >= c.

#include <cstddef>
#include <optional>
#include <vector>

#include <Eigen/Core>

#include "barn/core/rect.hpp"
#include "barn/core/rng.hpp"
#include "barn/core/robot_config.hpp"
#include "barn/core/types.hpp"
#include "barn/learning/exploration.hpp"
#include "barn/learning/lflh_config.hpp"
#include "barn/sim/lidar.hpp"

namespace barn::learning {

/// A disk of an obstacle, in the frame of the record's robot pose.
struct Disk {
  Eigen::Vector2d centre = Eigen::Vector2d::Zero();  // [m]
  double radius = 0.0;                               // [m]
};

/// A circle (one disk) or an ellipse (its inscribed disks, see the header comment).
struct Obstacle {
  Eigen::Vector2d centre = Eigen::Vector2d::Zero();  // [m]
  double semi_major = 0.0;                           // [m] a (= radius for a circle)
  double semi_minor = 0.0;                           // [m] b
  double orientation = 0.0;                          // [rad] of the major axis
  std::vector<Disk> disks;                           // the geometry that is cast and checked
};

/// The disks of an ellipse (a >= b > 0) at `centre`, major axis at `orientation`.
std::vector<Disk> ellipseDisks(const Eigen::Vector2d& centre, double a, double b, double orientation);
/// A circle or ellipse obstacle built from its parameters (circle if a == b).
Obstacle makeObstacle(const Eigen::Vector2d& centre, double a, double b, double orientation);
/// The obstacle translated by `offset`.
Obstacle translated(const Obstacle& obstacle, const Eigen::Vector2d& offset);

/// The union of footprint rectangles along a motion (see the header comment, step 1).
class SweptFootprint {
 public:
  /// `motion`: poses in order; `footprint`: the rectangle around each pose, in its frame;
  /// `step`: the most a footprint point may move between two kept poses [m].
  SweptFootprint(const std::vector<core::Pose2>& motion, const core::Rect& footprint, double step);

  /// Euclidean distance from `p` to the union of rectangles (0 inside). [m]
  double distance(const Eigen::Vector2d& p) const;
  /// Smallest gap between the obstacle's disks and the union (negative: overlap). [m]
  double gap(const Obstacle& obstacle) const;
  /// How far the continuous sweep can bulge beyond the union: step / 2. [m]
  double inflation() const { return 0.5 * step_; }
  const std::vector<core::Pose2>& poses() const { return poses_; }

 private:
  std::vector<core::Pose2> poses_;   // interpolated poses
  std::vector<double> cos_, sin_;    // of each pose's yaw
  core::Rect footprint_;             // [m] robot frame
  double step_;                      // [m]
};

/// One demonstration: the record's situation with hallucinated obstacles, and its label.
struct Demonstration {
  std::size_t record = 0;               // index of the record in the recording
  std::vector<core::Pose2> motion;      // [m, rad] the horizon's recorded poses, robot frame
  std::vector<Obstacle> obstacles;      // hugging obstacles first, then distractors
  std::size_t hugging = 0;              // how many of `obstacles` hug the motion
  std::vector<double> clearances;       // [m] target gap of each hugging obstacle
  Eigen::Vector2d goal = Eigen::Vector2d::UnitX();  // unit vector to the goal pose, robot frame
  core::Twist command;                  // the recorded cmd_vel: the label
  std::vector<double> ranges;           // [m] the rendered scan, +inf for no return
};

/// Hallucinates obstacles around record `record` (draw number `render`) and renders the scan.
/// nullopt if the record is too close to the end of the recording for the horizon and the goal,
/// or if its goal is closer than min_goal_distance (the robot barely moves).
std::optional<Demonstration> hallucinate(const Recording& recording, std::size_t record, int render,
                                         const HallucinationConfig& config,
                                         const core::RobotConfig& robot = {}, const core::LidarConfig& lidar = {});

/// The alternative motions of the constraining placement: constant (v, w) arcs from the origin
/// over `horizon` seconds (v in alternative_speed * (1..n) / n, w in
/// linspace(-alternative_turn_rate, alternative_turn_rate, alternative_turns)), swept with
/// `footprint`.
std::vector<SweptFootprint> alternativeSweeps(const HallucinationConfig& config, double horizon, const core::Rect& footprint);

/// Greedy maximum coverage: indices of at most `most` candidates, each in turn the one whose
/// footprint overlap rules out the most alternatives (at most 64) not yet ruled out (ties: the
/// lower index); stops early when no candidate rules out another.
std::vector<std::size_t> mostConstraining(const std::vector<Obstacle>& candidates,
                                          const std::vector<SweptFootprint>& alternatives, std::size_t most);

/// The scan of `obstacles` from a robot at the origin, cast by sim::LidarCaster; no noise if
/// `noise` is null.
std::vector<double> renderScan(const std::vector<Obstacle>& obstacles, const core::LidarConfig& lidar,
                               core::FastNoise* noise);

/// Obstacles mirrored across the robot's x axis (y -> -y).
std::vector<Obstacle> mirrored(const std::vector<Obstacle>& obstacles);

/// Training examples, one column each. Input layout (the policy's): `beams` ranges clipped to
/// [0, range_clip] (+inf -> range_clip), then the goal's x (forward) and y (left).
struct Dataset {
  int beams = 720;
  Eigen::MatrixXf inputs;            // (beams + 2) x n
  Eigen::MatrixXf targets;           // 2 x n: v [m/s], w [rad/s]
  std::vector<std::size_t> records;  // source record of each column (time order)
  std::size_t lookahead = 0;         // [records] a column looks this far past its record
  std::size_t record_count = 0;      // records in the recording(s)
  /// Where each recording begins in `records`' numbering: {0} for one recording; appendDataset
  /// numbers a joined recording's records on after the ones before.
  std::vector<std::size_t> recording_starts = {0};

  std::size_t size() const { return records.size(); }
};

/// Joins `more` (another recording's demonstrations, the same beams) onto `into`: its columns
/// follow, its records are numbered on after `into`'s, the lookahead is the larger of the two.
/// The training split then holds out the last share of each recording (trainer.hpp).
void appendDataset(Dataset& into, const Dataset& more);

/// Mirrors an input column and its target in place: beam order reversed, goal y and w negated.
/// Valid because the beams are symmetric about the x axis (angle_min = -angle_max, mount_y = 0).
void mirrorExample(float* input, float* target, int beams);

/// Every demonstration of the recording (records 0, stride, 2 stride, ..., renders_per_sample
/// each). Deterministic: each draw is seeded from (seed, record, render) alone.
Dataset buildDataset(const Recording& recording, const HallucinationConfig& config, double range_clip,
                     const core::RobotConfig& robot = {}, const core::LidarConfig& lidar = {});

}  // namespace barn::learning
