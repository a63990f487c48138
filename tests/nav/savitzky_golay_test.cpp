// Savitzky-Golay smoothing as scipy.signal.savgol_filter(x, 19, 3) computes it (mode interp).
// The exact fractions are the least-squares projection ("hat") matrix of a cubic over 19 points,
// H = A (A^T A)^-1 A^T, computed in rational arithmetic (sympy); the interior row is the classic
// closed form c_j = 3 (3m^2 + 3m - 1 - 5 j^2) / ((4m^2 - 1)(2m + 3)) with m = 9.
#include "barn/nav/savitzky_golay.hpp"

#include <stdexcept>
#include <vector>

#include <gtest/gtest.h>

namespace barn::nav {
namespace {

std::vector<double> spike(int n, int at) {
  std::vector<double> x(static_cast<std::size_t>(n), 0.0);
  x[static_cast<std::size_t>(at)] = 1.0;
  return x;
}

TEST(SavitzkyGolay, InteriorPointsAreTheClassicCubicWeights) {
  const SavitzkyGolay sg(19, 3);
  // m = 9: (4 81 - 1)(21) = 6783; c_0 = 3 (243 + 27 - 1) / 6783 = 807 / 6783,
  // c_9 = 3 (269 - 405) / 6783 = -408 / 6783.
  const std::vector<double> out = sg.smooth(spike(31, 12));
  EXPECT_NEAR(out[12], 807.0 / 6783.0, 1e-14);
  EXPECT_NEAR(out[21], -408.0 / 6783.0, 1e-14);  // point 21 sees the spike 9 points before it
  // Point 22 is past the last interior point (31 - 9 = 22): the cubic through points 12 ... 30
  // at t = 10, the spike at t = 0: H(10, 0) = -4/133.
  EXPECT_NEAR(out[22], -4.0 / 133.0, 1e-14);
  // Point 3 is an edge point: the cubic through points 0 ... 18 at t = 3, H(3, 12) = -373/10659.
  EXPECT_NEAR(out[3], -373.0 / 10659.0, 1e-14);
}

TEST(SavitzkyGolay, EdgePointsComeFromOneCubicFitThroughTheFirstOrLastWindow) {
  const SavitzkyGolay sg(19, 3);
  // A spike at the first point: the cubic fitted to points 0 ... 18 takes 851/1463 at t = 0,
  // 544/1463 at t = 1 and 16/77 at t = 2 (rows 0-2, column 0 of H).
  const std::vector<double> first = sg.smooth(spike(25, 0));
  EXPECT_NEAR(first[0], 851.0 / 1463.0, 1e-14);
  EXPECT_NEAR(first[1], 544.0 / 1463.0, 1e-14);
  EXPECT_NEAR(first[2], 16.0 / 77.0, 1e-14);
  // Point 9 is the first interior one: its window is 0 ... 18 too, centred, weight -408/6783.
  EXPECT_NEAR(first[9], -408.0 / 6783.0, 1e-14);
  // A spike at the last of 25 points: by symmetry the last point takes 851/1463; the last window
  // is points 6 ... 24, so point 16 (t = 10) takes H(10, 18) = -11/133, point 15 (the last
  // interior one, centred on 15) -408/6783, and point 6, an edge point of the first window, 0.
  const std::vector<double> last = sg.smooth(spike(25, 24));
  EXPECT_NEAR(last[24], 851.0 / 1463.0, 1e-14);
  EXPECT_NEAR(last[16], -11.0 / 133.0, 1e-14);
  EXPECT_NEAR(last[15], -408.0 / 6783.0, 1e-14);
  EXPECT_EQ(last[6], 0.0);
}

TEST(SavitzkyGolay, ACubicIsReproducedEverywhereEdgesIncluded) {
  const SavitzkyGolay sg(19, 3);
  std::vector<double> x;
  for (int i = 0; i < 40; ++i) x.push_back(0.001 * i * i * i - 0.02 * i * i + 0.3 * i + 1.0);
  const std::vector<double> out = sg.smooth(x);
  for (std::size_t i = 0; i < x.size(); ++i) EXPECT_NEAR(out[i], x[i], 1e-10) << i;
}

TEST(SavitzkyGolay, AnAlternatingWiggleIsDampedNotRemoved) {
  // (-1)^i through the interior weights: sum_j c_j (-1)^j = 181/2261 = 0.0800531 (the cubic
  // passes some of it).
  const SavitzkyGolay sg(19, 3);
  std::vector<double> x;
  for (int i = 0; i < 41; ++i) x.push_back(i % 2 == 0 ? 1.0 : -1.0);
  const std::vector<double> out = sg.smooth(x);
  EXPECT_NEAR(out[20], 181.0 / 2261.0, 1e-14);
  EXPECT_NEAR(out[21], -181.0 / 2261.0, 1e-14);
  // The first point: sum_j H(0, j) (-1)^j = 37/133.
  EXPECT_NEAR(out[0], 37.0 / 133.0, 1e-14);
}

TEST(SavitzkyGolay, APathShorterThanTheWindowIsReturnedRaw) {
  // scipy raises ValueError for mode interp when the window is longer than the data; LiCS-KI's node
  // catches it and keeps the raw plan.
  const SavitzkyGolay sg(19, 3);
  const std::vector<Eigen::Vector2d> path(18, Eigen::Vector2d(1.0, 2.0));
  EXPECT_EQ(sg.smoothPath(path), path);
  EXPECT_THROW(sg.smooth(std::vector<double>(18, 0.0)), std::invalid_argument);
}

TEST(SavitzkyGolay, SmoothsTheTwoCoordinatesApart) {
  const SavitzkyGolay sg(19, 3);
  std::vector<Eigen::Vector2d> path;
  for (int i = 0; i < 31; ++i) path.emplace_back(0.1 * i, i == 12 ? 1.0 : 0.0);
  const std::vector<Eigen::Vector2d> out = sg.smoothPath(path);
  EXPECT_NEAR(out[12].x(), 1.2, 1e-12);              // a line stays where it is
  EXPECT_NEAR(out[12].y(), 807.0 / 6783.0, 1e-14);   // the spike in y, as above
}

TEST(SavitzkyGolay, RefusesAnEvenWindowOrTooHighAnOrder) {
  EXPECT_THROW(SavitzkyGolay(18, 3), std::invalid_argument);
  EXPECT_THROW(SavitzkyGolay(5, 5), std::invalid_argument);
  EXPECT_THROW(SavitzkyGolay(5, -1), std::invalid_argument);
  EXPECT_NO_THROW(SavitzkyGolay(1, 0));
}

}  // namespace
}  // namespace barn::nav
