#include "barn/learning/hallucination.hpp"
#include "barn/learning/policy.hpp"

#include <cmath>
#include <limits>

#include <gtest/gtest.h>

namespace barn::learning {
namespace {

constexpr double kInf = std::numeric_limits<double>::infinity();

// 30 s of exploration at 2 m/s: fast turns and straights, the hardest case for the sweep.
const Recording& recording() {
  static const Recording r = [] {
    CollectConfig c;
    c.duration = 30.0;
    c.min_speed = 0.0;
    c.max_speed = 2.0;
    c.max_turn_rate = 1.4;
    return collectExploration(c, "test");
  }();
  return r;
}

TEST(Hallucination, ObstaclesNeverTouchTheSweptFootprintAndTheNearestHugsIt) {
  const HallucinationConfig config;
  const core::RobotConfig robot;
  int demos = 0;
  for (std::size_t record = 0; record < 1200; record += 37) {
    const auto demo = hallucinate(recording(), record, 0, config);
    if (!demo) continue;
    ++demos;
    ASSERT_GT(demo->hugging, 0u);
    // The reference: the recorded motion swept at 1 mm, far finer than the 20 mm the
    // hallucination uses; its bulge allowance (0.5 mm) is below every tolerance here.
    const SweptFootprint fine(demo->motion, core::Rect::centred(robot.footprint_length, robot.footprint_width), 0.001);
    double nearest = kInf;
    for (std::size_t k = 0; k < demo->obstacles.size(); ++k) {
      const double gap = fine.gap(demo->obstacles[k]);
      // Hugging obstacles keep their own clearance (>= 0.03 m); distractors at least clearance_min.
      const double required = k < demo->hugging ? demo->clearances[k] : config.clearance_min;
      EXPECT_GE(gap, required - 0.0005) << "record " << record << " obstacle " << k;
      nearest = std::min(nearest, gap);
      if (k < demo->hugging) {
        // Pushed to exactly clearance + sweep_step / 2 from the 20 mm sweep, which lies inside
        // the fine one: at most 0.01 m farther from the fine sweep than asked.
        EXPECT_LE(gap, demo->clearances[k] + 0.5 * config.sweep_step + 1e-6) << "record " << record << " obstacle " << k;
      }
    }
    // The most constrained configuration: something within clearance_max + 0.01 m of the sweep.
    EXPECT_LE(nearest, config.clearance_max + 0.5 * config.sweep_step + 1e-6) << "record " << record;
  }
  EXPECT_GT(demos, 25);
}

// Blocking obstacles are pushed forward instead of sideways: they hug the sweep like the others
// (exactly their clearance), and some lie ahead of the robot, beyond where the motion goes.
TEST(Hallucination, BlockingObstaclesHugTheSweepAndStandAhead) {
  HallucinationConfig config;
  config.constraining_min = config.constraining_max = 0;
  config.blocking_min = config.blocking_max = 3;
  const core::RobotConfig robot;
  int demos = 0, ahead = 0, obstacles = 0;
  for (std::size_t record = 0; record < 1200; record += 37) {
    const auto demo = hallucinate(recording(), record, 0, config);
    if (!demo) continue;
    ++demos;
    ASSERT_GT(demo->hugging, 0u);
    const SweptFootprint fine(demo->motion, core::Rect::centred(robot.footprint_length, robot.footprint_width), 0.001);
    for (std::size_t k = 0; k < demo->hugging; ++k) {
      const double gap = fine.gap(demo->obstacles[k]);
      EXPECT_GE(gap, demo->clearances[k] - 0.0005) << "record " << record << " obstacle " << k;
      EXPECT_LE(gap, demo->clearances[k] + 0.5 * config.sweep_step + 1e-6) << "record " << record << " obstacle " << k;
      const Eigen::Vector2d c = demo->obstacles[k].centre;
      ++obstacles;
      if (c.x() > 0.0 && std::abs(std::atan2(c.y(), c.x())) < 0.7) ++ahead;
    }
  }
  EXPECT_GT(demos, 25);
  EXPECT_GT(ahead, obstacles / 2);
}

// ---- Constraining placement ----

// A straight motion along x from (0, y) to (2, y), swept with a 0.2 x 0.2 m footprint.
SweptFootprint straightAt(double y) {
  return SweptFootprint({{0.0, y, 0.0}, {2.0, y, 0.0}}, core::Rect::centred(0.2, 0.2), 0.02);
}

TEST(ConstrainingPlacement, KeepsTheCandidatesThatRuleOutTheMostNewAlternativesAndStops) {
  const std::vector<SweptFootprint> alternatives = {straightAt(-1.0), straightAt(0.0), straightAt(1.0)};
  const std::vector<Obstacle> candidates = {
      makeObstacle({1.0, 0.0}, 0.05, 0.05, 0.0),   // blocks the middle one
      makeObstacle({1.0, 0.5}, 0.55, 0.55, 0.0),   // blocks the middle and the upper one
      makeObstacle({1.0, -1.0}, 0.05, 0.05, 0.0),  // blocks the lower one
      makeObstacle({5.0, 5.0}, 0.05, 0.05, 0.0),   // blocks none
  };
  // The widest first, then the one that adds the lower line; the small middle post adds nothing.
  EXPECT_EQ(mostConstraining(candidates, alternatives, 10), (std::vector<std::size_t>{1, 2}));
  EXPECT_EQ(mostConstraining(candidates, alternatives, 1), (std::vector<std::size_t>{1}));
  // Equal gains: the earlier candidate.
  EXPECT_EQ(mostConstraining({candidates[2], candidates[0]}, alternatives, 1), (std::vector<std::size_t>{0}));
  EXPECT_TRUE(mostConstraining({candidates[3]}, alternatives, 10).empty());
}

TEST(ConstrainingPlacement, AlternativesAreArcsOnTheGridOfSpeedsAndTurnRates) {
  HallucinationConfig config;
  config.alternative_speed = 1.0;
  config.alternative_speeds = 2;   // v = 0.5, 1.0
  config.alternative_turn_rate = 1.0;
  config.alternative_turns = 3;    // w = -1, 0, 1
  const std::vector<SweptFootprint> sweeps = alternativeSweeps(config, 2.0, core::Rect::centred(0.5, 0.4));
  ASSERT_EQ(sweeps.size(), 6u);
  // Speed-major order: (0.5, -1), (0.5, 0), (0.5, 1), (1, -1), (1, 0), (1, 1).
  const core::Pose2 straight = sweeps[4].poses().back();
  EXPECT_NEAR(straight.x, 2.0, 1e-12);
  EXPECT_NEAR(straight.y, 0.0, 1e-12);
  const core::Pose2 left = sweeps[2].poses().back();  // radius 0.5, turned 2 rad
  EXPECT_NEAR(left.x, 0.5 * std::sin(2.0), 1e-12);
  EXPECT_NEAR(left.y, 0.5 * (1.0 - std::cos(2.0)), 1e-12);
  EXPECT_NEAR(left.yaw, 2.0, 1e-12);
  const core::Pose2 right = sweeps[0].poses().back();
  EXPECT_NEAR(right.y, -left.y, 1e-12);
}

TEST(ConstrainingPlacement, KeptObstaclesHugTheMotionAndEachRulesOutAnAlternative) {
  HallucinationConfig config;
  config.candidates = 12;
  config.constraining_max = 6;
  config.alternative_speed = 2.0;  // the recording's speed limit
  config.alternative_turn_rate = 1.4;
  const core::RobotConfig robot;
  const core::Rect footprint = core::Rect::centred(robot.footprint_length, robot.footprint_width);
  int demos = 0;
  for (std::size_t record = 0; record < 1200; record += 37) {
    const auto demo = hallucinate(recording(), record, 0, config);
    if (!demo) continue;
    ++demos;
    EXPECT_LE(demo->hugging, 6u);
    const SweptFootprint fine(demo->motion, footprint, 0.001);
    const double horizon = static_cast<double>(demo->motion.size() - 1) / recording().rate;
    const std::vector<SweptFootprint> alternatives = alternativeSweeps(config, horizon, footprint);
    for (std::size_t k = 0; k < demo->hugging; ++k) {
      const double gap = fine.gap(demo->obstacles[k]);
      EXPECT_GE(gap, demo->clearances[k] - 0.0005) << "record " << record << " obstacle " << k;
      EXPECT_LE(gap, demo->clearances[k] + 0.5 * config.sweep_step + 1e-6) << "record " << record << " obstacle " << k;
      bool rules_out = false;
      for (const SweptFootprint& a : alternatives) rules_out = rules_out || a.gap(demo->obstacles[k]) < 0.0;
      EXPECT_TRUE(rules_out) << "record " << record << " obstacle " << k;
    }
  }
  EXPECT_GT(demos, 25);
}

TEST(Hallucination, DistractorsStayOutOfTheVelocitySector) {
  const HallucinationConfig config;
  for (std::size_t record = 0; record < 1200; record += 101) {
    const auto demo = hallucinate(recording(), record, 0, config);
    if (!demo) continue;
    // The sector at the start pose: radius |v| * 1 s, +-60 degrees around the heading.
    const double radius = std::abs(recording().records[record].v) * config.sector_time;
    for (std::size_t k = demo->hugging; k < demo->obstacles.size(); ++k) {
      for (const Disk& d : demo->obstacles[k].disks) {
        // Sample the disk boundary and interior densely: no point inside the sector.
        for (int a = 0; a < 72; ++a) {
          for (double s : {0.0, 0.5, 0.999}) {
            const Eigen::Vector2d q = d.centre + s * d.radius * Eigen::Vector2d(std::cos(a * M_PI / 36), std::sin(a * M_PI / 36));
            const bool inside = q.norm() < radius && std::abs(std::atan2(q.y(), q.x())) < config.sector_half_angle;
            EXPECT_FALSE(inside) << "record " << record << " distractor " << k;
          }
        }
      }
    }
  }
}

TEST(Hallucination, SameRecordAndDrawGiveTheSameDemonstrationOtherDrawsDiffer) {
  const HallucinationConfig config;
  const auto a = hallucinate(recording(), 200, 0, config);
  const auto b = hallucinate(recording(), 200, 0, config);
  const auto c = hallucinate(recording(), 200, 1, config);
  ASSERT_TRUE(a && b && c);
  EXPECT_EQ(a->ranges, b->ranges);
  EXPECT_NE(a->ranges, c->ranges);
  EXPECT_EQ(a->command.linear, c->command.linear);  // same record, same label
}

TEST(Hallucination, SkipsRecordsWithoutEnoughFutureForTheGoal) {
  const HallucinationConfig config;
  // The goal is 2 s = 100 records ahead of the record at 50 Hz.
  EXPECT_FALSE(hallucinate(recording(), recording().records.size() - 50, 0, config));
}

TEST(Ellipse, DisksLieInsideTheEllipseAndReachItsVertices) {
  // a = 0.5, b = 0.25: medial axis |x| <= (0.25 - 0.0625) / 0.5 = 0.375, end disks of radius
  // b^2 / a = 0.125 centred at x = +-0.375 reach x = +-0.5, the vertices.
  const std::vector<Disk> disks = ellipseDisks({1.0, 2.0}, 0.5, 0.25, 0.0);
  ASSERT_GE(disks.size(), 3u);
  EXPECT_NEAR(disks.front().centre.x() - disks.front().radius, 0.5, 1e-12);
  EXPECT_NEAR(disks.back().centre.x() + disks.back().radius, 1.5, 1e-12);
  double widest = 0.0;
  for (const Disk& d : disks) {
    widest = std::max(widest, d.radius);
    // Every disk boundary point satisfies (x/a)^2 + (y/b)^2 <= 1.
    for (int k = 0; k < 360; ++k) {
      const Eigen::Vector2d q = d.centre - Eigen::Vector2d(1.0, 2.0) +
                                d.radius * Eigen::Vector2d(std::cos(k * M_PI / 180), std::sin(k * M_PI / 180));
      EXPECT_LE(q.x() * q.x() / 0.25 + q.y() * q.y() / 0.0625, 1.0 + 1e-9);
    }
  }
  EXPECT_NEAR(widest, 0.25, 1e-3);  // the middle disk touches the co-vertices
  EXPECT_EQ(ellipseDisks({0, 0}, 0.3, 0.3, 1.0).size(), 1u);  // a circle is one disk
}

TEST(RenderScan, CircleAheadGivesTheHandComputedRange) {
  // A circle of radius 0.3 centred 2 m ahead of the robot. The sensor sits 0.055 m ahead of
  // the robot centre, so the beam straight ahead (beam 359.5: none is exactly at 0; beams 359
  // and 360 are at -+0.003277 rad) hits at about 2 - 0.055 - 0.3 = 1.645 m. For beam 360
  // at angle a = 0.5 * 4.71238 / 719 = 0.0032770 rad: t = d cos a - sqrt(r^2 - d^2 sin^2 a),
  // d = 1.945: 1.944990 - sqrt(0.09 - 0.0000406) = 1.944990 - 0.299932 = 1.645058.
  core::LidarConfig lidar;
  const std::vector<double> ranges = renderScan({makeObstacle({2.0, 0.0}, 0.3, 0.3, 0.0)}, lidar, nullptr);
  ASSERT_EQ(ranges.size(), 720u);
  EXPECT_NEAR(ranges[360], 1.645058, 2e-6);
  EXPECT_EQ(ranges[359], ranges[360]);  // symmetric beams
  EXPECT_TRUE(std::isinf(ranges[0]));   // nothing behind
  // The circle subtends +-asin(0.3 / 1.945) = +-0.1549 rad: 0.1549 / 0.006554 = 23.6 beams each side.
  int hits = 0;
  for (double r : ranges) hits += std::isfinite(r) ? 1 : 0;
  EXPECT_GE(hits, 46);
  EXPECT_LE(hits, 48);
}

TEST(RenderScan, NoObstaclesMeansNoReturns) {
  for (double r : renderScan({}, core::LidarConfig{}, nullptr)) EXPECT_TRUE(std::isinf(r));
}

TEST(Mirror, MirroredWorldGivesTheReversedScanAndTheMirroredExample) {
  const HallucinationConfig config;
  const auto demo = hallucinate(recording(), 300, 0, config);
  ASSERT_TRUE(demo);
  core::LidarConfig lidar;
  const std::vector<double> original = renderScan(demo->obstacles, lidar, nullptr);
  const std::vector<double> reflected = renderScan(mirrored(demo->obstacles), lidar, nullptr);
  // Beam i at angle a_i mirrors beam 719 - i at -a_i (angle_min = -angle_max, sensor on the x axis).
  for (std::size_t i = 0; i < 720; ++i) {
    if (std::isinf(original[i])) EXPECT_TRUE(std::isinf(reflected[719 - i])) << i;
    else EXPECT_NEAR(reflected[719 - i], original[i], 1e-9) << i;
  }
  // mirrorExample applied to the encoded original equals the encoding of the mirrored world
  // with the goal's y and the turn rate negated.
  std::vector<float> input(722), expected(722);
  float target[2] = {static_cast<float>(demo->command.linear), static_cast<float>(demo->command.angular)};
  encodeInput(original, demo->goal, 2.0, input.data());
  mirrorExample(input.data(), target, 720);
  encodeInput(reflected, {demo->goal.x(), -demo->goal.y()}, 2.0, expected.data());
  for (std::size_t i = 0; i < 722; ++i) EXPECT_NEAR(input[i], expected[i], 1e-6) << i;
  EXPECT_EQ(target[0], static_cast<float>(demo->command.linear));
  EXPECT_EQ(target[1], -static_cast<float>(demo->command.angular));
}

TEST(Dataset, EncodesClippedRangesAndTheUnitGoal) {
  std::vector<double> ranges(720, kInf);
  ranges[0] = 0.5;
  ranges[1] = 3.0;
  ranges[2] = std::numeric_limits<double>::quiet_NaN();
  std::vector<float> column(722);
  encodeInput(ranges, {3.0, 4.0}, 2.0, column.data());
  EXPECT_EQ(column[0], 0.5f);
  EXPECT_EQ(column[1], 2.0f);    // clipped
  EXPECT_EQ(column[2], 2.0f);    // NaN reads as free
  EXPECT_EQ(column[719], 2.0f);  // +inf reads as free
  EXPECT_FLOAT_EQ(column[720], 0.6f);  // (3, 4) / 5
  EXPECT_FLOAT_EQ(column[721], 0.8f);
}

TEST(Dataset, IsDeterministicAndLabelsAreTheRecordedCommands) {
  HallucinationConfig config;
  config.stride = 50;
  const Dataset a = buildDataset(recording(), config, 2.0);
  const Dataset b = buildDataset(recording(), config, 2.0);
  ASSERT_GT(a.size(), 20u);
  EXPECT_EQ(a.inputs, b.inputs);
  EXPECT_EQ(a.inputs.rows(), 722);
  for (std::size_t c = 0; c < a.size(); ++c) {
    EXPECT_EQ(a.records[c] % 50, 0u);
    EXPECT_EQ(a.targets(0, static_cast<Eigen::Index>(c)), static_cast<float>(recording().records[a.records[c]].command.linear));
  }
  EXPECT_EQ(a.lookahead, 100u);  // max(goal 2 s, horizon 2 s) at 50 Hz
}

}  // namespace
}  // namespace barn::learning
