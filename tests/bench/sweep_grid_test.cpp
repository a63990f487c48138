#include "barn/bench/sweep_grid.hpp"

#include <gmock/gmock.h>
#include <gtest/gtest.h>

#include <filesystem>
#include <fstream>
#include <random>

#include "barn/core/errors.hpp"

namespace barn::bench {
namespace {

using ::testing::ElementsAre;
using ::testing::HasSubstr;
using ::testing::ThrowsMessage;

TEST(SweepGrid, ParsesKeyAndValues) {
  const SweepParameter p = parseSweepParameter("max_speed=1.0,1.5,2");
  EXPECT_EQ(p.key, "max_speed");
  EXPECT_THAT(p.values, ElementsAre("1.0", "1.5", "2"));
  for (const char* bad : {"max_speed", "=1,2", "max_speed=", "max_speed=1,,2"})
    EXPECT_THAT([&] { parseSweepParameter(bad); }, ThrowsMessage<core::InputError>(HasSubstr(bad))) << bad;
}

TEST(SweepGrid, CellsRunLikeAnOdometerLastParameterFastest) {
  const SweepGrid grid = makeSweepGrid("dwa", {parseSweepParameter("a=1,2"), parseSweepParameter("b=x,y,z")});
  EXPECT_THAT(grid.cells, ElementsAre("cell_0_a=1_b=x", "cell_1_a=1_b=y", "cell_2_a=1_b=z", "cell_3_a=2_b=x",
                                      "cell_4_a=2_b=y", "cell_5_a=2_b=z"));
  EXPECT_THAT(cellValues(grid, 4), ElementsAre("2", "y"));
}

TEST(SweepGrid, RefusesAKeyTwiceAndTooManyCells) {
  EXPECT_THAT([] { makeSweepGrid("dwa", {parseSweepParameter("a=1"), parseSweepParameter("a=2")}); },
              ThrowsMessage<core::InputError>(HasSubstr("given twice")));
  std::string many = "a=";
  for (int i = 0; i < 101; ++i) many += (i ? "," : "") + std::to_string(i);
  EXPECT_THAT([&] { makeSweepGrid("dwa", {parseSweepParameter(many), parseSweepParameter("b" + many.substr(1))}); },
              ThrowsMessage<core::InputError>(HasSubstr("too many")));
}

TEST(SweepGrid, CellConfigSetsTheValuesInTheTypesBlock) {
  const SweepGrid grid = makeSweepGrid("pure_pursuit", {parseSweepParameter("speed=0.5,1.0"),
                                                        parseSweepParameter("pure_pursuit.lookahead=0.3,0.6")});
  const core::ConfigNode base = core::ConfigNode::parseString("type: pure_pursuit\npure_pursuit:\n  speed: 0.2\n", "base");
  const core::ConfigNode cell = cellConfig(grid, base, 1);
  double speed = 0.0, lookahead = 0.0;
  cell.child("pure_pursuit").child("speed").read(speed);
  cell.child("pure_pursuit").child("lookahead").read(lookahead);
  EXPECT_DOUBLE_EQ(speed, 0.5);
  EXPECT_DOUBLE_EQ(lookahead, 0.6);
}

TEST(SweepGrid, SweepFileRoundTrips) {
  std::random_device device;
  const auto dir = std::filesystem::temp_directory_path() / ("barn_sweep_grid_test_" + std::to_string(device()));
  std::filesystem::create_directories(dir);
  const SweepGrid grid = makeSweepGrid("inventec_fi", {parseSweepParameter("safety.front_pad_y=0.0,0.04"),
                                                       parseSweepParameter("max_speed=1.0,2.0")});
  std::ofstream(dir / kSweepFile) << formatSweepFile(grid);
  const SweepGrid back = readSweepFile(dir);
  std::filesystem::remove_all(dir);
  EXPECT_EQ(back.controller, grid.controller);
  ASSERT_EQ(back.parameters.size(), 2u);
  EXPECT_EQ(back.parameters[0].key, "safety.front_pad_y");
  EXPECT_EQ(back.parameters[1].values, grid.parameters[1].values);
  EXPECT_EQ(back.cells, grid.cells);
}

}  // namespace
}  // namespace barn::bench
