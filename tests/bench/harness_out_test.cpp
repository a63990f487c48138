// The official harness's results file: parsing, outcomes, recomputed scores, the nav_metric
// check and the line format (bench/harness_out.hpp).

#include "barn/bench/harness_out.hpp"

#include <gmock/gmock.h>
#include <gtest/gtest.h>

#include <cmath>

#include "barn/core/errors.hpp"

namespace barn::bench {
namespace {

using ::testing::HasSubstr;

// A world whose A* path is empty: the reference polyline is start -> goal, 10 m straight, so
// OT = 10 m / 2 m/s = 5 s under both presets (barn2024 moves start and goal together).
core::WorldSpec straightWorld(int id) {
  core::WorldSpec w;
  w.id = id;
  return w;
}

std::string errorOf(const std::string& text) {
  try {
    parseHarnessOut(text, "dwa_out.txt");
  } catch (const core::InputError& e) {
    return e.what();
  }
  return "";
}

TEST(HarnessOut, ParsesRunPyLines) {
  const auto lines = parseHarnessOut(
      "108 1 0 0 22.2800 4.1806\n"
      "\n"
      "0\t0  0 1 100.0110 0.0000\r\n"
      "126 0 1 0 22.5700 0.0000",  // no final newline
      "f");
  ASSERT_EQ(lines.size(), 3u);
  EXPECT_EQ(lines[0].line, 1);
  EXPECT_EQ(lines[0].world_id, 108);
  EXPECT_TRUE(lines[0].success);
  EXPECT_DOUBLE_EQ(lines[0].time, 22.28);
  EXPECT_DOUBLE_EQ(lines[0].nav_metric, 4.1806);
  EXPECT_EQ(lines[1].line, 3);  // the blank line 2 is skipped but counted
  EXPECT_TRUE(lines[1].timeout);
  EXPECT_EQ(harnessOutcome(lines[1]), Outcome::Timeout);
  EXPECT_EQ(lines[2].line, 4);
  EXPECT_EQ(harnessOutcome(lines[2]), Outcome::Collision);
  EXPECT_EQ(harnessOutcome(lines[0]), Outcome::Success);
}

TEST(HarnessOut, OutcomeFollowsRunPysStatusOrder) {
  HarnessLine both;
  both.collided = both.timeout = true;  // contact seen at the 100 s check: run.py says "collided"
  EXPECT_EQ(harnessOutcome(both), Outcome::Collision);
  HarnessLine none;  // never written by run.py; read as a failure without contact
  EXPECT_EQ(harnessOutcome(none), Outcome::Timeout);
}

TEST(HarnessOut, MalformedLinesNameFileLineAndField) {
  const std::string good = "0 1 0 0 20.0000 0.2500\n";
  EXPECT_THAT(errorOf(good + "6 1 0 0 20.0\n"), HasSubstr("dwa_out.txt:2: line: expected 6 fields"));
  EXPECT_THAT(errorOf(good + good + "x 1 0 0 20.0 0.25\n"), HasSubstr("dwa_out.txt:3: world_idx: 'x'"));
  EXPECT_THAT(errorOf("-1 1 0 0 20.0 0.25\n"), HasSubstr(":1: world_idx"));
  EXPECT_THAT(errorOf("0 2 0 0 20.0 0.25\n"), HasSubstr(":1: success: '2' is not 0 or 1"));
  EXPECT_THAT(errorOf("0 0 yes 0 20.0 0.25\n"), HasSubstr(":1: collided"));
  EXPECT_THAT(errorOf("0 1 1 0 20.0 0.25\n"), HasSubstr(":1: success: set together"));
  EXPECT_THAT(errorOf("0 1 0 0 nan 0.25\n"), HasSubstr(":1: time: 'nan'"));
  EXPECT_THAT(errorOf("0 1 0 0 -3 0.25\n"), HasSubstr(":1: time"));
  EXPECT_THAT(errorOf("0 1 0 0 20.0 inf\n"), HasSubstr(":1: nav_metric: 'inf'"));
  EXPECT_THAT(errorOf("0 1 0 0 20.0 0.25x\n"), HasSubstr(":1: nav_metric"));
  EXPECT_THAT(errorOf("\n \n"), HasSubstr("dwa_out.txt: no result lines"));
}

TEST(HarnessOut, ScoreIsRecomputedFromTheWorldsOptimalTime) {
  // OT = 5 s (straightWorld). Success at AT = 15 s:
  //   barn2023 (k = 4): clip(15, 4*5 = 20, 8*5 = 40) = 20 -> score 5 / 20 = 0.25
  //   barn2024 (k = 2): clip(15, 2*5 = 10, 40)        = 15 -> score 5 / 15 = 0.3333
  // Success at AT = 50 s: clip(50, ., 40) = 40 -> 5 / 40 = 0.125 under both.
  // A collision scores 0 whatever its time.
  const auto lines = parseHarnessOut("3 1 0 0 15.0000 0.2500\n3 1 0 0 50.0000 0.1250\n3 0 1 0 7.0000 0.0000\n", "f");
  const std::vector<core::WorldSpec> worlds = {straightWorld(3)};
  const HarnessImport k4 = importHarnessLines(lines, worlds, core::protocolPreset("barn2023"), "f");
  ASSERT_EQ(k4.results.size(), 3u);
  EXPECT_DOUBLE_EQ(k4.results[0].optimal_time, 5.0);
  EXPECT_DOUBLE_EQ(k4.results[0].score, 0.25);
  EXPECT_DOUBLE_EQ(k4.results[1].score, 0.125);
  EXPECT_EQ(k4.results[2].score, 0.0);
  EXPECT_EQ(k4.results[2].outcome, Outcome::Collision);
  EXPECT_EQ(k4.check.score_mismatches, 0);
  const HarnessImport k2 = importHarnessLines(lines, worlds, core::protocolPreset("barn2024"), "f");
  EXPECT_DOUBLE_EQ(k2.results[0].optimal_time, 5.0);
  EXPECT_DOUBLE_EQ(k2.results[0].score, 5.0 / 15.0);
  EXPECT_DOUBLE_EQ(k2.results[1].score, 0.125);
  // The check is on the protocol's own scale: this file's first line holds the k = 4 score.
  EXPECT_EQ(k2.check.score_mismatches, 1);
}

TEST(HarnessOut, TrialsAreNumberedPerWorldInFileOrderAndUnknownFieldsAreNaN) {
  const auto lines = parseHarnessOut("5 1 0 0 30 0.1667\n3 0 0 1 100.01 0\n5 0 0 0 40 0\n3 1 0 0 20 0.25\n", "f");
  const HarnessImport imported =
      importHarnessLines(lines, {straightWorld(3), straightWorld(5)}, core::protocolPreset("barn2023"), "f");
  ASSERT_EQ(imported.results.size(), 4u);
  EXPECT_EQ(imported.results[0].world_id, 5);
  EXPECT_EQ(imported.results[0].trial, 0);
  EXPECT_EQ(imported.results[1].trial, 0);
  EXPECT_EQ(imported.results[2].trial, 1);
  EXPECT_EQ(imported.results[2].outcome, Outcome::Timeout);  // no flag set
  EXPECT_EQ(imported.results[3].trial, 1);
  EXPECT_EQ(imported.unflagged, 1);
  EXPECT_EQ(imported.world_ids, (std::vector<int>{3, 5}));
  EXPECT_EQ(imported.max_trials, 2);
  EXPECT_EQ(imported.min_trials, 2);
  EXPECT_TRUE(std::isnan(imported.results[0].path_length));
  EXPECT_TRUE(std::isnan(imported.results[0].mean_speed));
  EXPECT_TRUE(std::isnan(imported.results[0].sim_time));
  EXPECT_EQ(imported.results[0].seed, 0u);
}

TEST(HarnessOut, WorldMissingFromTheFolderNamesTheLine) {
  const auto lines = parseHarnessOut("3 1 0 0 20 0.25\n4 1 0 0 20 0.25\n", "dwa_out.txt");
  try {
    importHarnessLines(lines, {straightWorld(3)}, core::protocolPreset("barn2023"), "dwa_out.txt");
    ADD_FAILURE() << "no InputError";
  } catch (const core::InputError& e) {
    EXPECT_THAT(e.what(), HasSubstr("dwa_out.txt:2: world_idx: world 4 is not in the world folder"));
  }
}

TEST(HarnessOut, NavMetricCheckRecognisesTheTimeRatio) {
  // OT = 5 s. Line 1 holds the k = 4 score (0.25); line 2 holds AT / OT = 30 / 5 = 6 (what the
  // 2022 harness wrote); line 3 holds neither.
  const auto lines = parseHarnessOut("3 1 0 0 15 0.25\n3 1 0 0 30 6.0000\n3 1 0 0 30 0.9\n", "f");
  const HarnessImport imported = importHarnessLines(lines, {straightWorld(3)}, core::protocolPreset("barn2023"), "f");
  EXPECT_EQ(imported.check.lines, 3);
  EXPECT_EQ(imported.check.score_mismatches, 2);
  EXPECT_EQ(imported.check.ratio_matches, 1);
  EXPECT_EQ(imported.check.worst_line, 2);
  EXPECT_NEAR(imported.check.max_score_difference, 6.0 - 5.0 / 30.0, 1e-12);
}

TEST(HarnessOut, NavMetricIsCheckedOnTheProtocolsOwnScale) {
  // OT = 5 s, AT = 15 s: k = 4 clips AT to 20 s -> 0.25; k = 2 to max(15, 10) -> 5 / 15 = 0.3333.
  // A 2024 file (run.py on k = 2) checks clean as barn2024 and not as barn2023.
  const auto lines = parseHarnessOut("3 1 0 0 15 0.3333\n3 0 1 0 4 0\n", "out_2024.txt");
  EXPECT_EQ(importHarnessLines(lines, {straightWorld(3)}, core::protocolPreset("barn2024"), "f").check.score_mismatches, 0);
  EXPECT_EQ(importHarnessLines(lines, {straightWorld(3)}, core::protocolPreset("barn2023"), "f").check.score_mismatches, 1);
}

TEST(HarnessOut, FormatRoundTripsTheColumns) {
  // nav_metric here is the barn2023 score of OT = 5 s, so export(import(text)) == text.
  const std::string text =
      "3 1 0 0 15.0000 0.2500\n"
      "3 0 1 0 7.5000 0.0000\n"
      "3 0 0 1 100.0100 0.0000\n"
      "5 1 0 0 30.0000 0.1667\n"
      "5 1 0 0 23.4567 0.2132\n";
  const HarnessImport imported = importHarnessLines(parseHarnessOut(text, "f"), {straightWorld(3), straightWorld(5)},
                                                    core::protocolPreset("barn2023"), "f");
  EXPECT_EQ(imported.check.score_mismatches, 0);
  EXPECT_EQ(harnessOut(imported.results), text);
  EpisodeResult error;
  error.world_id = 9;
  error.outcome = Outcome::Error;
  error.actual_time = 1.23456;
  EXPECT_EQ(harnessLine(error), "9 0 0 0 1.2346 0.0000\n");
}

}  // namespace
}  // namespace barn::bench
