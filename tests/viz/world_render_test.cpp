#include "barn/viz/world_render.hpp"

#include <algorithm>
#include <array>
#include <cmath>
#include <cstdint>
#include <filesystem>
#include <fstream>
#include <iterator>
#include <random>
#include <string>
#include <vector>

#include <gmock/gmock.h>
#include <gtest/gtest.h>

#include "barn/core/errors.hpp"
#include "barn/core/protocol.hpp"
#include "barn/core/world.hpp"
#include "image_check.hpp"

namespace barn::viz {
namespace {

namespace fs = std::filesystem;
using ::testing::HasSubstr;

// Obstacle rows of a tiny world: rows 0 and 29 are the corridor's side walls, plus a 3 x 3 blob
// (hollow centre, so it has both drawn and skipped cylinders) and one lone cell.
core::WorldSpec tinyWorld() {
  core::WorldSpec world;
  world.id = 7;
  world.fill_pct = 0.15;
  world.smooth_iter = 4;
  world.grid = core::Grid(30, 30);
  for (int c = 0; c < 30; ++c) {
    world.grid.at(0, c) = 1;
    world.grid.at(29, c) = 1;
  }
  for (int r = 10; r <= 12; ++r) {
    for (int c = 10; c <= 12; ++c) world.grid.at(r, c) = 1;
  }
  world.grid.at(20, 5) = 1;
  world.start_cell = {15, 0};
  world.goal_cell = {15, 29};
  world.path = {{15, 0}, {15, 0}, {15, 1}, {16, 2}, {16, 3}};  // start cell duplicated, as BARN
  return world;
}

using test::bigEndian32;
using test::readBytes;
using test::Size;

// Image size as the header documents it: view box = corridor x [-4.5, 0], y [0, 9.6] united
// with the goal disc, plus a 0.6 m margin per side.
Size expectedSize(const core::Protocol& protocol, double ppm) {
  const double goal_x = protocol.start_x + protocol.goal_dx;
  const double goal_y = protocol.start_y + protocol.goal_dy;
  const double r = protocol.success_radius;
  const double min_x = std::min(-4.5, goal_x - r);
  const double max_x = std::max(0.0, goal_x + r);
  const double min_y = std::min(0.0, goal_y - r);
  const double max_y = std::max(9.6, goal_y + r);
  return {std::lround((max_x - min_x + 1.2) * ppm), std::lround((max_y - min_y + 1.2) * ppm)};
}

class WorldRenderTest : public ::testing::Test {
 protected:
  void SetUp() override {
    // Unique per test and per run, so parallel ctest jobs never share a file.
    const std::string name = ::testing::UnitTest::GetInstance()->current_test_info()->name();
    const std::string tag = std::to_string(std::random_device{}());
    png_path_ = fs::temp_directory_path() / ("barn_world_render_" + name + "_" + tag + ".png");
    missing_dir_ = fs::temp_directory_path() / ("barn_world_render_missing_" + tag);
  }
  void TearDown() override {
    std::error_code ignored;
    fs::remove(png_path_, ignored);
  }

  fs::path png_path_;     // output of the test
  fs::path missing_dir_;  // never created
};

TEST_F(WorldRenderTest, WritesPngFile) {
  renderWorld(tinyWorld(), core::protocolPreset("barn2023"), png_path_);

  ASSERT_TRUE(fs::exists(png_path_));
  const std::vector<unsigned char> bytes = readBytes(png_path_);
  ASSERT_GE(bytes.size(), 24u);
  const std::array<unsigned char, 8> signature = {0x89, 'P', 'N', 'G', '\r', '\n', 0x1A, '\n'};
  EXPECT_TRUE(std::equal(signature.begin(), signature.end(), bytes.begin()));
  EXPECT_EQ(std::string(bytes.begin() + 12, bytes.begin() + 16), "IHDR");
}

TEST_F(WorldRenderTest, ImageSizeFollowsPixelsPerMetre) {
  const core::Protocol protocol = core::protocolPreset("barn2023");
  for (const double ppm : {120.0, 37.5}) {
    RenderOptions options;
    options.pixels_per_metre = ppm;
    renderWorld(tinyWorld(), protocol, png_path_, options);

    const std::vector<unsigned char> bytes = readBytes(png_path_);
    ASSERT_GE(bytes.size(), 24u);
    const Size expected = expectedSize(protocol, ppm);
    EXPECT_EQ(bigEndian32(bytes, 16), static_cast<std::uint32_t>(expected.width)) << ppm;
    EXPECT_EQ(bigEndian32(bytes, 20), static_cast<std::uint32_t>(expected.height)) << ppm;
  }
}

TEST_F(WorldRenderTest, DefaultSizeAt120PixelsPerMetre) {
  // Goal (-2, 13) m with a 1 m disc: x [-4.5, 0], y [0, 14] m.
  // (4.5 + 1.2) m * 120 px/m = 684 px; (14 + 1.2) m * 120 px/m = 1824 px.
  renderWorld(tinyWorld(), core::protocolPreset("barn2024"), png_path_);

  const std::vector<unsigned char> bytes = readBytes(png_path_);
  ASSERT_GE(bytes.size(), 24u);
  EXPECT_EQ(bigEndian32(bytes, 16), 684u);
  EXPECT_EQ(bigEndian32(bytes, 20), 1824u);
}

TEST_F(WorldRenderTest, ViewGrowsToKeepAFartherGoalInThePicture) {
  core::Protocol protocol = core::protocolPreset("barn2023");
  protocol.goal_dy = 12.0;  // goal at y = 15 m, disc to 16 m
  RenderOptions options;
  options.pixels_per_metre = 50.0;
  renderWorld(tinyWorld(), protocol, png_path_, options);

  const std::vector<unsigned char> bytes = readBytes(png_path_);
  ASSERT_GE(bytes.size(), 24u);
  // (16 + 1.2) m * 50 px/m = 860 px
  EXPECT_EQ(bigEndian32(bytes, 20), 860u);
  EXPECT_EQ(bigEndian32(bytes, 20),
            static_cast<std::uint32_t>(expectedSize(protocol, 50.0).height));
}

TEST_F(WorldRenderTest, RendersWithoutContainmentOrPathAndWithEmptyPath) {
  core::WorldSpec world = tinyWorld();
  world.path.clear();
  RenderOptions options;
  options.show_containment = false;
  options.show_path = false;
  renderWorld(world, core::protocolPreset("barn2023"), png_path_, options);
  EXPECT_TRUE(fs::exists(png_path_));
}

TEST_F(WorldRenderTest, ThrowsIoErrorNamingThePathWhenDirectoryIsMissing) {
  ASSERT_FALSE(fs::exists(missing_dir_));
  const fs::path target = missing_dir_ / "world.png";
  try {
    renderWorld(tinyWorld(), core::protocolPreset("barn2023"), target);
    FAIL() << "expected core::IoError";
  } catch (const core::IoError& e) {
    EXPECT_THAT(e.what(), HasSubstr(target.string()));
    EXPECT_THAT(e.what(), HasSubstr("cannot write"));
  }
  EXPECT_FALSE(fs::exists(target));
}

TEST_F(WorldRenderTest, RejectsNonPositivePixelsPerMetre) {
  RenderOptions options;
  options.pixels_per_metre = 0.0;
  EXPECT_THROW(renderWorld(tinyWorld(), core::protocolPreset("barn2023"), png_path_, options),
               core::InputError);
  EXPECT_FALSE(fs::exists(png_path_));
}

TEST_F(WorldRenderTest, RejectsImagesLargerThanCairoAllows) {
  RenderOptions options;
  options.pixels_per_metre = 3000.0;  // (4.5 + 1.2) m * 3000 px/m = 17100 px wide, 45600 px high
  try {
    renderWorld(tinyWorld(), core::protocolPreset("barn2023"), png_path_, options);
    FAIL() << "expected core::InputError";
  } catch (const core::InputError& e) {
    EXPECT_THAT(e.what(), HasSubstr("45600"));
  }
  EXPECT_FALSE(fs::exists(png_path_));
}

}  // namespace
}  // namespace barn::viz
