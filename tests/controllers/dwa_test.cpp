#include "barn/controllers/dwa.hpp"

#include <cmath>
#include <limits>
#include <stdexcept>
#include <string>

#include <gmock/gmock.h>
#include <gtest/gtest.h>

namespace barn::controllers {
namespace {

struct Segment {
  Eigen::Vector2d a, b;  // robot frame [m]
};

// A 720-beam UST-10 scan from the sensor (at the robot centre here) against wall segments.
core::LaserScan scanOf(const std::vector<Segment>& walls) {
  const core::LidarConfig lidar;
  core::LaserScan scan;
  scan.angle_min = lidar.angle_min;
  scan.angle_increment = lidar.angleIncrement();
  scan.range_min = lidar.range_min;
  scan.range_max = lidar.range_max;
  for (int i = 0; i < lidar.beams; ++i) {
    const double angle = lidar.angle_min + i * lidar.angleIncrement();
    const Eigen::Vector2d u(std::cos(angle), std::sin(angle));
    double best = std::numeric_limits<double>::infinity();
    for (const auto& w : walls) {
      // Solve t u = a + s (b - a), t > 0, s in [0, 1].
      const Eigen::Vector2d e = w.b - w.a;
      const double det = u.x() * (-e.y()) - u.y() * (-e.x());
      if (std::abs(det) < 1e-12) continue;
      const double t = (w.a.x() * (-e.y()) - w.a.y() * (-e.x())) / det;
      const double s = (u.x() * w.a.y() - u.y() * w.a.x()) / det;
      if (t > 0 && s >= 0 && s <= 1) best = std::min(best, t);
    }
    scan.ranges.push_back(best);
  }
  return scan;
}

// The robot at the odom origin facing +x, goal 6 m ahead; a few ticks so the costmaps and the
// plan settle on the scan. Returns the last command.
core::Twist commandFor(const core::LaserScan& scan, DwaConfig config = {}) {
  config.nav.global_costmap.origin_x = -3.0;
  config.nav.global_costmap.origin_y = -3.0;
  config.nav.global_costmap.width = 10.0;
  config.nav.global_costmap.height = 6.0;
  DwaController dwa(config);
  EpisodeInfo info;
  info.goal = {6.0, 0.0};
  info.lidar.mount_x = 0.0;  // the scans above are taken from the robot centre
  dwa.reset(info);
  Observation obs;
  obs.scan = &scan;
  obs.goal = info.goal;
  core::Twist cmd;
  for (int tick = 0; tick < 3; ++tick) {
    obs.time = 0.05 * tick;
    core::LaserScan stamped = scan;
    stamped.stamp = obs.time;
    obs.scan = &stamped;
    cmd = dwa.act(obs);
  }
  return cmd;
}

TEST(Dwa, DrivesStraightAtFullSpeedInTheOpen) {
  const core::Twist cmd = commandFor(scanOf({}));
  // The window from rest is [0.1, min(0.5, 0 + 10 * 0.05)] = [0.1, 0.5]; the goal is straight
  // ahead, so the fastest straight sample wins.
  EXPECT_NEAR(cmd.linear, 0.5, 1e-9);
  EXPECT_NEAR(cmd.angular, 0.0, 0.2);
}

TEST(Dwa, DoesNotDriveIntoAWallAhead) {
  // A wall across the whole front 0.45 m ahead: the slowest forward roll-out (0.1 m/s for 2 s
  // = 0.2 m) would put the padded footprint's front edge (0.21 + 0.1 = 0.31 m) 0.06 m into it.
  const core::Twist cmd = commandFor(scanOf({{{0.45, -3.0}, {0.45, 3.0}}}));
  EXPECT_LE(cmd.linear, 0.0 + 1e-9);
}

TEST(Dwa, TurnsLeftIntoAGapToTheLeft) {
  // A wall ahead at 1.2 m with a 1.2 m gap on the left (y in [0.4, 1.6]) and walls boxing the
  // right side: the plan goes through the gap, so the robot turns left.
  const std::vector<Segment> walls = {
      {{1.2, -3.0}, {1.2, 0.4}},   // ahead, blocking the right and the centre
      {{1.2, 1.6}, {1.2, 3.0}},    // ahead, left of the gap
      {{-1.0, -0.8}, {1.2, -0.8}}, // right side
  };
  const core::Twist cmd = commandFor(scanOf(walls));
  EXPECT_GT(cmd.angular, 0.2);
}

// Short walls 0.36 m ahead of and behind the robot (|y| <= 0.4): the padded footprint
// (+-0.31 x +-0.265) clears them standing still, but any forward arc (its front edge reaches
// the wall's cell after 4 cm), any in-place turn (the corners sweep a 0.408 m circle) and the
// back-up all cross a lethal cell. The robot's own cell is 7 cells from both walls (cost 0),
// so the path around the walls' ends stays reachable.
const std::vector<Segment> kBoxedIn = {{{0.36, -0.4}, {0.36, 0.4}}, {{-0.36, -0.4}, {-0.36, 0.4}}};

TEST(Dwa, BacksUpBlindWhenNothingIsLegal) {
  // TrajectoryPlanner: with no legal arc or rotation the escape trajectory (escape_vel) is
  // driven even though its footprint hits (its cost -1 is replaced by +1).
  const core::Twist cmd = commandFor(scanOf(kBoxedIn));
  EXPECT_DOUBLE_EQ(cmd.linear, -0.5);
  EXPECT_DOUBLE_EQ(cmd.angular, 0.0);
}

TEST(Dwa, EscapingEndsAfterTurningEscapeResetTheta) {
  DwaConfig config;
  config.nav.global_costmap.width = 10.0;
  config.nav.global_costmap.height = 6.0;
  DwaController dwa(config);
  EpisodeInfo info;
  info.goal = {6.0, 0.0};
  info.lidar.mount_x = 0.0;
  dwa.reset(info);
  // One scan (later cycles see no new one, so the map stays as it was).
  const core::LaserScan scan = scanOf(kBoxedIn);
  Observation obs;
  obs.scan = &scan;
  obs.goal = info.goal;
  dwa.act(obs);
  ASSERT_TRUE(dwa.escaping());
  // Still boxed in after turning 0.05 rad (< escape_reset_theta 0.1): still escaping.
  obs.time = 0.05;
  obs.odom_pose = {0.0, 0.0, 0.05};
  dwa.act(obs);
  EXPECT_TRUE(dwa.escaping());
  // 0.11 rad from where the escape began: escaping ends (upstream: distance OR angle).
  obs.time = 0.10;
  obs.odom_pose.yaw = 0.11;
  dwa.act(obs);
  EXPECT_FALSE(dwa.escaping());
}

TEST(Dwa, WaitsForAPlanThenRecoversAfterPlannerPatience) {
  // The goal lies in a wall 1 m ahead: the planner never finds a path, so no roll-out can
  // reach it (-2) and no command is valid. move_base stops and waits in PLANNING; after
  // planner_patience (5 s) without a plan it runs the first recovery (clearing, a no-op in
  // BARN) and waits again; 5 s later the second, the rotation. Without the PLANNING state the
  // robot would only recover after controller_patience (15 s).
  DwaConfig config;
  config.nav.global_costmap.width = 10.0;
  config.nav.global_costmap.height = 6.0;
  config.nav.global_costmap.origin_x = -3.0;
  config.nav.global_costmap.origin_y = -3.0;
  DwaController dwa(config);
  EpisodeInfo info;
  info.goal = {1.0, 0.0};
  info.lidar.mount_x = 0.0;
  dwa.reset(info);
  const core::LaserScan wall = scanOf({{{1.0, -3.0}, {1.0, 3.0}}});
  Observation obs;
  obs.goal = info.goal;
  double first_turn = -1.0;
  for (int tick = 0; tick <= 220 && first_turn < 0.0; ++tick) {
    obs.time = 0.05 * tick;
    core::LaserScan stamped = wall;
    stamped.stamp = obs.time;
    obs.scan = &stamped;
    const core::Twist cmd = dwa.act(obs);
    EXPECT_DOUBLE_EQ(cmd.linear, 0.0);
    if (cmd.angular != 0.0) {
      first_turn = obs.time;
      EXPECT_GT(cmd.angular, 0.0);  // rotate_recovery turns counter-clockwise
      EXPECT_EQ(dwa.stateLabel(), "recovery");
    } else {
      EXPECT_EQ(dwa.stateLabel(), "waiting") << "at " << obs.time << " s";
    }
  }
  // The clearing after 5 s (patience counted from the first failed cycle), the turn 5 s later.
  EXPECT_GT(first_turn, 10.0);
  EXPECT_LT(first_turn, 10.3);
  EXPECT_GT(dwa.navStack().plansMade(), 100);
  EXPECT_EQ(dwa.navStack().plansMade(), dwa.navStack().plansFailed());
}

TEST(Dwa, RejectsUnknownConfigKeysAndBadValues) {
  DwaConfig config;
  config.max_vel_x = -1.0;
  core::Errors errors;
  validate(config, errors, "dwa");
  ASSERT_FALSE(errors.empty());
  EXPECT_NE(errors.messages().front().find("dwa.max_vel_x"), std::string::npos);
}

// A DWA on the open field of commandFor's map with the goal at `goal`.
struct OpenField {
  explicit OpenField(const Eigen::Vector2d& goal) : dwa(config()) {
    info.goal = goal;
    info.lidar.mount_x = 0.0;
    dwa.reset(info);
  }
  static DwaConfig config() {
    DwaConfig c;
    c.nav.global_costmap.origin_x = -3.0;
    c.nav.global_costmap.origin_y = -3.0;
    c.nav.global_costmap.width = 10.0;
    c.nav.global_costmap.height = 6.0;
    return c;
  }
  // One tick at time 0.05 k from rest, a fresh empty scan.
  core::Twist tick(int k) {
    scan = scanOf({});
    scan.stamp = 0.05 * k;
    Observation obs;
    obs.time = 0.05 * k;
    obs.scan = &scan;
    obs.goal = info.goal;
    return dwa.act(obs);
  }
  EpisodeInfo info;
  core::LaserScan scan;
  DwaController dwa;
};

TEST(Dwa, TakesNewSampleCountsWhileRunning) {
  // The goal ahead and to the left: the best arc turns left. From rest the yaw-rate window is
  // [-1, 1] (20 rad/s^2 x 0.05 s). With 5 samples the arcs try 0 and -1, -0.5, 0, 0.5 (the top
  // is never tried) and the rotations +-1: whatever wins is a multiple of 0.5. With BARN's 20
  // the step is 2 / 19 and the left turn is not.
  OpenField field({3.0, 2.0});
  core::Twist cmd;
  for (int k = 0; k < 3; ++k) cmd = field.tick(k);
  EXPECT_GT(cmd.angular, 0.0);
  EXPECT_NE(std::fmod(cmd.angular, 0.5), 0.0);
  field.dwa.setParameter("vtheta_samples", 5);
  EXPECT_EQ(field.dwa.parameters().vtheta_samples, 5);
  cmd = field.tick(3);
  EXPECT_EQ(cmd.angular, 0.5);
  // Two samples: the arcs try 0 and -1 only, and no rotation is wider than the step 2: straight on.
  field.dwa.setParameter("vtheta_samples", 2);
  cmd = field.tick(4);
  EXPECT_EQ(cmd.angular, 0.0);
}

TEST(Dwa, TakesANewTopSpeedUntilReset) {
  // Straight ahead in the open the fastest sample wins: the window from rest is [0.1, 0.5], and
  // with max_vel_x 0.3 it is [0.1, 0.3].
  OpenField field({6.0, 0.0});
  field.dwa.setParameter("max_vel_x", 0.3);
  core::Twist cmd;
  for (int k = 0; k < 3; ++k) cmd = field.tick(k);
  EXPECT_NEAR(cmd.linear, 0.3, 1e-9);
  field.dwa.reset(field.info);
  EXPECT_EQ(field.dwa.parameters().max_vel_x, 0.5);
  for (int k = 0; k < 3; ++k) cmd = field.tick(k);
  EXPECT_NEAR(cmd.linear, 0.5, 1e-9);
}

TEST(Dwa, PassesTheStacksKeysOnAndRefusesBadValues) {
  OpenField field({6.0, 0.0});
  field.tick(0);
  // The inflation radius reaches the global costmap at its next update (10 Hz: tick 2).
  field.dwa.setParameter("global_costmap.inflation_radius", 0.6);
  field.tick(1);
  field.tick(2);
  EXPECT_EQ(field.dwa.navStack().globalCostmap().config().inflation_radius, 0.6);
  const auto refusal = [&](const char* key, double value) {
    try {
      field.dwa.setParameter(key, value);
    } catch (const std::invalid_argument& e) {
      return std::string(e.what());
    }
    return std::string();
  };
  EXPECT_THAT(refusal("vx_samples", 1), ::testing::HasSubstr("dwa.vx_samples: must be >= 2"));
  EXPECT_THAT(refusal("vtheta_samples", 7.5), ::testing::HasSubstr("vtheta_samples: must be a whole number"));
  EXPECT_THAT(refusal("max_vel_x", 0.05), ::testing::HasSubstr("dwa.min_vel_x"));  // below min_vel_x 0.1
  EXPECT_THAT(refusal("pdist_scale", -1.0), ::testing::HasSubstr("dwa.pdist_scale: must be >= 0, got -1"));
  EXPECT_THAT(refusal("sim_time", 1.0),
              ::testing::AllOf(::testing::HasSubstr("not a settable parameter"), ::testing::HasSubstr("vx_samples"),
                               ::testing::HasSubstr("local_costmap.inflation_radius")));
  // A refused value leaves the parameters as they were.
  EXPECT_EQ(field.dwa.parameters().vx_samples, 6);
}

}  // namespace
}  // namespace barn::controllers
