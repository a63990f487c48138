#include "barn/sim/simulator.hpp"

#include <cmath>

#include <gtest/gtest.h>

namespace barn::sim {
namespace {

// Traction limit of the default Jackal: mu g = 0.5 * 9.81 = 4.905 m/s^2.
constexpr double kTraction = 0.5 * 9.81;

// Runs `seconds` of simulated time with the command re-sent every physics step.
void drive(Simulator& sim, core::Twist cmd, double seconds) {
  const long steps = std::lround(seconds / sim.dt());
  for (long k = 0; k < steps; ++k) {
    sim.command(cmd);
    sim.step();
  }
}

TEST(PlantHash, TellsPlantsApart) {
  core::RobotConfig robot;
  PhysicsConfig physics;
  const std::uint64_t plain = plantHash(robot, physics);
  EXPECT_NE(plain, 0u);  // 0 means unknown
  EXPECT_EQ(plantHash(core::RobotConfig{}, PhysicsConfig{}), plain);
  robot.icr_offset = 0.037;
  EXPECT_NE(plantHash(robot, physics), plain);
  physics.rate = 1000.0;
  EXPECT_NE(plantHash({}, physics), plain);
  EXPECT_NE(plantHash({}, physics), plantHash(robot, physics));
}

TEST(Simulator, AcceleratesNoFasterThanTractionAndTheSpeedLimit) {
  const ObstacleField empty;
  Simulator sim(empty, core::RobotConfig{}, PhysicsConfig{}, {0.0, 0.0, 0.0});
  double previous = 0.0;
  for (int k = 0; k < 200; ++k) {  // 1 s at 200 Hz
    sim.command({3.0, 0.0});       // above the 2 m/s limit
    sim.step();
    const double v = sim.forwardSpeed();
    EXPECT_LE(v - previous, kTraction * sim.dt() + 1e-6) << "step " << k;
    EXPECT_LE(v, 2.0 + 1e-6);
    previous = v;
  }
  // 2 m/s / 4.905 m/s^2 = 0.408 s to full speed, so after 1 s it cruises at the limit.
  EXPECT_NEAR(sim.forwardSpeed(), 2.0, 1e-6);
}

TEST(Simulator, YawRateFollowsTheControllerAccelerationLimit) {
  const ObstacleField empty;
  Simulator sim(empty, core::RobotConfig{}, PhysicsConfig{}, {0.0, 0.0, 0.0});
  sim.command({0.0, 10.0});  // clamped to 4 rad/s
  sim.step();
  // 25 rad/s^2 * 0.005 s = 0.125 rad/s after one step (traction allows 40 rad/s^2).
  EXPECT_NEAR(sim.yawRate(), 0.125, 1e-9);
  drive(sim, {0.0, 10.0}, 0.5);
  EXPECT_NEAR(sim.yawRate(), 4.0, 1e-9);
}

TEST(Simulator, WithoutTurnSlipOrPivotATurnInPlaceStaysOnTheSpot) {
  const ObstacleField empty;
  core::RobotConfig robot;
  robot.turn_slip_speed = 0.0;
  robot.icr_offset = 0.0;
  Simulator sim(empty, robot, PhysicsConfig{}, {1.0, 2.0, 0.3}, 7);
  drive(sim, {0.0, 1.5}, 5.0);
  EXPECT_NEAR(sim.pose().x, 1.0, 1e-6);
  EXPECT_NEAR(sim.pose().y, 2.0, 1e-6);
}

TEST(Simulator, TurnSlipMakesATurningBodyWanderReproduciblyPerSeed) {
  // 5 s at 1.5 rad/s with 0.02 m/s of slip per rad/s: slip speed stddev 0.03 m/s, correlated
  // over 0.5 s, so the body wanders a few centimetres (random walk ~ sqrt(2 0.03^2 0.5 5) =
  // 0.047 m), never metres; the same seed wanders the same way, another seed differently.
  core::RobotConfig robot;
  robot.turn_slip_speed = 0.02;
  const ObstacleField empty;
  const auto wander = [&](std::uint64_t seed) {
    Simulator sim(empty, robot, PhysicsConfig{}, {0.0, 0.0, 0.0}, seed);
    drive(sim, {0.0, 1.5}, 5.0);
    return sim.pose().position();
  };
  const Eigen::Vector2d a = wander(1), again = wander(1), b = wander(2);
  EXPECT_GT(a.norm(), 1e-4);
  EXPECT_LT(a.norm(), 0.5);
  EXPECT_EQ(a, again);
  EXPECT_NE(a, b);
  // Driving straight (no yaw rate) is untouched by turn slip.
  Simulator straight(empty, robot, PhysicsConfig{}, {0.0, 0.0, 0.0}, 3);
  drive(straight, {0.5, 0.0}, 2.0);
  EXPECT_NEAR(straight.pose().y, 0.0, 1e-9);
}

TEST(Simulator, APivotAheadOfTheCentreSwingsTheCentreRoundIt) {
  // Pivot 0.131 m ahead (the front axle): a quarter turn to the left about it carries the centre
  // along a circle of radius 0.131 m around the pivot's start position (0.131, 0) — from angle pi
  // to 3 pi / 2, i.e. to (0.131, -0.131). The traction limit (4.9 m/s^2) easily supplies the
  // 0.131 x 1 rad/s of slide, so the result is exact up to the start-up of the yaw rate.
  core::RobotConfig robot;
  robot.turn_slip_speed = 0.0;
  robot.icr_offset = 0.131;
  const ObstacleField empty;
  Simulator sim(empty, robot, PhysicsConfig{}, {0.0, 0.0, 0.0});
  drive(sim, {0.0, 1.0}, std::acos(-1.0) / 2);
  const double turned = sim.pose().yaw;
  EXPECT_NEAR(turned, std::acos(-1.0) / 2, 0.03);  // the yaw rate takes 0.04 s to build up
  // Wherever the turn stopped, the centre is 0.131 m behind the pivot along the heading.
  EXPECT_NEAR(sim.pose().x, 0.131 - 0.131 * std::cos(turned), 2e-3);
  EXPECT_NEAR(sim.pose().y, -0.131 * std::sin(turned), 2e-3);
}

// Commanded to a speed, then to 0: the wheels stop within 0.1 s (20 m/s^2) but the body
// slides at the traction limit, covering v^2 / (2 mu g).
double stoppingDistance(double speed) {
  const ObstacleField empty;
  Simulator sim(empty, core::RobotConfig{}, PhysicsConfig{}, {0.0, 0.0, 0.0});
  drive(sim, {speed, 0.0}, 2.0);
  const double x0 = sim.pose().x;
  drive(sim, {0.0, 0.0}, 2.0);
  EXPECT_NEAR(sim.forwardSpeed(), 0.0, 1e-9);
  return sim.pose().x - x0;
}

TEST(Simulator, BrakingFromTwoMetresPerSecondSlidesAsTractionPredicts) {
  // 2^2 / (2 * 4.905) = 0.4077 m; the discrete integration is short by up to v dt = 0.01 m.
  const double from_fast = stoppingDistance(2.0);
  EXPECT_NEAR(from_fast, 4.0 / (2.0 * kTraction), 0.011);
  // 0.7^2 / (2 * 4.905) = 0.0499 m: eight times shorter.
  const double from_slow = stoppingDistance(0.7);
  EXPECT_NEAR(from_slow, 0.49 / (2.0 * kTraction), 0.004);
  EXPECT_GT(from_fast, 5.0 * from_slow);
}

TEST(Simulator, StopsWhenCommandsStopArriving) {
  const ObstacleField empty;
  Simulator sim(empty, core::RobotConfig{}, PhysicsConfig{}, {0.0, 0.0, 0.0});
  sim.command({1.0, 0.0});
  for (int k = 0; k < 400; ++k) sim.step();  // 2 s without a new command
  // Driven for 0.25 s (accelerating at 4.905 m/s^2 for 0.204 s to 1 m/s), then braked.
  EXPECT_NEAR(sim.forwardSpeed(), 0.0, 1e-9);
  EXPECT_LT(sim.pose().x, 0.25 * 1.0 + 1.0 / (2.0 * kTraction));
  EXPECT_GT(sim.pose().x, 0.1);
}

TEST(Simulator, DrivingIntoACylinderIsACollisionAtTheFrontBumper) {
  // Cylinder on the driving line at x = 2: contact when the chassis front (x + 0.21) meets
  // its surface at 2 - 0.075, i.e. robot centre x = 1.715.
  ObstacleField field;
  field.centres = {{2.0, 0.0}};
  Simulator sim(field, core::RobotConfig{}, PhysicsConfig{}, {0.0, 0.0, 0.0});
  while (!sim.collision() && sim.time() < 10.0) {
    sim.command({0.5, 0.0});
    sim.step();
  }
  ASSERT_TRUE(sim.collision());
  EXPECT_EQ(sim.collision()->point, Eigen::Vector2d(2.0, 0.0));
  EXPECT_EQ(sim.collision()->rect_index, 0);  // the chassis
  // At 0.5 m/s a step moves 2.5 mm, so contact is found within one step past 1.715.
  EXPECT_GE(sim.pose().x, 1.715 - 1e-6);
  EXPECT_LT(sim.pose().x, 1.715 + 0.0026);
}

TEST(Simulator, CirclesWithTheirOwnRadiiCollideAtTheirOwnSurface) {
  // The small circle (r 0.05) beside the path is passed; the large one (r 0.5) ahead is hit
  // when the chassis front (x + 0.21) meets its surface at 3 - 0.5, i.e. centre x = 2.29.
  ObstacleField field;
  field.centres = {{1.0, 0.4}, {3.0, 0.0}};
  field.radii = {0.05, 0.5};
  Simulator sim(field, core::RobotConfig{}, PhysicsConfig{}, {0.0, 0.0, 0.0});
  while (!sim.collision() && sim.time() < 10.0) {
    sim.command({0.5, 0.0});
    sim.step();
  }
  ASSERT_TRUE(sim.collision());
  EXPECT_EQ(sim.collision()->point, Eigen::Vector2d(3.0, 0.0));
  EXPECT_GE(sim.pose().x, 2.29 - 1e-6);
  EXPECT_LT(sim.pose().x, 2.29 + 0.0026);
}

// The widest part of the Jackal is the wheels' outer side at y = 0.187795 + 0.02 = 0.207795.
double sideClearanceRun(double gap) {
  ObstacleField field;
  field.centres = {{1.5, 0.207795 + 0.075 + gap}};
  Simulator sim(field, core::RobotConfig{}, PhysicsConfig{}, {0.0, 0.0, 0.0});
  drive(sim, {1.0, 0.0}, 3.0);
  return sim.collision() ? 1.0 : 0.0;
}

TEST(Simulator, BrushingPastACylinderIsNoCollisionButTouchingIs) {
  EXPECT_EQ(sideClearanceRun(0.01), 0.0);    // 1 cm clear
  EXPECT_EQ(sideClearanceRun(0.002), 0.0);   // 2 mm: inside Box2D's 1 cm polygon skin, still clear
  EXPECT_EQ(sideClearanceRun(-0.002), 1.0);  // 2 mm overlap
}

TEST(Simulator, RectangleCircleOverlapIsExactAtCorners) {
  const core::Rect rect = core::Rect::centred(0.42, 0.31);
  const core::Pose2 pose{0.0, 0.0, 0.0};
  // A circle on the corner's diagonal: the corner (0.21, 0.155) is at distance
  // |c - corner| from the centre; overlap iff that is < r.
  const Eigen::Vector2d corner(0.21, 0.155);
  const Eigen::Vector2d dir = Eigen::Vector2d(1.0, 1.0).normalized();
  EXPECT_FALSE(rectOverlapsCircle(pose, rect, corner + dir * (0.075 + 1e-9), 0.075));
  EXPECT_TRUE(rectOverlapsCircle(pose, rect, corner + dir * (0.075 - 1e-9), 0.075));
  // Rotated by 90 degrees the long side lies along y.
  const core::Pose2 turned{0.0, 0.0, M_PI / 2};
  EXPECT_TRUE(rectOverlapsCircle(turned, rect, {0.0, 0.21 + 0.07}, 0.075));
  EXPECT_FALSE(rectOverlapsCircle(turned, rect, {0.21 + 0.07, 0.0}, 0.075));
}

TEST(Simulator, SameCommandsGiveTheSamePoseBitForBit) {
  ObstacleField field;
  field.centres = {{5.0, 5.0}};
  const auto run = [&] {
    Simulator sim(field, core::RobotConfig{}, PhysicsConfig{}, {0.1, 0.2, 0.3});
    for (int k = 0; k < 1000; ++k) {
      sim.command({1.5 * std::sin(0.01 * k), 2.0 * std::cos(0.013 * k)});
      sim.step();
    }
    return sim.pose();
  };
  const core::Pose2 a = run();
  const core::Pose2 b = run();
  EXPECT_EQ(a.x, b.x);
  EXPECT_EQ(a.y, b.y);
  EXPECT_EQ(a.yaw, b.yaw);
}

TEST(Simulator, TurningAtSpeedSlidesSideways) {
  // At 2 m/s and 4 rad/s the centripetal demand v w = 8 m/s^2 exceeds mu g = 4.9 m/s^2, so
  // the body cannot follow the heading: a sideways velocity appears.
  const ObstacleField empty;
  Simulator sim(empty, core::RobotConfig{}, PhysicsConfig{}, {0.0, 0.0, 0.0});
  drive(sim, {2.0, 0.0}, 1.0);
  drive(sim, {2.0, 4.0}, 0.3);
  EXPECT_GT(std::abs(sim.sidewaysSpeed()), 0.1);
}

}  // namespace
}  // namespace barn::sim
