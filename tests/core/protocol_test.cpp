#include "barn/core/protocol.hpp"

#include <gmock/gmock.h>
#include <gtest/gtest.h>

#include <cmath>
#include <filesystem>
#include <string>
#include <vector>

#include "barn/core/errors.hpp"
#include "barn/core/npy.hpp"

namespace barn::core {
namespace {

namespace fs = std::filesystem;
using testing::ElementsAre;
using testing::HasSubstr;

const fs::path kDatasetDir = fs::path(BARN_SOURCE_DIR) / ".." / "shared" / "barn_dataset";

/// The message of the InputError thrown by protocolPreset(name), or "" if none was thrown.
std::string presetError(const std::string& name) {
  try {
    protocolPreset(name);
  } catch (const InputError& e) {
    return e.what();
  }
  return "";
}

/// A path along grid row `row` from column 0 to 29, start cell duplicated as in BARN.
std::vector<Cell> straightPath(int row) {
  std::vector<Cell> path{{row, 0}};
  for (int c = 0; c < kBarnGridSize; ++c) path.push_back({row, c});
  return path;
}

// ---------------------------------------------------------------------------------------------
// Presets

TEST(Protocol, NamesListTheDefaultFirst) {
  EXPECT_THAT(protocolNames(), ElementsAre("barn2023", "barn2024"));
}

TEST(Protocol, Barn2023StartsAtXMinus2AndClipsAtFourTimesOT) {
  const Protocol p = protocolPreset("barn2023");
  EXPECT_EQ(p.name, ProtocolName::Barn2023);
  EXPECT_DOUBLE_EQ(p.start().x(), -2.0);
  EXPECT_DOUBLE_EQ(p.start().y(), 3.0);
  EXPECT_DOUBLE_EQ(p.start_yaw, 1.57);  // run.py's 1.57, not pi/2
  // Goal = start + (0, 10) = (-2, 13).
  EXPECT_DOUBLE_EQ(p.goal().x(), -2.0);
  EXPECT_DOUBLE_EQ(p.goal().y(), 13.0);
  EXPECT_DOUBLE_EQ(p.clip_low, 4.0);
  EXPECT_DOUBLE_EQ(p.clip_high, 8.0);
  EXPECT_DOUBLE_EQ(p.success_radius, 1.0);
  EXPECT_DOUBLE_EQ(p.timeout, 100.0);
}

TEST(Protocol, Barn2024StartsOnTheCorridorCentreAndClipsAtTwiceOT) {
  const Protocol p = protocolPreset("barn2024");
  EXPECT_EQ(p.name, ProtocolName::Barn2024);
  EXPECT_DOUBLE_EQ(p.start().x(), -2.25);
  EXPECT_DOUBLE_EQ(p.start().y(), 3.0);
  // Goal = start + (0, 10) = (-2.25, 13).
  EXPECT_DOUBLE_EQ(p.goal().x(), -2.25);
  EXPECT_DOUBLE_EQ(p.goal().y(), 13.0);
  EXPECT_DOUBLE_EQ(p.clip_low, 2.0);
  EXPECT_DOUBLE_EQ(p.clip_high, 8.0);
}

TEST(Protocol, TheScoreScaleEndsAtOneOverTheLowerClip) {
  // A success at or under clip_low * OT scores OT / (clip_low OT); at or over 8 OT, 1 / 8.
  EXPECT_DOUBLE_EQ(protocolPreset("barn2023").maxScore(), 0.25);
  EXPECT_DOUBLE_EQ(protocolPreset("barn2024").maxScore(), 0.5);
  EXPECT_DOUBLE_EQ(protocolPreset("barn2023").minSuccessScore(), 0.125);
  const Protocol p = protocolPreset("barn2024");
  EXPECT_DOUBLE_EQ(barnScore(true, 0.5, 10.0, p), p.maxScore());
  EXPECT_DOUBLE_EQ(barnScore(true, 1000.0, 10.0, p), p.minSuccessScore());
}

TEST(Protocol, UnknownPresetThrowsInputErrorNamingIt) {
  EXPECT_THROW(protocolPreset("barn2025"), InputError);
  EXPECT_THAT(presetError("barn2025"), HasSubstr("barn2025"));
  EXPECT_THAT(presetError(""), HasSubstr("unknown protocol"));
}

// ---------------------------------------------------------------------------------------------
// Reference path and OT

TEST(OtPathPoint, UsesRunPyOffsetsNotTheCellCentres) {
  // x = -4.575 + 0.15 r, y = 5.075 + 0.15 c.
  EXPECT_DOUBLE_EQ(otPathPoint({0, 0}).x(), -4.575);
  EXPECT_DOUBLE_EQ(otPathPoint({0, 0}).y(), 5.075);
  // (15, 29): x = -4.575 + 2.25 = -2.325, y = 5.075 + 4.35 = 9.425.
  EXPECT_NEAR(otPathPoint({15, 29}).x(), -2.325, 1e-12);
  EXPECT_NEAR(otPathPoint({15, 29}).y(), 9.425, 1e-12);
}

TEST(ReferencePathLength, StraightPathInLineWithStartAndGoalIsTenMetres) {
  // Row 15 lies at x = -4.575 + 0.15 * 15 = -2.325. With the start moved onto that line the
  // polyline is straight: start (-2.325, 3) -> (-2.325, 5.075) [2.075 m] -> duplicate [0 m]
  // -> 29 steps of 0.15 m to y = 9.425 [4.35 m] -> goal (-2.325, 13) [3.575 m] = 10.0 m.
  Protocol p = protocolPreset("barn2023");
  p.start_x = -2.325;
  EXPECT_NEAR(referencePathLength(straightPath(15), p), 10.0, 1e-12);
  // OT = 10 m / 2 m/s = 5 s.
  EXPECT_NEAR(optimalTime(straightPath(15), p), 5.0, 1e-12);
}

TEST(ReferencePathLength, StraightPathFromTheBarn2023StartAddsTwoSlantedEnds) {
  // Start (-2, 3) is 0.325 m off row 15's line x = -2.325:
  //   first leg  sqrt(0.325^2 + 2.075^2) = sqrt(4.41125)  = 2.1002976
  //   middle     29 * 0.15                                = 4.35
  //   last leg   sqrt(0.325^2 + 3.575^2) = sqrt(12.88625) = 3.5897423
  //   total                                               = 10.0400399
  const Protocol p = protocolPreset("barn2023");
  const double expected = std::sqrt(4.41125) + 4.35 + std::sqrt(12.88625);
  EXPECT_NEAR(expected, 10.0400399, 1e-7);
  EXPECT_NEAR(referencePathLength(straightPath(15), p), expected, 1e-12);
  EXPECT_NEAR(optimalTime(straightPath(15), p), expected / 2.0, 1e-12);
}

TEST(ReferencePathLength, EmptyPathIsStartToGoal) {
  // No path cells: the polyline is start -> goal = 10 m.
  EXPECT_NEAR(referencePathLength({}, protocolPreset("barn2024")), 10.0, 1e-12);
}

TEST(ReferencePathLength, ReproducesBarnWorld108) {
  // run.py's OT for world 108 of the original dataset has L = 10.66037 m
  // (start x = -2), confirmed against the 2022 dwa_out.txt AT/OT column.
  const fs::path file = kDatasetDir / "path_files" / "path_108.npy";
  if (!fs::exists(file)) GTEST_SKIP() << "BARN dataset not found at " << kDatasetDir << " (needs path_files/path_108.npy)";
  const NpyInt64Array array = readNpyInt64(file);
  ASSERT_EQ(array.shape.size(), 2u);
  ASSERT_EQ(array.shape[1], 2u);
  std::vector<Cell> path;
  for (std::size_t i = 0; i < array.shape[0]; ++i)
    path.push_back({static_cast<int>(array.values[2 * i]), static_cast<int>(array.values[2 * i + 1])});
  ASSERT_EQ(path.size(), 31u);
  EXPECT_EQ(path[0], path[1]);  // BARN's duplicated start
  const Protocol p = protocolPreset("barn2023");
  EXPECT_NEAR(referencePathLength(path, p), 10.66037, 1e-5);
  // OT = 10.66037 / 2 = 5.330185 s.
  EXPECT_NEAR(optimalTime(path, p), 5.330185, 1e-5);
}

// ---------------------------------------------------------------------------------------------
// Score: success * OT / clip(AT, clip_low * OT, 8 * OT)

TEST(BarnScore, FailureScoresZeroHoweverFast) {
  const Protocol p = protocolPreset("barn2023");
  EXPECT_EQ(barnScore(false, 5.0, 5.0, p), 0.0);
  EXPECT_EQ(barnScore(false, 30.0, 5.0, p), 0.0);
}

TEST(BarnScore, RunFasterThanTheLowerClipScoresTheCap) {
  // OT = 5 s, AT = 10 s = 2 OT.
  //   barn2023: clip(10, 20, 40) = 20 -> 5 / 20 = 0.25
  //   barn2024: clip(10, 10, 40) = 10 -> 5 / 10 = 0.5
  EXPECT_DOUBLE_EQ(barnScore(true, 10.0, 5.0, protocolPreset("barn2023")), 0.25);
  EXPECT_DOUBLE_EQ(barnScore(true, 10.0, 5.0, protocolPreset("barn2024")), 0.5);
  // Even faster (AT = 1 s < OT) still scores the cap, never more.
  EXPECT_DOUBLE_EQ(barnScore(true, 1.0, 5.0, protocolPreset("barn2023")), 0.25);
  EXPECT_DOUBLE_EQ(barnScore(true, 1.0, 5.0, protocolPreset("barn2024")), 0.5);
  // barn2023 at exactly AT = 4 OT = 20 s: 5 / 20 = 0.25 as well.
  EXPECT_DOUBLE_EQ(barnScore(true, 20.0, 5.0, protocolPreset("barn2023")), 0.25);
}

TEST(BarnScore, RunBetweenTheClipsScoresOTOverAT) {
  // AT = 6 OT = 30 s lies inside both clip ranges: 5 / 30 = 1/6.
  EXPECT_DOUBLE_EQ(barnScore(true, 30.0, 5.0, protocolPreset("barn2023")), 1.0 / 6.0);
  EXPECT_DOUBLE_EQ(barnScore(true, 30.0, 5.0, protocolPreset("barn2024")), 1.0 / 6.0);
  // barn2024 only: AT = 3 OT = 15 s -> 5 / 15 = 1/3 (barn2023 would clip it to 0.25).
  EXPECT_DOUBLE_EQ(barnScore(true, 15.0, 5.0, protocolPreset("barn2024")), 1.0 / 3.0);
  EXPECT_DOUBLE_EQ(barnScore(true, 15.0, 5.0, protocolPreset("barn2023")), 0.25);
}

TEST(BarnScore, SlowSuccessfulRunScoresTheFloorOfOneEighth) {
  // AT = 50 s > 8 OT = 40 s: clip to 40 -> 5 / 40 = 0.125, in both editions.
  EXPECT_DOUBLE_EQ(barnScore(true, 50.0, 5.0, protocolPreset("barn2023")), 0.125);
  EXPECT_DOUBLE_EQ(barnScore(true, 50.0, 5.0, protocolPreset("barn2024")), 0.125);
  // A run at the 100 s timeout limit that still succeeded: also 0.125.
  EXPECT_DOUBLE_EQ(barnScore(true, 100.0, 5.0, protocolPreset("barn2023")), 0.125);
}

}  // namespace
}  // namespace barn::core
