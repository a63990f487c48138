#pragma once
/// The corridor of the MECO Barners' 2023 BARN entry (`meco`): a rectangle of free space with a
/// direction of travel, and the geometry the fitter, the manager and the motion planner share.
///
/// The team keeps a corridor as four half-planes (the columns of a 3 x 4 matrix W, one per
/// edge: front, right, back, left) and grows it by moving one edge's line outward. Here it is
/// kept as its centre, its heading and its two extents, which is the same rectangle: moving an
/// edge by d moves the centre by d / 2 along that edge's normal and adds d to the extent.
///
/// Frames. The fitter builds corridors in the robot frame (x forward, y left) and hands them
/// on in the odom frame; the manager and the navigator work in the odom frame only. Headings
/// are measured from the frame's x axis, counter-clockwise. (The team's world corridors measure
/// their tilt from +y, their local ones from +x; a heading here is their world tilt + pi / 2.)
///
/// Source: meco-group/Barn_challenge@66cef2c, corridors/scripts/corridor.py,
/// corridor_world.py, corridor_helpers.py (MIT; facts restated, no code copied).

#include <array>
#include <span>
#include <string_view>

#include <Eigen/Core>

#include "barn/core/types.hpp"

namespace barn::controllers {

/// The four edges in the team's order (the columns of their W).
enum class MecoEdge { Front, Right, Back, Left };
std::span<const std::string_view> enumNames(MecoEdge);

struct MecoCorridor {
  Eigen::Vector2d center = Eigen::Vector2d::Zero();         // [m]
  double heading = 0.0;                                     // [rad] direction of travel, from the frame's x axis
  double length = 0.0;                                      // [m] along the heading (the team's "height")
  double width = 0.0;                                       // [m] across it
  Eigen::Vector2d growth_center = Eigen::Vector2d::Zero();  // [m] where the robot stood when it was fitted

  /// Unit vector along the heading (the front edge's outward normal).
  Eigen::Vector2d axis() const;
  /// Unit vector to the left of the heading (the left edge's outward normal).
  Eigen::Vector2d left() const;
  /// The outward unit normal of `edge`.
  Eigen::Vector2d normal(MecoEdge edge) const;
  /// Distance from the centre to `edge`'s line [m].
  double halfExtent(MecoEdge edge) const;

  /// Whether `p` lies inside or on the boundary, each edge moved out by `tolerance` (the team's
  /// check_inside: every half-plane <= 0; check_inside_one_point: <= 1e-3).
  bool contains(const Eigen::Vector2d& p, double tolerance = 0.0) const;
  /// Front right, back right, back left, front left: the team's corner order (the intersections
  /// of the edges front-right, right-back, back-left, left-front).
  std::array<Eigen::Vector2d, 4> corners() const;
  /// The largest y of the four corners [m]: in the odom frame, the team's measure of progress
  /// (BARN's goal lies along +y).
  double maxCornerY() const;
  /// The middle of the front edge moved `margin` back toward the centre (compute_goal_point).
  Eigen::Vector2d frontPoint(double margin) const;
  /// The middle of the back edge moved `margin` forward toward the centre (compute_initial_point).
  Eigen::Vector2d backPoint(double margin) const;

  /// Moves `edge` outward by `distance` (inward if negative).
  void moveEdge(MecoEdge edge, double distance);
  /// The same rectangle with the heading turned a quarter: clockwise (the old right edge becomes
  /// the front) or counter-clockwise (the old left edge becomes the front). Length and width swap.
  void turnQuarter(bool clockwise);
  /// The same rectangle facing the other way (the team's corridor rotated by pi for backtracking).
  MecoCorridor reversed() const;
  /// This corridor, given in the frame of `pose`, expressed in the pose's parent frame.
  MecoCorridor toParent(const core::Pose2& pose) const;
};

/// Where two lines meet: `a` + s `da` = `b` + t `db`; false if they are parallel.
bool intersectLines(const Eigen::Vector2d& a, const Eigen::Vector2d& da, const Eigen::Vector2d& b,
                    const Eigen::Vector2d& db, Eigen::Vector2d& point);

/// A point on `edge`'s line and the line's direction.
void edgeLine(const MecoCorridor& corridor, MecoEdge edge, Eigen::Vector2d& point, Eigen::Vector2d& direction);

}  // namespace barn::controllers
