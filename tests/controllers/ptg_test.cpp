#include "barn/controllers/ptg.hpp"

#include <cmath>
#include <limits>
#include <numbers>
#include <vector>

#include <gtest/gtest.h>

namespace barn::controllers {
namespace {

constexpr double kPi = std::numbers::pi;
constexpr double kInf = std::numeric_limits<double>::infinity();

// A PTG with round numbers: 4 paths (alpha = -3pi/4, -pi/4, pi/4, 3pi/4), every path at 1 m/s,
// w_max 4 rad/s so that path 2 (alpha = pi/4) turns at 1 rad/s on a circle of radius 1, and no
// turning term in the distance (pseudo-metres = metres). A small grid keeps the test quick.
PtgConfig roundPtg() {
  PtgConfig c;
  c.num_paths = 4;
  c.ref_distance = 2.0;
  c.resolution = 0.1;
  c.v_max = 1.0;
  c.v_falloff = 0.0;
  c.w_max_deg = 4.0 * 180.0 / kPi;
  c.turning_radius_reference = 0.0;
  return c;
}

// The BARN Jackal PTG, built once for the whole file (its grid takes a while).
const ArcPtg& jackalPtg() {
  static const ArcPtg ptg{PtgConfig{}};
  return ptg;
}

TEST(PtgIndex, MapsPathsToDirectionsAndBack) {
  // alpha_k = pi (-1 + (2k + 1) / n): n = 151, k = 75 is straight ahead, k = 150 is pi 150 / 151.
  EXPECT_DOUBLE_EQ(pathAlpha(75, 151), 0.0);
  EXPECT_NEAR(pathAlpha(150, 151), kPi * 150.0 / 151.0, 1e-12);
  EXPECT_EQ(alphaIndex(0.0, 151), 75);
  EXPECT_EQ(alphaIndex(pathAlpha(17, 151), 151), 17);
  // alpha = pi: round((151 * 2 - 1) / 2) = 151, clamped to the last path; -pi wraps to +pi too.
  EXPECT_EQ(alphaIndex(kPi, 151), 150);
  EXPECT_EQ(alphaIndex(-kPi, 151), 150);
  EXPECT_EQ(alphaIndex(-kPi + 1e-9, 151), 0);
}

TEST(Ptg, DrivesTheJackalFilesSpeedsOnEachPath) {
  const ArcPtg& ptg = jackalPtg();
  // Straight: v = 1.2, w = 0.
  EXPECT_DOUBLE_EQ(ptg.linearSpeed(75), 1.2);
  EXPECT_DOUBLE_EQ(ptg.angularSpeed(75), 0.0);
  // Path 150: alpha = 3.120787; v = 1.2 (1 - 3.120787 / 3.2) = 0.029705; w = (150 / 151) 60 deg/s = 1.040262.
  EXPECT_NEAR(ptg.linearSpeed(150), 0.029705, 1e-6);
  EXPECT_NEAR(ptg.angularSpeed(150), 1.040262, 1e-6);
  // Its loop ends the path: 1.95 pi / 1.040262 sqrt(0.029705^2 + (1.040262 x 0.1)^2) = 0.637097 m.
  EXPECT_NEAR(ptg.pathLength(150), 0.637097, 1e-6);
  EXPECT_DOUBLE_EQ(ptg.pathLength(75), 3.0);
  EXPECT_DOUBLE_EQ(ptg.pathLength(100), 3.0);  // R = 2.34 m: 3 m is far short of a loop
}

TEST(Ptg, PlacesTheRobotOnTheArcOfItsPath) {
  const ArcPtg round(roundPtg());
  // Path 2: v = 1, w = 1, R = 1; a quarter circle, pi / 2 m, ends at (1, 1) heading pi / 2.
  const core::Pose2 quarter = round.poseAt(2, kPi / 2);
  EXPECT_NEAR(quarter.x, 1.0, 1e-12);
  EXPECT_NEAR(quarter.y, 1.0, 1e-12);
  EXPECT_NEAR(quarter.yaw, kPi / 2, 1e-12);
  // Path 1 mirrors it: (1, -1) heading -pi / 2.
  const core::Pose2 right = round.poseAt(1, kPi / 2);
  EXPECT_NEAR(right.x, 1.0, 1e-12);
  EXPECT_NEAR(right.y, -1.0, 1e-12);
  EXPECT_NEAR(right.yaw, -kPi / 2, 1e-12);

  const ArcPtg& jackal = jackalPtg();
  // Path 100: v = 0.809902, w = 0.346754, R = 2.335665; 1.5 pseudo-metres take
  // t = 1.5 / sqrt(v^2 + (0.1 w)^2) = 1.5 / 0.810644 = 1.850376 s, a turn of 0.641628 rad:
  // (R sin 0.641628, R (1 - cos 0.641628)) = (1.397896, 0.464511).
  const core::Pose2 p = jackal.poseAt(100, 1.5);
  EXPECT_NEAR(p.x, 1.397896, 1e-6);
  EXPECT_NEAR(p.y, 0.464511, 1e-6);
  EXPECT_NEAR(p.yaw, 0.641628, 1e-6);
  // Straight: 2 m ahead.
  const core::Pose2 s = jackal.poseAt(75, 2.0);
  EXPECT_DOUBLE_EQ(s.x, 2.0);
  EXPECT_DOUBLE_EQ(s.y, 0.0);
}

TEST(Ptg, MapsAPointBackToItsPathAndDistance) {
  const ArcPtg& jackal = jackalPtg();
  // A point on path 100, 1.5 m along, maps back to (100, 1.5).
  const core::Pose2 p = jackal.poseAt(100, 1.5);
  const TpPoint on_path = jackal.inverseMap({p.x, p.y});
  EXPECT_TRUE(on_path.exact);
  EXPECT_EQ(on_path.k, 100);
  EXPECT_NEAR(on_path.distance, 1.5, 1e-9);
  // (1, 1): the circle R = (1 + 1) / 2 = 1, a quarter turn. The path of radius 1:
  // |alpha| = 1.2 / (1 x 1.047198 / pi + 1.2 / 3.2) = 1.694118, index round(115.71) = 116;
  // distance (pi / 2) sqrt(1 + 0.1^2) = 1.578631.
  const TpPoint diagonal = jackal.inverseMap({1.0, 1.0});
  EXPECT_TRUE(diagonal.exact);
  EXPECT_EQ(diagonal.k, 116);
  EXPECT_NEAR(diagonal.distance, 1.578631, 1e-6);
  // Mirrored to the right: path 150 - 116 = 34.
  EXPECT_EQ(jackal.inverseMap({1.0, -1.0}).k, 34);
  // Straight ahead: the middle path, the distance itself.
  const TpPoint ahead = jackal.inverseMap({2.5, 0.0});
  EXPECT_EQ(ahead.k, 75);
  EXPECT_DOUBLE_EQ(ahead.distance, 2.5);
  // Straight behind: no forward path gets there.
  EXPECT_FALSE(jackal.inverseMap({-1.0, 0.0}).exact);
  // Inside the tightest circle (R = 1.2 (1 - pi / 3.2) / 1.047198 = 0.020915): not exact.
  EXPECT_FALSE(jackal.inverseMap({0.0, 0.02}).exact);
  EXPECT_TRUE(jackal.inverseMap({0.0, 0.05}).exact);
}

TEST(PtgCollision, APointAheadIsHitAtItsDistanceLessTheHalfLength) {
  const ArcPtg& jackal = jackalPtg();
  // The polygon's front edge is at x = 0.30: a point 1.0 m ahead (0.1 m left) is met after 0.70 m.
  EXPECT_NEAR(jackal.collisionDistance(75, {1.0, 0.1}), 0.70, 1e-12);
  // Beside the polygon's width (|y| > 0.27) the straight path never meets it.
  EXPECT_EQ(jackal.collisionDistance(75, {1.0, 0.3}), kInf);
  // Beyond the path's 3 m: 3.5 - 0.3 = 3.2 > 3.
  EXPECT_EQ(jackal.collisionDistance(75, {3.5, 0.0}), kInf);
  // Inside the polygon: 0.
  EXPECT_EQ(jackal.collisionDistance(75, {0.1, 0.1}), 0.0);
  EXPECT_TRUE(jackal.insideShape({0.1, 0.1}));
  EXPECT_FALSE(jackal.insideShape({0.35, 0.1}));
}

TEST(PtgCollision, AgreesWithTheRobotPolygonPlacedAlongThePath) {
  // The exact distance against a walk along the path in 1 mm steps: the first pose whose polygon
  // holds the point (the point in that pose's frame inside the shape) is at most 1 mm later.
  const ArcPtg& jackal = jackalPtg();
  const std::vector<Eigen::Vector2d> points{{1.2, 0.4}, {0.6, -0.5}, {0.0, 0.45}, {-0.2, 0.42}, {2.0, 1.3}};
  for (int k : {0, 20, 60, 75, 90, 130, 150})
    for (const Eigen::Vector2d& point : points) {
      double walked = kInf;
      for (double d = 0.0; d <= jackal.pathLength(k); d += 0.001)
        if (jackal.insideShape(jackal.poseAt(k, d).inverseTransform(point))) {
          walked = d;
          break;
        }
      const double exact = jackal.collisionDistance(k, point);
      if (walked == kInf) {
        EXPECT_TRUE(exact == kInf || exact > jackal.pathLength(k) - 0.001) << "k " << k << " " << point.transpose();
      } else {
        EXPECT_LE(exact, walked + 1e-9) << "k " << k << " " << point.transpose();
        EXPECT_GT(exact, walked - 0.001 - 1e-9) << "k " << k << " " << point.transpose();
      }
    }
}

TEST(PtgObstacles, APointAheadBlocksTheStraightPathAtItsCollisionDistance) {
  const ArcPtg& jackal = jackalPtg();
  // The cell holding (1.025, 0.125) has corners x = 1.00 and 1.05, y = 0.10 and 0.15: on the
  // straight path the nearest corner is met after 1.00 - 0.30 = 0.70 m; normalised 0.70 / 3.
  std::vector<double> tp;
  const std::vector<Eigen::Vector2d> ahead{{1.025, 0.125}};
  jackal.tpObstacles(ahead, tp);
  ASSERT_EQ(tp.size(), 151u);
  EXPECT_NEAR(tp[75], 0.70 / 3.0, 1e-6);
  // A path bending away to the right (path 50, R = -2.34 m) misses it: free to its end (3 m,
  // normalised 1).
  EXPECT_DOUBLE_EQ(tp[50], 1.0);
  // Nothing seen: every path free to its end, the looping hard turns shorter (0.637097 / 3).
  const std::vector<Eigen::Vector2d> none;
  jackal.tpObstacles(none, tp);
  EXPECT_DOUBLE_EQ(tp[75], 1.0);
  EXPECT_NEAR(tp[150], 0.637097 / 3.0, 1e-6);
}

TEST(PtgObstacles, IgnoresAPointAlreadyInsideTheRobot) {
  // MRPT's COLL_BEH_BACK_AWAY: a point inside the polygon blocks nothing.
  const ArcPtg& jackal = jackalPtg();
  std::vector<double> tp;
  const std::vector<Eigen::Vector2d> inside{{0.2, 0.0}};
  jackal.tpObstacles(inside, tp);
  EXPECT_DOUBLE_EQ(tp[75], 1.0);
  EXPECT_DOUBLE_EQ(tp[100], 1.0);
}

TEST(PtgConfig, RejectsAShapeWithoutMatchingCoordinates) {
  PtgConfig c;
  c.shape_y.pop_back();
  c.v_falloff = 0.5;  // 0.5 pi > 1: the hard turns would drive backwards
  core::Errors errors;
  validate(c, errors, "ptg");
  ASSERT_EQ(errors.messages().size(), 2u);
  EXPECT_NE(errors.messages()[0].find("ptg.v_falloff"), std::string::npos);
  EXPECT_NE(errors.messages()[1].find("ptg.shape_y"), std::string::npos);
}

}  // namespace
}  // namespace barn::controllers
