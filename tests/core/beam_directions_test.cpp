#include "barn/core/beam_directions.hpp"

#include <cmath>
#include <numbers>

#include <gtest/gtest.h>

namespace barn::core {
namespace {

LaserScan layout(double angle_min, double increment, std::size_t beams) {
  LaserScan scan;
  scan.angle_min = angle_min;
  scan.angle_increment = increment;
  scan.ranges.assign(beams, 1.0);
  return scan;
}

TEST(BeamDirections, AreTheCosineAndSineOfEachBeamsAngle) {
  BeamDirections beams;
  const LaserScan scan = layout(-3 * std::numbers::pi / 4, std::numbers::pi / 4, 7);
  beams.update(scan);
  for (std::size_t i = 0; i < 7; ++i) {
    EXPECT_EQ(beams.cos(i), std::cos(scan.angle(i))) << i;
    EXPECT_EQ(beams.sin(i), std::sin(scan.angle(i))) << i;
  }
  EXPECT_NEAR(beams.cos(1), 0.0, 1e-15);  // beam 1 looks straight right (-pi/2)
  EXPECT_NEAR(beams.sin(1), -1.0, 1e-15);
  EXPECT_NEAR(beams.cos(3), 1.0, 1e-15);  // beam 3 straight ahead
}

TEST(BeamDirections, FollowTheLayoutWhenItChanges) {
  // The same table for scans of another first angle, increment or beam count must not keep
  // the old directions.
  BeamDirections beams;
  beams.update(layout(0.0, 0.1, 4));
  const LaserScan shifted = layout(0.5, 0.1, 4);
  beams.update(shifted);
  EXPECT_EQ(beams.cos(2), std::cos(shifted.angle(2)));
  const LaserScan finer = layout(0.5, 0.05, 4);
  beams.update(finer);
  EXPECT_EQ(beams.sin(3), std::sin(finer.angle(3)));
  const LaserScan longer = layout(0.5, 0.05, 9);
  beams.update(longer);
  EXPECT_EQ(beams.sin(8), std::sin(longer.angle(8)));
}

}  // namespace
}  // namespace barn::core
