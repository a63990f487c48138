#include "barn/controllers/eband.hpp"

#include <cmath>
#include <limits>
#include <vector>

#include <gtest/gtest.h>

#include "barn/bench/episode.hpp"
#include "barn/core/config.hpp"
#include "tests/bench/empty_world.hpp"

namespace barn::controllers {
namespace {

// The padded BARN footprint's circumscribed radius: hypot(0.31, 0.265).
const double kCircumscribed = std::hypot(0.31, 0.265);
// A free cell's bubble radius: -ln(1 / 252) / 10.
const double kFreeRadius = std::log(252.0) / 10.0;

// A fixed 6 x 6 m costmap centred on the origin with BARN's inflation.
nav::Costmap emptyMap() {
  nav::CostmapConfig c;
  c.width = 6.0;
  c.height = 6.0;
  c.origin_x = -3.0;
  c.origin_y = -3.0;
  return nav::Costmap(c, nav::NavStackConfig{}.inscribedRadius(c));
}

// Plan poses every 2.5 cm (NavFn's half-cell steps) along the polyline, yaw 0 as NavFn's.
std::vector<core::Pose2> densePlan(const std::vector<Eigen::Vector2d>& corners) {
  std::vector<core::Pose2> poses;
  for (std::size_t k = 0; k + 1 < corners.size(); ++k) {
    const Eigen::Vector2d a = corners[k], b = corners[k + 1];
    const int steps = static_cast<int>(std::ceil((b - a).norm() / 0.025));
    for (int i = 0; i < steps; ++i) {
      const Eigen::Vector2d p = a + (b - a) * (static_cast<double>(i) / steps);
      poses.push_back({p.x(), p.y(), 0.0});
    }
  }
  poses.push_back({corners.back().x(), corners.back().y(), 0.0});
  return poses;
}

// Every neighbour pair overlaps and no bubble is redundant (its neighbours do not overlap
// without it): what refinement leaves.
void expectRefined(const ElasticBand& eband) {
  const auto& b = eband.bubbles();
  ASSERT_GE(b.size(), 2u);
  for (std::size_t k = 0; k + 1 < b.size(); ++k) EXPECT_TRUE(eband.overlap(b[k], b[k + 1])) << "pair " << k;
  for (std::size_t k = 1; k + 1 < b.size(); ++k) EXPECT_FALSE(eband.overlap(b[k - 1], b[k + 1])) << "bubble " << k;
}

double bandLength(const std::vector<EbandBubble>& band) {
  double length = 0.0;
  for (std::size_t k = 0; k + 1 < band.size(); ++k)
    length += (band[k + 1].center.position() - band[k].center.position()).norm();
  return length;
}

// ---------------------------------------------------------------------------------------------
// Bubbles from the costmap

TEST(EbandBubbles, RadiusInvertsTheInflationAndIsZeroInCollision) {
  nav::Costmap map = emptyMap();
  map.markObstacle({0.0, 0.0});
  map.update();
  const EbandConfig config;
  ElasticBand eband(config, kCircumscribed);
  eband.setCostmap(map);
  nav::CellIndex cell;
  ASSERT_TRUE(map.toCell({0.0, 0.0}, cell));
  const Eigen::Vector2d centre = map.cellCentre(cell);
  // Free space (and off the map) counts as cost 1: 0.553 m whatever the true distance.
  EXPECT_NEAR(eband.obstacleDistance({2.0, 2.0, 0.0}), kFreeRadius, 1e-12);
  EXPECT_NEAR(eband.obstacleDistance({50.0, 0.0, 0.0}), kFreeRadius, 1e-12);
  EXPECT_NEAR(kFreeRadius, 0.553, 5e-4);
  // The obstacle cell and the inscribed disc around it: 0.
  EXPECT_EQ(eband.obstacleDistance({centre.x(), centre.y(), 0.0}), 0.0);
  EXPECT_EQ(eband.obstacleDistance({centre.x() + 0.25, centre.y(), 1.0}), 0.0);
  // The inflation ring's outer cell, 6 cells out: -ln(cost / 252) / 10, about 3.5 cm.
  const core::Pose2 ring{centre.x() + 0.30, centre.y(), 0.0};
  const int cost = map.costAt(ring.position());
  ASSERT_GT(cost, 0);
  ASSERT_LT(cost, nav::kInscribedCost);
  EXPECT_NEAR(eband.obstacleDistance(ring), -std::log(cost / 252.0) / 10.0, 1e-12);
  EXPECT_NEAR(eband.obstacleDistance(ring), 0.035, 0.002);
  // Yaw is ignored.
  EXPECT_EQ(eband.obstacleDistance({ring.x, ring.y, 2.0}), eband.obstacleDistance(ring));
}

// ---------------------------------------------------------------------------------------------
// Band construction and refinement

TEST(EbandBand, AStraightPlanInTheOpenBecomesAFewOverlappingBubbles) {
  const nav::Costmap map = emptyMap();
  const EbandConfig config;
  ElasticBand eband(config, kCircumscribed);
  eband.setCostmap(map);
  const std::vector<core::Pose2> plan = densePlan({{-2.0, 0.0}, {2.0, 0.0}});
  ASSERT_GT(plan.size(), 150u);
  ASSERT_TRUE(eband.setPlan(plan));
  expectRefined(eband);
  const auto& b = eband.bubbles();
  // Free bubbles overlap up to 0.7 x 2 x 0.553 = 0.774 m apart: 4 m needs at least 6.
  EXPECT_GE(b.size(), 6u);
  EXPECT_LE(b.size(), 12u);
  EXPECT_DOUBLE_EQ(b.front().center.x, -2.0);
  EXPECT_DOUBLE_EQ(b.back().center.x, 2.0);
  for (const EbandBubble& bubble : b) EXPECT_NEAR(bubble.expansion, kFreeRadius, 1e-12);
}

TEST(EbandBand, APlanThroughAnObstacleIsRefusedAndGapsAreFilled) {
  nav::Costmap map = emptyMap();
  map.markObstacle({0.0, 0.0});
  map.update();
  const EbandConfig config;
  ElasticBand eband(config, kCircumscribed);
  eband.setCostmap(map);
  // A pose in the inscribed disc: the plan cannot become a band, the old band stays.
  ASSERT_TRUE(eband.setPlan(densePlan({{-2.0, 1.0}, {2.0, 1.0}})));
  const std::size_t before = eband.bubbles().size();
  EXPECT_FALSE(eband.setPlan(densePlan({{-2.0, 0.0}, {2.0, 0.0}})));
  EXPECT_EQ(eband.bubbles().size(), before);
  // Two poses 3 m apart in the open: midpoint bubbles fill the gap.
  ASSERT_TRUE(eband.setPlan({{-1.5, 2.0, 0.0}, {1.5, 2.0, 0.0}}));
  expectRefined(eband);
  EXPECT_GE(eband.bubbles().size(), 5u);
  // A gap whose midpoint is in collision cannot be filled.
  EXPECT_FALSE(eband.setPlan({{-1.5, 0.0, 0.0}, {1.5, 0.0, 0.0}}));
}

TEST(EbandBand, TheRobotJoinsAtTheFrontDroppingPassedBubbles) {
  const nav::Costmap map = emptyMap();
  const EbandConfig config;
  ElasticBand eband(config, kCircumscribed);
  eband.setCostmap(map);
  ASSERT_TRUE(eband.setPlan(densePlan({{-2.0, 0.0}, {2.0, 0.0}})));
  const std::size_t before = eband.bubbles().size();
  // The robot has moved 1.5 m along: the farthest bubble it overlaps follows it directly.
  const core::Pose2 robot{-0.5, 0.05, 0.3};
  ASSERT_TRUE(eband.addFrames({robot}, true));
  const auto& b = eband.bubbles();
  EXPECT_LT(b.size(), before);
  EXPECT_DOUBLE_EQ(b.front().center.x, robot.x);
  EXPECT_DOUBLE_EQ(b.front().center.yaw, robot.yaw);
  EXPECT_TRUE(eband.overlap(b[0], b[1]));
  for (std::size_t k = 1; k < b.size(); ++k) EXPECT_GT(b[k].center.x, robot.x);  // those behind are gone
  EXPECT_DOUBLE_EQ(b.back().center.x, 2.0);
}

// ---------------------------------------------------------------------------------------------
// Optimisation

TEST(EbandOptimisation, TheInternalForceStraightensABentBand) {
  const nav::Costmap map = emptyMap();
  const EbandConfig config;
  ElasticBand eband(config, kCircumscribed);
  eband.setCostmap(map);
  ASSERT_TRUE(eband.setPlan(densePlan({{-2.0, 0.0}, {0.0, 1.5}, {2.0, 0.0}})));
  const std::vector<EbandBubble> bent = eband.bubbles();
  ASSERT_TRUE(eband.optimize());
  const auto& b = eband.bubbles();
  expectRefined(eband);
  // The ends stay, the band contracts toward the straight line between them.
  EXPECT_DOUBLE_EQ(b.front().center.x, -2.0);
  EXPECT_DOUBLE_EQ(b.back().center.x, 2.0);
  EXPECT_LT(bandLength(b), bandLength(bent) - 0.5);  // 5.0 m -> 4.1 m
  double highest = 0.0;
  for (const EbandBubble& bubble : b) highest = std::max(highest, bubble.center.y);
  EXPECT_LT(highest, 0.8);  // from 1.5 m (0.44 m)
}

TEST(EbandOptimisation, TheExternalForcePushesBubblesAwayFromAWall) {
  // A wall along y = 0.5 (0.5 m from the band, outside the inflation): the rims of the middle
  // bubbles (0.553 m) reach it, so they are pushed toward -y; the ends stay.
  nav::Costmap map = emptyMap();
  for (double x = -1.5; x <= 1.5; x += 0.05) map.markObstacle({x, 0.5});
  map.update();
  const EbandConfig config;
  ElasticBand eband(config, kCircumscribed);
  eband.setCostmap(map);
  ASSERT_TRUE(eband.setPlan(densePlan({{-2.5, 0.0}, {2.5, 0.0}})));
  // The force on a middle bubble points away from the wall, across the band.
  const auto& start = eband.bubbles();
  const std::size_t mid = start.size() / 2;
  const Eigen::Vector3d external = eband.externalForce(start[mid]);
  EXPECT_LT(external.y(), -0.5);
  EXPECT_NEAR(external.z(), 0.0, 1e-12);
  const Eigen::Vector3d force = eband.forcesAt(mid, start, start[mid]);
  EXPECT_LT(force.y(), -0.5);
  ASSERT_TRUE(eband.optimize());
  const auto& b = eband.bubbles();
  EXPECT_DOUBLE_EQ(b.front().center.y, 0.0);
  EXPECT_DOUBLE_EQ(b.back().center.y, 0.0);
  double lowest = 0.0;
  for (std::size_t k = 1; k + 1 < b.size(); ++k) {
    lowest = std::min(lowest, b[k].center.y);
    EXPECT_GT(b[k].expansion, config.eband_tiny_bubble_expansion);
  }
  EXPECT_LT(lowest, -0.25);  // about 0.36 m below the start line
}

TEST(EbandOptimisation, FailsWhenABubbleIsInCollision) {
  nav::Costmap map = emptyMap();
  const EbandConfig config;
  ElasticBand eband(config, kCircumscribed);
  eband.setCostmap(map);
  ASSERT_TRUE(eband.setPlan(densePlan({{-2.0, 0.0}, {2.0, 0.0}})));
  const std::vector<EbandBubble> before = eband.bubbles();
  // An obstacle appears on a bubble's centre: optimisation fails and leaves the band alone.
  const Eigen::Vector2d on = before[before.size() / 2].center.position();
  map.markObstacle(on);
  map.update();
  EXPECT_FALSE(eband.optimize());
  ASSERT_EQ(eband.bubbles().size(), before.size());
  for (std::size_t k = 0; k < before.size(); ++k) EXPECT_EQ(eband.bubbles()[k].center.x, before[k].center.x);
}

// ---------------------------------------------------------------------------------------------
// Command law (differential drive)

std::vector<EbandBubble> band(const core::Pose2& robot, double robot_radius, const Eigen::Vector2d& next,
                              const Eigen::Vector2d& end) {
  return {{robot, robot_radius}, {{next.x(), next.y(), 0.0}, kFreeRadius}, {{end.x(), end.y(), 0.0}, kFreeRadius}};
}

TEST(EbandCommand, DrivesAtTheBubbleSpeedTowardTheNextBubble) {
  EbandController eband{EbandConfig{}};
  // Straight ahead in the open: 2 x 0.7 x 0.553 x 0.75 = 0.581 m/s, no turn.
  const auto ahead = eband.commandFor(band({0.0, 0.0, 0.0}, kFreeRadius, {0.7, 0.0}, {4.0, 0.0}));
  EXPECT_NEAR(ahead.twist.linear, 2.0 * 0.7 * kFreeRadius * 0.75, 1e-12);
  EXPECT_NEAR(ahead.twist.angular, 0.0, 1e-12);
  EXPECT_FALSE(ahead.turning_in_place);
  // The next bubble 0.2 rad to the left (inside the 0.5 rad cone): cos-slowed, turning left at
  // k_prop x 0.2; to the right the mirror image.
  const double b = 0.2;
  const auto left = eband.commandFor(band({0.0, 0.0, 0.0}, kFreeRadius, {0.7 * std::cos(b), 0.7 * std::sin(b)}, {4.0, 0.0}));
  EXPECT_NEAR(left.twist.linear, 2.0 * 0.7 * kFreeRadius * 0.75 * std::cos(b), 1e-12);
  EXPECT_NEAR(left.twist.angular, 4.0 * b, 1e-12);
  const auto right = eband.commandFor(band({0.0, 0.0, 0.0}, kFreeRadius, {0.7 * std::cos(b), -0.7 * std::sin(b)}, {4.0, 0.0}));
  EXPECT_NEAR(right.twist.angular, -4.0 * b, 1e-12);
  // In the robot's frame, whatever its pose.
  const auto turned = eband.commandFor(band({1.0, 2.0, 1.0}, kFreeRadius, {1.0 + 0.7 * std::cos(1.0 + b), 2.0 + 0.7 * std::sin(1.0 + b)},
                                            {5.0, 5.0}));
  EXPECT_NEAR(turned.twist.angular, 4.0 * b, 1e-9);
}

TEST(EbandCommand, TurnsInPlaceWhenTheNextBubbleIsOutsideItsCone) {
  EbandController eband{EbandConfig{}};
  // atan2(0.7 x 0.553, 0.7) = 0.505 rad: a bearing of 0.6 turns in place, clipped to 1 rad/s.
  const auto left = eband.commandFor(band({0.0, 0.0, 0.0}, kFreeRadius, {0.7 * std::cos(0.6), 0.7 * std::sin(0.6)}, {4.0, 0.0}));
  EXPECT_TRUE(left.turning_in_place);
  EXPECT_EQ(left.twist.linear, 0.0);
  EXPECT_DOUBLE_EQ(left.twist.angular, 1.0);
  // Behind on the right: turn clockwise.
  const auto behind = eband.commandFor(band({0.0, 0.0, 0.0}, kFreeRadius, {-0.5, -0.3}, {-4.0, 0.0}));
  EXPECT_TRUE(behind.turning_in_place);
  EXPECT_DOUBLE_EQ(behind.twist.angular, -1.0);
  // A small bearing below the limit: k_prop x bearing.
  const auto small = eband.commandFor(band({0.0, 0.0, 0.0}, 0.05, {0.1 * std::cos(0.2), 0.1 * std::sin(0.2)}, {4.0, 0.0}));
  // The next bubble (0.553) at 0.1 m spans atan2(0.387, 0.1) = 1.32 rad: drive, not turn.
  EXPECT_FALSE(small.turning_in_place);
  EXPECT_NEAR(small.twist.angular, 0.8, 1e-12);
}

TEST(EbandCommand, SpeedLimitsAndSlowDowns) {
  EbandController eband{EbandConfig{}};
  // The robot's centre in the inflation ring (3.5 cm): 2 x 0.7 x 0.035 x 0.75 = 0.037,
  // raised to min_vel_lin.
  const auto crawl = eband.commandFor(band({0.0, 0.0, 0.0}, 0.035, {0.05, 0.0}, {4.0, 0.0}));
  EXPECT_DOUBLE_EQ(crawl.twist.linear, 0.1);
  // Within 0.75 m of the band's end the limit is halved: 0.29 m/s.
  const auto near_end = eband.commandFor(band({0.0, 0.0, 0.0}, kFreeRadius, {0.3, 0.0}, {0.6, 0.0}));
  EXPECT_NEAR(near_end.twist.linear, 2.0 * 0.7 * kFreeRadius * 0.375, 1e-12);
  // A larger multiplier is clamped to max_vel_lin.
  EbandConfig fast;
  fast.bubble_velocity_multiplier = 4.0;
  EbandController clamped{fast};
  EXPECT_DOUBLE_EQ(clamped.commandFor(band({0.0, 0.0, 0.0}, kFreeRadius, {0.7, 0.0}, {4.0, 0.0})).twist.linear, 0.75);
}

TEST(EbandCommand, AtTheGoalTurnsToItsYawThenReportsReached) {
  EbandController eband{EbandConfig{}};
  // The band's end 3 cm away (inside 0.6 x 0.1), the robot at yaw 1.0, the goal's yaw 0.
  std::vector<EbandBubble> at_goal = {{{0.0, 0.0, 1.0}, kFreeRadius}, {{0.03, 0.0, 0.0}, kFreeRadius}};
  const auto turn = eband.commandFor(at_goal);
  EXPECT_TRUE(turn.turning_in_place);
  EXPECT_FALSE(turn.goal_reached);
  EXPECT_EQ(turn.twist.linear, 0.0);
  EXPECT_DOUBLE_EQ(turn.twist.angular, -1.0);  // 4 x -1.0, clipped
  // Hysteresis: 8 cm away (outside the 6 cm box, inside the 10 cm one) it keeps turning.
  at_goal[0].center = {-0.05, 0.0, 0.5};
  EXPECT_TRUE(eband.commandFor(at_goal).turning_in_place);
  // Aligned within 0.05 rad: done.
  at_goal[0].center = {0.0, 0.0, 0.02};
  const auto done = eband.commandFor(at_goal);
  EXPECT_TRUE(done.goal_reached);
  EXPECT_EQ(done.twist.linear, 0.0);
  EXPECT_EQ(done.twist.angular, 0.0);
}

// ---------------------------------------------------------------------------------------------
// Config and episodes

TEST(EbandConfigTest, RejectsBadValues) {
  EbandConfig config;
  config.min_vel_lin = 1.0;  // above max_vel_lin
  core::Errors errors;
  validate(config, errors, "eband");
  ASSERT_FALSE(errors.empty());
  EXPECT_NE(errors.messages().front().find("eband.min_vel_lin"), std::string::npos);
}

TEST(EbandEpisode, ReachesTheGoalDownAFreeCorridor) {
  // The empty field: NavFn's path straight up the corridor, the band a few free bubbles, the
  // robot at 2 x 0.7 x 0.553 x 0.75 = 0.58 m/s: the 10 m (9 m to the 1 m circle) in ~16 s.
  const core::WorldSpec world = bench::emptyWorld();
  const sim::ObstacleField field = sim::ObstacleField::fromWorld(world);
  EbandController eband{EbandConfig{}};
  const bench::EpisodeResult r = bench::runEpisode(world, field, eband, {}, 7, true);
  EXPECT_EQ(r.outcome, bench::Outcome::Success) << r.error;
  EXPECT_GT(r.actual_time, 14.0);
  EXPECT_LT(r.actual_time, 19.0);
  EXPECT_GT(r.mean_speed, 0.5);
  EXPECT_EQ(eband.stateLabel(), "driving");
}

TEST(EbandEpisode, WaitsWithoutAPlanAndRecoversAsMoveBase) {
  // The goal inside a wall 1 m ahead: no plan, no band, so every cycle fails; move_base stops
  // and waits, and after planner_patience without a plan runs its recoveries.
  EbandConfig config;
  config.nav.global_costmap.width = 10.0;
  config.nav.global_costmap.height = 6.0;
  EbandController eband(config);
  EpisodeInfo info;
  info.goal = {1.0, 0.0};
  info.lidar.mount_x = 0.0;
  eband.reset(info);
  // The wall's returns: beams hitting x = 1 from the origin.
  const core::LidarConfig lidar;
  core::LaserScan scan;
  scan.angle_min = lidar.angle_min;
  scan.angle_increment = lidar.angleIncrement();
  scan.range_min = lidar.range_min;
  scan.range_max = lidar.range_max;
  for (int i = 0; i < lidar.beams; ++i) {
    const double c = std::cos(lidar.angle_min + i * lidar.angleIncrement());
    scan.ranges.push_back(c > 0.2 ? 1.0 / c : std::numeric_limits<double>::infinity());
  }
  Observation obs;
  obs.goal = info.goal;
  obs.scan = &scan;
  double first_turn = -1.0;
  for (int tick = 0; tick <= 220 && first_turn < 0.0; ++tick) {
    obs.time = 0.05 * tick;
    scan.stamp = obs.time;
    const core::Twist cmd = eband.act(obs);
    EXPECT_EQ(cmd.linear, 0.0);
    if (cmd.angular != 0.0) {
      first_turn = obs.time;
      EXPECT_GT(cmd.angular, 0.0);  // rotate_recovery turns counter-clockwise
      EXPECT_EQ(eband.stateLabel(), "recovery");
    } else if (tick > 0) {
      EXPECT_EQ(eband.stateLabel(), "waiting") << "at " << obs.time << " s";
    }
  }
  EXPECT_GT(first_turn, 10.0);
  EXPECT_LT(first_turn, 10.3);
}

}  // namespace
}  // namespace barn::controllers
