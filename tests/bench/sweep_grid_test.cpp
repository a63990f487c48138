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

// A sweep folder of its own, removed afterwards.
class SweepFile : public ::testing::Test {
 protected:
  void SetUp() override {
    std::random_device device;
    dir_ = std::filesystem::temp_directory_path() / ("barn_sweep_grid_test_" + std::to_string(device()));
    std::filesystem::create_directories(dir_);
  }
  void TearDown() override { std::filesystem::remove_all(dir_); }
  SweepGrid readBack(const std::string& text) {
    std::ofstream(dir_ / kSweepFile) << text;
    return readSweepFile(dir_);
  }
  std::filesystem::path dir_;
};

TEST_F(SweepFile, RoundTrips) {
  const SweepGrid grid = makeSweepGrid("inventec_fi", {parseSweepParameter("safety.front_pad_y=0.0,0.04"),
                                                       parseSweepParameter("max_speed=1.0,2.0"),
                                                       parseSweepParameter("label=a b,\"q\",true,null")});
  const SweepGrid back = readBack(formatSweepFile(grid));
  EXPECT_EQ(back.controller, grid.controller);
  ASSERT_EQ(back.parameters.size(), 3u);
  EXPECT_EQ(back.parameters[0].key, "safety.front_pad_y");
  EXPECT_EQ(back.parameters[0].values, grid.parameters[0].values);  // "0.0" stays "0.0", not 0
  EXPECT_EQ(back.parameters[1].values, grid.parameters[1].values);
  EXPECT_EQ(back.parameters[2].values, grid.parameters[2].values);  // strings that look like YAML
  EXPECT_EQ(back.cells, grid.cells);
  EXPECT_EQ(formatSweepFile(back), formatSweepFile(grid));
}

TEST_F(SweepFile, AFileWrittenByEarlierVersionsStillReads) {
  // Every string quoted, one cell per line.
  const SweepGrid back = readBack(R"(# barnbench sweep: one run record per cell in the folders below
controller: "dwa"
parameters:
  - key: "max_vel_x"
    values: ["0.5", "1"]
cells:
  - "cell_0_max_vel_x=0.5"
  - "cell_1_max_vel_x=1"
)");
  EXPECT_EQ(back.controller, "dwa");
  ASSERT_EQ(back.parameters.size(), 1u);
  EXPECT_EQ(back.parameters[0].key, "max_vel_x");
  EXPECT_THAT(back.parameters[0].values, ElementsAre("0.5", "1"));
  EXPECT_THAT(back.cells, ElementsAre("cell_0_max_vel_x=0.5", "cell_1_max_vel_x=1"));
}

TEST_F(SweepFile, AMalformedFieldIsAnErrorNamingIt) {
  EXPECT_THAT([&] { readBack("controller: dwa\nparameters:\n  - key: a\n    values: {x: 1}\n"); },
              ThrowsMessage<core::InputError>(HasSubstr("sweep.yaml: parameters[0].values: expected a list of strings")));
  EXPECT_THAT([&] { readBack("controller: dwa\nparameters: 3\n"); },
              ThrowsMessage<core::InputError>(HasSubstr("sweep.yaml: parameters: expected a list of maps")));
  EXPECT_THAT([&] { readBack("controller: dwa\ncels: []\n"); },
              ThrowsMessage<core::InputError>(HasSubstr("sweep.yaml: cels: unknown key")));
}

TEST_F(SweepFile, CellsThatAreNotTheGridOfItsParametersAreRefused) {
  // A cell folder is never taken from the file unchecked ("../../elsewhere" would resume a
  // record outside the sweep).
  const std::string head = "controller: dwa\nparameters:\n  - key: a\n    values: [\"1\", \"2\"]\n";
  EXPECT_NO_THROW(readBack(head + "cells: [cell_0_a=1, cell_1_a=2]\n"));
  for (const char* cells : {"cells: [cell_0_a=1]\n", "cells: [cell_0_a=1, ../../elsewhere]\n", "cells: []\n"})
    EXPECT_THAT([&] { readBack(head + cells); }, ThrowsMessage<core::InputError>(HasSubstr("cells: not the cells"))) << cells;
  EXPECT_THAT([&] { readBack("controller: dwa\ncells: []\n"); },
              ThrowsMessage<core::InputError>(HasSubstr("parameters: missing")));
}

TEST(SweepGrid, ACellCountThatWouldOverflowIsTooManyNotFew) {
  // 64 parameters of 2 values: 2^64 cells, which a size_t product would wrap to 0.
  std::vector<SweepParameter> parameters;
  for (int k = 0; k < 64; ++k) parameters.push_back(parseSweepParameter("k" + std::to_string(k) + "=1,2"));
  EXPECT_THAT([&] { makeSweepGrid("dwa", parameters); }, ThrowsMessage<core::InputError>(HasSubstr("too many")));
}

}  // namespace
}  // namespace barn::bench
