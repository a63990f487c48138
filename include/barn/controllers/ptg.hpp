#pragma once
/// A parameterized trajectory generator (PTG) of circular arcs for a differential drive, after
/// MRPT's `CPTG_DiffDrive_C`, and the TP-space obstacles of a polygonal robot on it: the building
/// blocks of MRPT's TP-space reactive navigation (Blanco, Gonzalez-Jimenez, Fernandez-Madrigal,
/// IROS 2006), which `almeria_tps` runs.
///
/// Robot frame throughout: x forward, y left, origin at the robot centre.
///
/// Paths. Path k of N has the direction parameter alpha_k = pi (-1 + (2k + 1) / N), so paths
/// 0 ... N-1 sweep alpha from near -pi (hard right) through 0 (straight, the middle path when N
/// is odd) to near +pi (hard left). Along path k the robot drives the constant command
///     v_k = v_max (1 - v_falloff |alpha_k|),   w_k = (alpha_k / pi) w_max,
/// a circle of radius R_k = v_k / w_k about (0, R_k) (a straight line for alpha_k = 0). MRPT
/// measures progress along a path in "pseudo-metres" that count turning too:
///     d = t sqrt(v_k^2 + (w_k r)^2),   r = turning_radius_reference,
/// so a point a turn angle theta along the circle lies d = theta sqrt(R_k^2 + r^2) along the path.
/// A path ends at d = ref_distance or after a turn of 1.95 pi (MRPT stops simulating a path
/// there, so tight circles do not count their own loop), whichever comes first:
/// pathLength(k).
///
/// TP-space. A point of the plane maps to (k, d): the path whose circle through the origin,
/// tangent to x, passes through the point, and how far along it the point lies (inverseMap,
/// MRPT's closed form for this PTG). An obstacle point maps, for every path k, to the distance
/// d along k at which the robot's polygon first touches it (collisionDistance); the TP-obstacle
/// of path k is the least such distance over all obstacle points, or the path's length, divided
/// by ref_distance (so 1 is "free as far as the PTG looks").
///
/// The collision grid. As MRPT does, collision distances are tabulated once on a grid of
/// `resolution` cells over [-ref_distance, ref_distance]^2: a cell lists, for each path that
/// touches it, the least collision distance over the cell's four corners (MRPT marks every cell
/// sharing a corner that lies inside the robot polygon at some pose along the path with that
/// pose's distance: the same table, here computed exactly per corner instead of at sampled
/// poses). An obstacle point reads its cell's list: no geometry per scan.
///
/// Obstacles inside the robot polygon at the start. MRPT's default COLLISION_BEHAVIOR
/// (COLL_BEH_BACK_AWAY) ignores an obstacle point that lies inside the robot polygon where the
/// collision distance is below the robot's largest vertex radius (moving away from it), and
/// blocks the path (distance 0) otherwise. With the table above such a point's distance is 0 on
/// every path that reaches its cell, so points inside the polygon are ignored.
///
/// Sources (BSD-3): MRPT/mrpt@0392d57 libs/nav/src/tpspace/CPTG_DiffDrive_C.cpp (steering
/// function, inverse map), @213cb1c libs/nav/src/tpspace/CPTG_DiffDrive_CollisionGridBased.cpp
/// (path simulation, pseudo-metres, collision grid), @01228ee
/// libs/nav/src/tpspace/CParameterizedTrajectoryGenerator.cpp (alpha <-> index, TP-obstacle
/// initial values and post-processing); the parameters: the BARN Jackal PTG file
/// mrpt-ros-pkg/mrpt_navigation@58fe36f mrpt_tps_astar_planner/configs/ini/ptgs_jackal.ini.

#include <cstdint>
#include <span>
#include <string>
#include <vector>

#include <Eigen/Core>

#include "barn/core/config.hpp"
#include "barn/core/errors.hpp"
#include "barn/core/types.hpp"

namespace barn::controllers {

/// The PTG's parameters. Defaults: PTG0 of the BARN Jackal file (ptgs_jackal.ini at
/// mrpt-ros-pkg/mrpt_navigation@58fe36f), or MRPT's default where the file sets none.
struct PtgConfig {
  int num_paths = 151;
  double ref_distance = 3.0;
  double resolution = 0.05;
  double v_max = 1.2;
  // Ini: PTG0_v_max_mps = ROBOT_MAX_V * (1 - abs(dir) / 3.2), dir read as alpha [rad]
  // (our reading; 3.2 > pi keeps v > 0 on the hard-turn paths). 0: every path at v_max, as in
  // MRPT's plain CPTG_DiffDrive_C.
  double v_falloff = 1.0 / 3.2;
  double w_max_deg = 60.0;
  double turning_radius_reference = 0.10;
  // Ini: RobotModel_shape2D_xs/ys, the Jackal's +-0.265 x +-0.225 box grown to +-0.30 x +-0.27
  // ("Barn map obstacles are points, we must ADD the cylinders radius"). A simple polygon.
  std::vector<double> shape_x = {0.30, 0.30, -0.30, -0.30};
  std::vector<double> shape_y = {-0.27, 0.27, 0.27, -0.27};

  template <class V> void visit(V& v) {
    v("num_paths", num_paths, {.range = core::closed(3, 65535), .doc = "ini: PTG0_num_paths"});
    v("ref_distance", ref_distance,
      {.unit = "m", .range = core::kPositive, .doc = "ini: PTG0_refDistance = NAV_MAX_REF_DIST"});
    v("resolution", resolution, {.unit = "m", .doc = "ini: PTG0_resolution, the collision grid's cell size"});
    v("v_max", v_max, {.unit = "m/s", .range = core::kPositive, .doc = "ini: ROBOT_MAX_V"});
    v("v_falloff", v_falloff, {.unit = "1/rad"});
    v("w_max_deg", w_max_deg, {.unit = "deg/s", .range = core::kPositive, .doc = "ini: PTG0_w_max_dps = ROBOT_MAX_W"});
    v("turning_radius_reference", turning_radius_reference,
      {.unit = "m", .range = core::kNonNegative, .doc = "MRPT default (CPTG_DiffDrive_CollisionGridBased)"});
    v("shape_x", shape_x, {.unit = "m"});
    v("shape_y", shape_y, {.unit = "m"});
  }
};
void validate(const PtgConfig& config, core::Errors& errors, const std::string& prefix);

/// MRPT's path index <-> direction parameter (CParameterizedTrajectoryGenerator::index2alpha,
/// alpha2index): alpha_k = pi (-1 + (2k + 1) / n); the index of alpha (wrapped to (-pi, pi]) is
/// round((n (1 + alpha / pi) - 1) / 2), half away from zero, clamped to [0, n - 1].
double pathAlpha(int k, int n);
int alphaIndex(double alpha, int n);

/// A point of TP-space: path `k`, `distance` along it.
struct TpPoint {
  int k = 0;
  double distance = 0.0;  // [m] pseudo-metres along path k
  bool exact = true;      // false: no path reaches the point (MRPT then discards the PTG)
};

/// The circular-arc PTG with its collision grid (built in the constructor; read-only after, so
/// one instance may be shared by every episode and thread).
class ArcPtg {
 public:
  explicit ArcPtg(const PtgConfig& config);

  const PtgConfig& config() const { return config_; }
  int pathCount() const { return config_.num_paths; }
  double refDistance() const { return config_.ref_distance; }
  double alpha(int k) const { return pathAlpha(k, config_.num_paths); }
  double linearSpeed(int k) const;   // [m/s] v_k
  double angularSpeed(int k) const;  // [rad/s] w_k
  /// [m] Where path k ends: ref_distance or a turn of 1.95 pi, whichever is nearer.
  double pathLength(int k) const { return path_length_[static_cast<std::size_t>(k)]; }
  /// The robot's pose `distance` [m] along path k.
  core::Pose2 poseAt(int k, double distance) const;
  /// MRPT's inverse map of a robot-frame point (see the header comment). A point behind the
  /// robot on the x axis, or inside the tightest path's circle, is not exact.
  TpPoint inverseMap(const Eigen::Vector2d& point) const;

  /// Whether `point` lies inside the robot polygon (at the start of every path).
  bool insideShape(const Eigen::Vector2d& point) const;
  /// [m] The largest distance of a polygon vertex from the robot centre.
  double maxRobotRadius() const { return max_radius_; }
  /// [m] How far along path k the robot polygon first touches `point`, computed exactly (the
  /// point's circle about the path's centre of rotation against the polygon's edges): 0 if the
  /// point is inside the polygon, +inf if the path ends first.
  double collisionDistance(int k, const Eigen::Vector2d& point) const;

  /// The TP-obstacles of `points` (robot frame), normalised by ref_distance, into `out`
  /// (pathCount() values): each path's length, lowered to the least tabulated collision
  /// distance of a point in the grid, with MRPT's handling of points inside the polygon.
  void tpObstacles(std::span<const Eigen::Vector2d> points, std::vector<double>& out) const;

  /// The collision grid's entries for the cell holding `point` (empty outside the grid).
  struct CellEntry {
    std::uint16_t k;
    float distance;  // [m]
  };
  std::span<const CellEntry> cellEntries(const Eigen::Vector2d& point) const;

 private:
  void buildGrid();

  PtgConfig config_;
  std::vector<Eigen::Vector2d> shape_;  // [m] polygon vertices
  double max_radius_ = 0.0;             // [m]
  double w_max_ = 0.0;                  // [rad/s]
  std::vector<double> path_length_;     // [m] per path
  int cells_ = 0;                       // cells per side of the grid
  std::vector<std::uint32_t> cell_begin_;  // cells_^2 + 1 offsets into entries_
  std::vector<CellEntry> entries_;
};

}  // namespace barn::controllers
