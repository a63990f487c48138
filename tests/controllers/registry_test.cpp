#include "barn/controllers/registry.hpp"

#include <gmock/gmock.h>
#include <gtest/gtest.h>

#include <cmath>
#include <filesystem>
#include <numbers>
#include <set>
#include <string>
#include <vector>

#include "barn/controllers/pure_pursuit.hpp"
#include "barn/controllers/straight.hpp"
#include "barn/core/errors.hpp"

namespace barn::controllers {
namespace {

using ::testing::AllOf;
using ::testing::Contains;
using ::testing::HasSubstr;
using ::testing::IsEmpty;

core::ConfigNode yaml(const std::string& text) { return core::ConfigNode::parseString(text, "run.yaml"); }

/// The message of the InputError makeControllerFactory throws for `text`, or "" if none.
std::string factoryError(const std::string& text) {
  try {
    makeControllerFactory(yaml(text));
  } catch (const core::InputError& e) {
    return e.what();
  }
  return "";
}

TEST(ControllerRegistry, EveryShippedConfigBuildsAKnownTypeAndEveryTypeShipsOne) {
  const std::vector<std::string> types = controllerTypes();
  EXPECT_EQ(std::set<std::string>(types.begin(), types.end()).size(), types.size()) << "a type listed twice";
  std::set<std::string> shipped_types;
  for (const auto& entry : std::filesystem::directory_iterator(std::string(BARN_SOURCE_DIR) + "/configs/controllers")) {
    if (entry.path().extension() != ".yaml") continue;
    const core::ConfigNode config = core::ConfigNode::parseFile(entry.path().string());
    std::string type;
    config.child("type").read(type);
    EXPECT_THAT(types, Contains(type)) << entry.path();
    shipped_types.insert(type);
    try {
      makeControllerFactory(config);
    } catch (const core::InputError& e) {
      // A controller whose published network is not shipped (lics, applr_dwa) fails, until the
      // user converts their copy, only by naming the import command.
      EXPECT_THAT(e.what(), HasSubstr("tools/import_")) << entry.path();
    }
  }
  // Each type but `external` (which runs the user's own program) has a ready-made config.
  for (const std::string& type : types) {
    if (type == "external") continue;
    EXPECT_TRUE(shipped_types.count(type)) << type << " has no configs/controllers/*.yaml";
  }
}

TEST(ControllerRegistry, TheShippedBaselineConfigsHoldTheCodesDefaults) {
  // These files say their values are the code's defaults (the BARN baselines and the teams' values
  // as published): their effective configs equal the bare type's.
  for (const char* name : {"dwa", "eband", "kulfm", "pure_pursuit", "straight", "rrsl_vfh", "in2bot", "ut_amrl",
                           "almeria_tps", "meco"}) {
    const std::string file = std::string(BARN_SOURCE_DIR) + "/configs/controllers/" + name + ".yaml";
    const core::ConfigNode shipped = core::ConfigNode::parseFile(file);
    std::string type;
    shipped.child("type").read(type);
    EXPECT_EQ(effectiveControllerConfig(shipped),
              effectiveControllerConfig(core::ConfigNode::parseString("type: " + type, "defaults")))
        << file;
  }
}

TEST(ControllerRegistry, MakesAStraightController) {
  const ControllerFactory factory = makeControllerFactory(yaml("type: straight\nstraight: {speed: 0.8, rate: 10}"));
  const auto controller = factory();
  ASSERT_NE(controller, nullptr);
  EXPECT_NE(dynamic_cast<StraightController*>(controller.get()), nullptr);
  // 1 / 10 Hz = 0.1 s.
  EXPECT_DOUBLE_EQ(controller->period(), 0.1);
}

TEST(ControllerRegistry, MakesAPurePursuitControllerWithDefaults) {
  const ControllerFactory factory = makeControllerFactory(yaml("type: pure_pursuit"));
  const auto controller = factory();
  EXPECT_NE(dynamic_cast<PurePursuitController*>(controller.get()), nullptr);
  // Default rate 20 Hz: 0.05 s.
  EXPECT_DOUBLE_EQ(controller->period(), 0.05);
}

TEST(ControllerRegistry, FactoryMakesAFreshControllerEachCall) {
  const ControllerFactory factory = makeControllerFactory(yaml("type: straight"));
  const auto a = factory();
  const auto b = factory();
  EXPECT_NE(a.get(), b.get());
}

TEST(ControllerRegistry, UnknownTypeNamesItAndListsTheKnownOnes) {
  const std::string error = factoryError("type: teb");
  EXPECT_THAT(error, AllOf(HasSubstr("unknown controller 'teb'"), HasSubstr("straight"), HasSubstr("pure_pursuit")));
  EXPECT_THAT(error, HasSubstr("run.yaml: type"));
}

TEST(ControllerRegistry, MissingTypeIsAnError) {
  EXPECT_THAT(factoryError("straight: {speed: 1}"), HasSubstr("type: missing"));
  EXPECT_THAT(factoryError("type: [1, 2]"), HasSubstr("type: expected a string"));
}

TEST(ControllerRegistry, UnknownKeyInTheBlockIsNamedWithItsPath) {
  const std::string error = factoryError("type: pure_pursuit\npure_pursuit: {speedd: 1}");
  EXPECT_THAT(error, HasSubstr("pure_pursuit.speedd"));
  EXPECT_THAT(error, HasSubstr("unknown key"));
  // The message lists the keys that do exist.
  EXPECT_THAT(error, HasSubstr("speed, lookahead, rate"));
}

TEST(ControllerRegistry, OutOfRangeValueIsNamedWithItsPath) {
  EXPECT_THAT(factoryError("type: pure_pursuit\npure_pursuit: {speed: -0.5}"),
              HasSubstr("pure_pursuit.speed: must be > 0"));
  EXPECT_THAT(factoryError("type: straight\nstraight: {heading_gain: 0}"),
              HasSubstr("straight.heading_gain: must be > 0"));
}

TEST(ControllerRegistry, AnOutOfRangeValueNamesItsUnit) {
  EXPECT_THAT(factoryError("type: dwa\ndwa: {max_vel_x: -0.5}"),
              HasSubstr("run.yaml: dwa.max_vel_x: must be > 0 m/s, got -0.5 m/s"));
}

TEST(ControllerRegistry, AKeysUnitComesFromTheConfigStruct) {
  // What a sweep's axis shows: DwaConfig's visit() states max_vel_x in m/s.
  EXPECT_EQ(controllerKeyUnit("dwa", "max_vel_x"), "m/s");
  EXPECT_EQ(controllerKeyUnit("dwa", "dwa.acc_lim_theta"), "rad/s^2");
  EXPECT_EQ(controllerKeyUnit("dwa", "vx_samples"), "");  // a count
  EXPECT_EQ(controllerKeyUnit("dwa", "no_such_key"), "");
  EXPECT_EQ(controllerKeyUnit("no_such_type", "speed"), "");
}

TEST(ControllerRegistry, TheSchemaHoldsTheConfigsValues) {
  const std::vector<core::FieldRow> rows = controllerSchema(yaml("type: pure_pursuit\npure_pursuit: {speed: 0.75}"));
  ASSERT_EQ(rows.size(), 3u);
  EXPECT_EQ(rows[0].key, "speed");
  EXPECT_EQ(rows[0].value, "0.75");
  EXPECT_EQ(rows[0].unit, "m/s");
  EXPECT_EQ(rows[0].range, "> 0");
}

TEST(ControllerRegistry, EveryProblemIsReportedAtOnce) {
  const std::string error = factoryError("type: straight\nstraight: {speed: -1, rate: 0}");
  EXPECT_THAT(error, AllOf(HasSubstr("straight.speed"), HasSubstr("straight.rate")));
}

TEST(ControllerRegistry, WrongValueTypeIsAnError) {
  EXPECT_THAT(factoryError("type: straight\nstraight: {speed: fast}"), HasSubstr("straight.speed: expected a finite number"));
}

TEST(ControllerRegistry, StrayTopLevelKeyIsAnError) {
  // A block for another controller, or a typo, next to the chosen one.
  EXPECT_THAT(factoryError("type: straight\npure_pursuit: {speed: 1}"),
              AllOf(HasSubstr("run.yaml: pure_pursuit"), HasSubstr("unknown key")));
  EXPECT_THAT(factoryError("type: straight\nsped: 1"), HasSubstr("run.yaml: sped"));
}

TEST(ControllerRegistry, EffectiveConfigListsEveryField) {
  EXPECT_EQ(effectiveControllerConfig(yaml("type: pure_pursuit\npure_pursuit: {speed: 0.75}")),
            "type: pure_pursuit\n"
            "pure_pursuit:\n"
            "  speed: 0.75\n"
            "  lookahead: 0.5\n"
            "  rate: 20\n");
  EXPECT_EQ(effectiveControllerConfig(yaml("type: straight")),
            "type: straight\n"
            "straight:\n"
            "  speed: 1\n"
            "  heading_gain: 2\n"
            "  rate: 20\n");
}

TEST(ControllerRegistry, EffectiveConfigIsValidatedToo) {
  EXPECT_THROW(effectiveControllerConfig(yaml("type: straight\nstraight: {speed: -1}")), core::InputError);
}

// ---------------------------------------------------------------------------------------------
// The straight controller's control law

core::Twist straightAct(const core::Pose2& pose, const Eigen::Vector2d& goal, const StraightConfig& config = {}) {
  StraightController controller(config);
  EpisodeInfo info;
  info.goal = goal;
  controller.reset(info);
  Observation obs;
  obs.odom_pose = pose;
  obs.goal = goal;
  return controller.act(obs);
}

TEST(StraightController, DrivesAtFullSpeedWhenFacingTheGoal) {
  // Robot at the origin facing +y, goal 10 m ahead: heading error 0.
  const core::Twist cmd = straightAct({0.0, 0.0, std::numbers::pi / 2}, {0.0, 10.0});
  EXPECT_DOUBLE_EQ(cmd.linear, 1.0);
  EXPECT_NEAR(cmd.angular, 0.0, 1e-12);
}

TEST(StraightController, TurnsInPlaceWhenTheGoalIsBehind) {
  // Facing +x, goal at (-5, 1): bearing atan2(1, -5) = 2.944 rad to the left; cos < 0, so no
  // forward motion; 2 * 2.944 = 5.9 rad/s clamps to the 4 rad/s limit.
  const core::Twist left = straightAct({0.0, 0.0, 0.0}, {-5.0, 1.0});
  EXPECT_EQ(left.linear, 0.0);
  EXPECT_DOUBLE_EQ(left.angular, 4.0);
  // Mirrored: turns right.
  const core::Twist right = straightAct({0.0, 0.0, 0.0}, {-5.0, -1.0});
  EXPECT_EQ(right.linear, 0.0);
  EXPECT_DOUBLE_EQ(right.angular, -4.0);
}

TEST(StraightController, SlowsDownWithTheHeadingError) {
  // Goal at 45 degrees to the left: linear 1 * cos(pi/4) = 0.7071, angular 2 * pi/4 = 1.5708.
  const core::Twist cmd = straightAct({0.0, 0.0, 0.0}, {5.0, 5.0});
  EXPECT_NEAR(cmd.linear, std::cos(std::numbers::pi / 4), 1e-12);
  EXPECT_NEAR(cmd.angular, 2.0 * std::numbers::pi / 4, 1e-12);
}

TEST(StraightController, RespectsTheRobotsAngularLimit) {
  StraightController controller({});
  EpisodeInfo info;
  info.robot.max_angular_speed = 1.0;
  controller.reset(info);
  Observation obs;
  obs.goal = {-5.0, 1.0};  // behind-left of a robot at the origin facing +x
  EXPECT_DOUBLE_EQ(controller.act(obs).angular, 1.0);
}

TEST(ControllerRegistry, ADuplicateTopLevelKeyIsRefusedNotTheFirstTaken) {
  EXPECT_THAT(factoryError("type: pure_pursuit\ntype: straight\n"), HasSubstr("type: duplicate key"));
  EXPECT_THAT(factoryError("type: pure_pursuit\npure_pursuit: {speed: 0.5}\npure_pursuit: {speed: 1.9}\n"),
              HasSubstr("pure_pursuit: duplicate key"));
}

}  // namespace
}  // namespace barn::controllers
