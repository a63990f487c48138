// The units a controller config file states for its keys (figure axes of `barn sweep`).

#include "report/config_units.hpp"

#include <filesystem>
#include <fstream>
#include <random>
#include <string>

#include <gtest/gtest.h>

namespace barn::report {
namespace {

namespace fs = std::filesystem;

// The shape of configs/controllers/*.yaml: a type, its block, a nested block, units in brackets.
constexpr char kConfig[] = R"(# A controller.
type: inventec
inventec:
  max_speed: 0.7               # [m/s] paper and code: speed clip 0.7
  heading_tolerance_deg: 10    # code: HardTurn -> LfLH below 10 deg
  heading_gain: 1.5            # [1/s] code
  mix: 0.5                     # [-] a share
  safety:
    type: front                # code
    front_pad_x: 0.01          # [m] code: 0.215 + 0.01 each side
  footprint_width: 0.43
)";

class ConfigUnits : public ::testing::Test {
 protected:
  void SetUp() override {
    file_ = fs::temp_directory_path() / ("barn_config_units_" + std::to_string(std::random_device{}()) + ".yaml");
    std::ofstream(file_) << kConfig;
  }
  void TearDown() override { fs::remove(file_); }
  fs::path file_;
};

TEST_F(ConfigUnits, ReadsTheBracketOpeningAKeysComment) {
  EXPECT_EQ(configKeyUnit(file_, "max_speed"), "m/s");
  EXPECT_EQ(configKeyUnit(file_, "heading_gain"), "1/s");
}

TEST_F(ConfigUnits, FollowsNestedBlocksWithOrWithoutTheTypeInFront) {
  EXPECT_EQ(configKeyUnit(file_, "safety.front_pad_x"), "m");
  EXPECT_EQ(configKeyUnit(file_, "inventec.safety.front_pad_x"), "m");
  EXPECT_EQ(configKeyUnit(file_, "front_pad_x"), "") << "a nested key needs its block";
}

TEST_F(ConfigUnits, IsEmptyWhenNoUnitIsStated) {
  EXPECT_EQ(configKeyUnit(file_, "heading_tolerance_deg"), "") << "a comment without brackets";
  EXPECT_EQ(configKeyUnit(file_, "footprint_width"), "") << "no comment";
  EXPECT_EQ(configKeyUnit(file_, "mix"), "") << "[-]: dimensionless";
  EXPECT_EQ(configKeyUnit(file_, "no_such_key"), "");
  EXPECT_EQ(configKeyUnit(file_.string() + ".missing", "max_speed"), "");
}

TEST(ConfigUnitsOfTheRepository, PurePursuitStatesItsSpeedAndLookahead) {
  const fs::path file = fs::path(BARN_SOURCE_DIR) / "configs" / "controllers" / "pure_pursuit.yaml";
  EXPECT_EQ(configKeyUnit(file, "speed"), "m/s");
  EXPECT_EQ(configKeyUnit(file, "lookahead"), "m");
}

}  // namespace
}  // namespace barn::report
