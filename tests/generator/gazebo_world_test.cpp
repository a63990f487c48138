// The exported .world file: its cylinders, read back from the SDF text, are exactly the world's
// obstacles (core::allCylinders), static, of BARN's size.

#include "generator/gazebo_world.hpp"

#include <gmock/gmock.h>
#include <gtest/gtest.h>

#include <algorithm>
#include <cstdlib>
#include <filesystem>
#include <set>
#include <string>
#include <vector>

#include <Eigen/Core>

#include "barn/core/world_file.hpp"
#include "barn/core/world_geometry.hpp"
#include "generator/dataset_files.hpp"

namespace barn::generator {
namespace {

using testing::HasSubstr;

const std::filesystem::path kWorlds = std::filesystem::path(BARN_SOURCE_DIR) / "worlds";

/// The text between the first `open` and the next `close` at or after `from`; empty if none.
std::string between(const std::string& text, const std::string& open, const std::string& close, std::size_t from = 0) {
  const std::size_t start = text.find(open, from);
  if (start == std::string::npos) return "";
  const std::size_t end = text.find(close, start + open.size());
  if (end == std::string::npos) return "";
  return text.substr(start + open.size(), end - start - open.size());
}

/// Every occurrence of <tag>VALUE</tag> in `text`.
std::vector<std::string> tagValues(const std::string& text, const std::string& tag) {
  std::vector<std::string> values;
  const std::string open = "<" + tag + ">";
  const std::string close = "</" + tag + ">";
  for (std::size_t at = text.find(open); at != std::string::npos; at = text.find(open, at + 1))
    values.push_back(between(text, open, close, at));
  return values;
}

/// One <model> of the SDF, as a simple text scan sees it.
struct ScannedModel {
  std::string name;
  std::string text;  // everything between <model ...> and </model>
};

std::vector<ScannedModel> scanModels(const std::string& sdf) {
  std::vector<ScannedModel> models;
  const std::string open = "<model name='";
  for (std::size_t at = sdf.find(open); at != std::string::npos; at = sdf.find(open, at + 1)) {
    const std::size_t name_end = sdf.find('\'', at + open.size());
    const std::size_t end = sdf.find("</model>", at);
    models.push_back({sdf.substr(at + open.size(), name_end - at - open.size()), sdf.substr(at, end - at)});
  }
  return models;
}

/// Points sorted for a set comparison; centres lie 0.075 m apart or more, so the tolerance of
/// the comparison cannot pair the wrong points.
std::vector<Eigen::Vector2d> sorted(std::vector<Eigen::Vector2d> points) {
  std::sort(points.begin(), points.end(), [](const auto& a, const auto& b) {
    return a.x() < b.x() - 1e-6 || (std::abs(a.x() - b.x()) <= 1e-6 && a.y() < b.y());
  });
  return points;
}

/// Checks the .world text of `world` against core::allCylinders; returns the cylinder models.
std::vector<ScannedModel> expectCylindersOf(const core::WorldSpec& world, const std::string& sdf) {
  std::vector<ScannedModel> cylinders;
  std::vector<Eigen::Vector2d> poses;
  std::set<std::string> names;
  for (const ScannedModel& m : scanModels(sdf)) {
    EXPECT_TRUE(names.insert(m.name).second) << "model name " << m.name << " twice";
    if (m.name == "ground_plane") continue;
    cylinders.push_back(m);
    EXPECT_EQ(tagValues(m.text, "static"), std::vector<std::string>{"1"}) << m.name;
    EXPECT_EQ(tagValues(m.text, "radius"), (std::vector<std::string>{"0.075", "0.075"})) << m.name << ": collision and visual";
    EXPECT_EQ(tagValues(m.text, "length"), (std::vector<std::string>{"1", "1"})) << m.name;
    EXPECT_EQ(tagValues(m.text, "mass"), std::vector<std::string>{"1"}) << m.name;
    EXPECT_EQ(tagValues(m.text, "ixx"), std::vector<std::string>{"0.145833"}) << m.name;
    EXPECT_EQ(tagValues(m.text, "iyy"), std::vector<std::string>{"0.145833"}) << m.name;
    EXPECT_EQ(tagValues(m.text, "izz"), std::vector<std::string>{"0.125"}) << m.name;
    const std::vector<std::string> pose = tagValues(m.text, "pose");
    EXPECT_EQ(pose.size(), 1u) << m.name;
    if (pose.size() != 1) continue;
    char* end = nullptr;
    const double x = std::strtod(pose[0].c_str(), &end);
    const double y = std::strtod(end, &end);
    EXPECT_STREQ(end, " 0 0 0 0") << m.name << ": standing on z = 0, upright";
    poses.emplace_back(x, y);
  }
  const std::vector<Eigen::Vector2d> expected = sorted(core::allCylinders(world.grid));
  const std::vector<Eigen::Vector2d> got = sorted(poses);
  EXPECT_EQ(got.size(), expected.size()) << "world " << world.id;
  for (std::size_t i = 0; i < std::min(got.size(), expected.size()); ++i) {
    EXPECT_NEAR(got[i].x(), expected[i].x(), 1e-9) << "world " << world.id << " cylinder " << i;
    EXPECT_NEAR(got[i].y(), expected[i].y(), 1e-9) << "world " << world.id << " cylinder " << i;
  }
  return cylinders;
}

TEST(GazeboWorld, CylindersOfEveryCommittedWorldAreExactlyItsObstacles) {
  for (const core::WorldSpec& world : core::readWorldSet(kWorlds)) {
    expectCylindersOf(world, formatGazeboWorld(world));
    if (testing::Test::HasFailure()) FAIL() << "first failing world: " << world.id;
  }
}

TEST(GazeboWorld, WallsAreBlueAndTheFieldRed) {
  const core::WorldSpec world = core::readWorldFile(kWorlds / core::worldFileName(0));
  const auto cylinders = expectCylindersOf(world, formatGazeboWorld(world));
  std::size_t walls = 0, field = 0;
  for (const ScannedModel& m : cylinders) {
    const auto ambient = tagValues(m.text, "ambient");
    ASSERT_EQ(ambient.size(), 1u) << m.name;
    EXPECT_EQ(tagValues(m.text, "diffuse"), ambient) << m.name;
    if (ambient[0] == "0.152 0.379 0.720 1") ++walls;
    else if (ambient[0] == "0.648 0.192 0.192 1") ++field;
    else ADD_FAILURE() << m.name << ": colour " << ambient[0];
  }
  // 30 back-wall cylinders + 2 x 33 side-wall cylinders.
  EXPECT_EQ(walls, 96u);
  EXPECT_EQ(field, core::fieldCylinders(world.grid).size());
}

TEST(GazeboWorld, HasTheCompetitionWorldsPhysicsAndGround) {
  const core::WorldSpec world = core::readWorldFile(kWorlds / core::worldFileName(0));
  const std::string sdf = formatGazeboWorld(world);
  EXPECT_THAT(sdf, HasSubstr("<sdf version='1.6'>"));
  EXPECT_THAT(sdf, HasSubstr("<physics name='default_physics' default='0' type='ode'>"));
  EXPECT_EQ(tagValues(sdf, "max_step_size"), std::vector<std::string>{"0.001"});
  EXPECT_EQ(tagValues(sdf, "real_time_update_rate"), std::vector<std::string>{"1000"});
  EXPECT_EQ(tagValues(sdf, "real_time_factor"), std::vector<std::string>{"1"});
  EXPECT_EQ(tagValues(sdf, "gravity"), std::vector<std::string>{"0 0 -9.8"});
  EXPECT_THAT(sdf, HasSubstr("<light name='sun' type='directional'>"));
  const std::string ground = between(sdf, "<model name='ground_plane'>", "</model>");
  EXPECT_EQ(tagValues(ground, "size"), (std::vector<std::string>{"100 100", "100 100"}));
  EXPECT_EQ(tagValues(ground, "mu"), std::vector<std::string>{"100"});
  EXPECT_EQ(tagValues(ground, "mu2"), std::vector<std::string>{"50"});
}

TEST(GazeboWorld, HarnessFilesAreTheWorldAndItsPathFile) {
  const core::WorldSpec world = core::readWorldFile(kWorlds / core::worldFileName(7));
  const auto files = harnessFiles({world});
  ASSERT_EQ(files.size(), 2u);
  EXPECT_EQ(files[0].name, "world_7.world");
  EXPECT_EQ(files[0].content, formatGazeboWorld(world));
  EXPECT_EQ(files[1].name, datasetFile(kPathFiles, 7).string());
  EXPECT_EQ(files[1].name, "path_files/path_7.npy");
}

}  // namespace
}  // namespace barn::generator
