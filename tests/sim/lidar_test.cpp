#include "barn/sim/lidar.hpp"

#include <cmath>
#include <limits>

#include <gtest/gtest.h>

#include "barn/core/world_file.hpp"
#include "barn/core/world_geometry.hpp"
#include "barn/sim/simulator.hpp"

namespace barn::sim {
namespace {

constexpr double kInf = std::numeric_limits<double>::infinity();

// The textbook ray-circle distance, written independently of the caster: the ray from the
// origin at angle a meets the circle (centre d, radius r) at t = d.u - sqrt(r^2 - |d x u|^2).
double analyticRange(double angle, const Eigen::Vector2d& d, double r) {
  const Eigen::Vector2d u(std::cos(angle), std::sin(angle));
  const double along = d.dot(u);
  const double across = d.x() * u.y() - d.y() * u.x();
  if (across * across > r * r || along <= 0.0) return kInf;
  return along - std::sqrt(r * r - across * across);
}

// Brute force over every circle: the nearest analytic hit.
double bruteForceRange(double angle, const core::Pose2& sensor, const ObstacleField& field) {
  double best = kInf;
  for (std::size_t i = 0; i < field.centres.size(); ++i) {
    const Eigen::Vector2d d = sensor.inverseTransform(field.centres[i]);
    best = std::min(best, analyticRange(angle, d, field.radiusOf(i)));
  }
  return best;
}

TEST(Lidar, RayAgainstOneCircleGivesTheAnalyticDistance) {
  ObstacleField field;
  field.centres = {{2.0, 0.5}};
  core::LidarConfig config;
  config.noise_stddev = 0.0;
  LidarCaster caster(config, field);
  std::vector<double> ranges;
  caster.cast({0.0, 0.0, 0.0}, ranges);
  ASSERT_EQ(ranges.size(), 720u);
  int hits = 0;
  for (int i = 0; i < 720; ++i) {
    const double angle = config.angle_min + i * config.angleIncrement();
    const double expected = analyticRange(angle, {2.0, 0.5}, 0.075);
    if (std::isinf(expected)) {
      EXPECT_TRUE(std::isinf(ranges[static_cast<std::size_t>(i)])) << "beam " << i;
    } else {
      ++hits;
      EXPECT_NEAR(ranges[static_cast<std::size_t>(i)], expected, 1e-12) << "beam " << i;
    }
  }
  // The circle subtends 2 asin(0.075 / 2.0616) = 0.0728 rad = 11.1 beams of 0.006554 rad.
  EXPECT_GE(hits, 11);
  EXPECT_LE(hits, 12);
}

TEST(Lidar, HeadOnBeamHitsTheNearSurface) {
  // A beam straight at a circle centred 3 m away stops at 3 - 0.075 m. Beam 0 is at angle_min,
  // so a sensor yawed by -angle_min points beam 0 along +x.
  ObstacleField field;
  field.centres = {{3.0, 0.0}};
  core::LidarConfig config;
  LidarCaster caster(config, field);
  std::vector<double> ranges;
  caster.cast({0.0, 0.0, -config.angle_min}, ranges);
  EXPECT_NEAR(ranges[0], 2.925, 1e-12);
}

TEST(Lidar, ContainmentWallMatchesBruteForce) {
  // The back wall and side walls of BARN seen from the start pose, against brute force.
  ObstacleField field;
  field.centres = core::containmentCylinders();
  core::LidarConfig config;
  LidarCaster caster(config, field);
  const core::Pose2 sensor{-2.0, 1.0, 3.0};  // facing the back wall at y = 0.075
  std::vector<double> ranges;
  caster.cast(sensor, ranges);
  int finite = 0;
  for (int i = 0; i < 720; ++i) {
    const double angle = config.angle_min + i * config.angleIncrement();
    const double expected = bruteForceRange(angle, sensor, field);
    if (std::isinf(expected)) {
      EXPECT_TRUE(std::isinf(ranges[static_cast<std::size_t>(i)])) << "beam " << i;
    } else {
      ++finite;
      EXPECT_NEAR(ranges[static_cast<std::size_t>(i)], expected, 1e-9) << "beam " << i;
    }
  }
  EXPECT_GT(finite, 500);  // the walls surround the sensor on three sides
}

TEST(Lidar, CirclesWithTheirOwnRadiiMatchBruteForce) {
  // Hallucinated LfLH obstacles: circles of 0.05-0.6 m, overlapping, one of them large and
  // close enough to hide others, around a sensor that is not at the origin.
  ObstacleField field;
  field.centres = {{1.0, 0.2}, {1.3, 0.5}, {2.5, 0.0}, {0.3, -1.2}, {-1.5, 1.0}, {0.5, 2.0}, {-0.4, -0.6}};
  field.radii = {0.3, 0.05, 0.6, 0.2, 0.45, 0.1, 0.15};
  core::LidarConfig config;
  LidarCaster caster(config, field);
  const core::Pose2 sensor{0.1, -0.1, 0.4};
  std::vector<double> ranges;
  caster.cast(sensor, ranges);
  int finite = 0;
  for (int i = 0; i < 720; ++i) {
    const double angle = config.angle_min + i * config.angleIncrement();
    const double expected = bruteForceRange(angle, sensor, field);
    if (std::isinf(expected)) {
      EXPECT_TRUE(std::isinf(ranges[static_cast<std::size_t>(i)])) << "beam " << i;
    } else {
      ++finite;
      EXPECT_NEAR(ranges[static_cast<std::size_t>(i)], expected, 1e-12) << "beam " << i;
    }
  }
  EXPECT_GT(finite, 200);
}

TEST(Lidar, SeesNothingInTheBlindWedgeButCatchesCirclesStraddlingItsEdge) {
  core::LidarConfig config;
  std::vector<double> ranges;
  // Directly behind: invisible.
  ObstacleField behind;
  behind.centres = {{-1.0, 0.0}};
  LidarCaster blind(config, behind);
  blind.cast({0.0, 0.0, 0.0}, ranges);
  for (double r : ranges) EXPECT_TRUE(std::isinf(r));
  // Bearing 137 degrees at 1 m: the circle spans 137 +- 4.3 degrees, so the last beams
  // (up to 135 degrees) see its near part.
  ObstacleField edge;
  edge.centres = {{std::cos(137.0 * M_PI / 180.0), std::sin(137.0 * M_PI / 180.0)}};
  LidarCaster straddle(config, edge);
  straddle.cast({0.0, 0.0, 0.0}, ranges);
  EXPECT_TRUE(std::isfinite(ranges.back()));
  EXPECT_NEAR(ranges.back(), bruteForceRange(config.angle_max, {0, 0, 0}, edge), 1e-12);
}

TEST(Lidar, ReportsInfinityBeyondMaxRangeAndClampsBelowMinRange) {
  ObstacleField field;
  field.centres = {{40.0, 0.0}};
  core::LidarConfig config;
  LidarCaster far(config, field);
  std::vector<double> ranges;
  far.cast({0.0, 0.0, -config.angle_min}, ranges);
  EXPECT_TRUE(std::isinf(ranges[0]));  // 39.925 m > 30 m
  field.centres = {{0.12, 0.0}};       // surface 0.045 m away, below range_min 0.1
  LidarCaster near(config, field);
  near.cast({0.0, 0.0, -config.angle_min}, ranges);
  EXPECT_EQ(ranges[0], 0.1);
}

TEST(Lidar, NoiseIsSeededAndHasTheConfiguredSpread) {
  const core::WorldSpec world = core::readWorldFile("worlds/world_000.yaml");
  const ObstacleField field = ObstacleField::fromWorld(world);
  core::LidarConfig config;  // noise_stddev 0.001
  LidarCaster caster(config, field);
  const core::Pose2 robot{-2.0, 3.0, 1.57};
  core::FastNoise a(7), b(7), c(8);
  const auto scan_a = caster.scan(robot, 0.0, &a);
  const auto scan_b = caster.scan(robot, 0.0, &b);
  const auto scan_c = caster.scan(robot, 0.0, &c);
  const auto exact = caster.scan(robot, 0.0, nullptr);
  EXPECT_EQ(scan_a.ranges, scan_b.ranges);
  EXPECT_NE(scan_a.ranges, scan_c.ranges);
  double sum_sq = 0.0;
  int n = 0;
  for (std::size_t i = 0; i < exact.ranges.size(); ++i) {
    if (!std::isfinite(exact.ranges[i])) {
      EXPECT_TRUE(std::isinf(scan_a.ranges[i]));  // noise never turns a miss into a hit
      continue;
    }
    const double e = scan_a.ranges[i] - exact.ranges[i];
    sum_sq += e * e;
    ++n;
  }
  ASSERT_GT(n, 300);
  // sample std of n >= 300 normals with sigma 1 mm: relative error ~ 1 / sqrt(2n) < 4.1%;
  // allow 20%.
  EXPECT_NEAR(std::sqrt(sum_sq / n), 0.001, 0.0002);
}

// The fast caster against Box2D's RayCast on thousands of rays in real worlds. Box2D computes
// in float32, whose rounding moves its ranges by up to ~1e-4 m at 10 m (measured: 2.5e-4 m
// at 10 m in world 0). So the comparison has two parts: both casters must see the same
// cylinder on every beam, and the exact (double) distance to the cylinder Box2D saw must
// equal the fast caster's range to 1e-5 m. Box2D's own ranges must agree to float precision.
TEST(Lidar, AgreesWithBox2DRayCastInRealWorlds) {
  core::LidarConfig config;
  int compared = 0;
  int grazing = 0;
  double worst_exact = 0.0;
  double worst_float = 0.0;
  for (const char* name : {"worlds/world_000.yaml", "worlds/world_100.yaml", "worlds/world_200.yaml",
                           "worlds/world_299.yaml"}) {
    const core::WorldSpec world = core::readWorldFile(name);
    const ObstacleField field = ObstacleField::fromWorld(world);
    const Simulator reference(field, core::RobotConfig{}, PhysicsConfig{}, {-2.0, 3.0, 1.57});
    LidarCaster caster(config, field);
    core::Rng rng(42);
    int poses = 0;
    while (poses < 10) {
      // A sensor pose in free space: anywhere from the start area to beyond the field.
      const core::Pose2 sensor{-4.2 + 4.0 * rng.uniform01(), 1.0 + 10.0 * rng.uniform01(),
                               -M_PI + 2.0 * M_PI * rng.uniform01()};
      bool free = true;
      for (const auto& c : field.centres) free = free && (c - sensor.position()).norm() > 0.2;
      if (!free) continue;
      ++poses;
      std::vector<double> fast;
      caster.cast(sensor, fast);
      const Simulator::ReferenceScan box2d = reference.referenceScan(config, sensor);
      for (std::size_t i = 0; i < fast.size(); ++i) {
        ++compared;
        const double angle = config.angle_min + static_cast<double>(i) * config.angleIncrement();
        const int hit = box2d.hit[i];
        const double exact = hit < 0 ? kInf
                                     : analyticRange(angle, sensor.inverseTransform(field.centres[static_cast<std::size_t>(hit)]),
                                                     field.radius);
        if (std::isinf(fast[i]) && hit < 0) continue;
        if (std::abs(exact - fast[i]) > 1e-5) {
          // Different obstacles seen: acceptable only for a ray grazing a circle, where float32
          // and float64 may disagree on hit or miss (|d x u| within 1e-5 m of r).
          bool near_tangent = false;
          for (const auto& c : field.centres) {
            const Eigen::Vector2d d = sensor.inverseTransform(c);
            const double across = d.x() * std::sin(angle) - d.y() * std::cos(angle);
            near_tangent = near_tangent || (d.x() * std::cos(angle) + d.y() * std::sin(angle) > 0 &&
                                            std::abs(std::abs(across) - field.radius) < 1e-5);
          }
          EXPECT_TRUE(near_tangent) << name << " beam " << i << ": fast " << fast[i] << ", box2d " << box2d.ranges[i];
          ++grazing;
          continue;
        }
        if (hit < 0) continue;
        worst_exact = std::max(worst_exact, std::abs(exact - fast[i]));
        worst_float = std::max(worst_float, std::abs(box2d.ranges[i] - fast[i]) / std::max(1.0, fast[i]));
      }
    }
  }
  EXPECT_EQ(compared, 4 * 10 * 720);
  EXPECT_LE(grazing, 5);
  EXPECT_LT(worst_exact, 1e-5) << "largest difference to the exact range " << worst_exact << " m";
  // float32 relative precision 6e-8; Box2D's ray-circle formula (a difference of squares of a
  // 30 m ray) loses about three digits: measured 1.3e-4 relative on these rays.
  EXPECT_LT(worst_float, 3e-4) << "largest relative difference to Box2D's float range " << worst_float;
}

}  // namespace
}  // namespace barn::sim
