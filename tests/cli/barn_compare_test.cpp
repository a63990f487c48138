// `barn import-out`, `barn export-out` and `barn compare` end to end: run the real executable
// on small harness files over the repository's worlds (and, if given, the official harness's
// Gazebo DWA results over the official worlds: tests/external_data.hpp).
//
// Exit codes (src/cli/main.cpp): 0 ok, 2 bad usage or input.

#include <gmock/gmock.h>
#include <gtest/gtest.h>

#include <charconv>
#include <filesystem>
#include <string>

#include <nlohmann/json.hpp>

#include "barn/core/protocol.hpp"
#include "barn/core/world_file.hpp"
#include "cli_runner.hpp"
#include "tests/external_data.hpp"

namespace {

using namespace barn::test;
using testing::HasSubstr;
using testing::Not;

const fs::path kRepo = BARN_SOURCE_DIR;
const fs::path kWorlds = kRepo / "worlds";

std::string fixed4(double value) {
  char buffer[64];
  const auto result = std::to_chars(buffer, buffer + sizeof buffer, value, std::chars_format::fixed, 4);
  return std::string(buffer, result.ptr);
}

/// barn2023 score of a success at `time` on repository world `id` (OT from its A* path).
double score2023(int id, double time) {
  char name[32];
  std::snprintf(name, sizeof name, "world_%03d.yaml", id);
  const auto world = barn::core::readWorldFile(kWorlds / name);
  const auto protocol = barn::core::protocolPreset("barn2023");
  return barn::core::barnScore(true, time, barn::core::optimalTime(world.path, protocol), protocol);
}

class BarnCompare : public ::testing::Test {
 protected:
  void SetUp() override {
    dir_ = uniqueTempPath("barn_compare_test");
    fs::create_directories(dir_);
  }
  void TearDown() override {
    std::error_code ec;
    fs::remove_all(dir_, ec);
  }

  /// Worlds 3 and 5 of the repository, 3 trials each, ordered by world; nav_metric holds the
  /// barn2023 score, so export reproduces the text.
  std::string harnessText() const {
    return "3 1 0 0 " + fixed4(31.5) + " " + fixed4(score2023(3, 31.5)) + "\n" +  //
           "3 0 1 0 12.2500 0.0000\n" +                                            //
           "3 1 0 0 " + fixed4(27.125) + " " + fixed4(score2023(3, 27.125)) + "\n" +
           "5 0 0 1 100.0110 0.0000\n" +  //
           "5 1 0 0 " + fixed4(40.0) + " " + fixed4(score2023(5, 40.0)) + "\n" +
           "5 1 0 0 " + fixed4(35.75) + " " + fixed4(score2023(5, 35.75)) + "\n";
  }

  /// Writes `text` as a harness file and imports it into `record`.
  RunResult importText(const std::string& text, const fs::path& record, const std::string& extra = "") {
    const fs::path file = dir_ / (record.filename().string() + "_out.txt");
    writeFile(file, text);
    return run("import-out " + quote(file) + " --world-dir " + quote(kWorlds) + " --out " + quote(record) + " " + extra);
  }

  fs::path dir_;
};

TEST_F(BarnCompare, ImportThenExportReproducesTheFile) {
  const fs::path record = dir_ / "gazebo";
  const RunResult imported = importText(harnessText(), record, "--controller-label gazebo:test");
  ASSERT_EQ(imported.exit_code, 0) << imported.output;
  EXPECT_THAT(imported.output, Not(HasSubstr("warning")));
  const std::string manifest = readFile(record / "manifest.yaml");
  EXPECT_THAT(manifest, HasSubstr("controller: \"gazebo:test\""));
  EXPECT_THAT(manifest, HasSubstr("source: \"" + (dir_ / "gazebo_out.txt").lexically_normal().string() + "\""));
  EXPECT_THAT(manifest, HasSubstr("source_digest: \""));
  EXPECT_THAT(manifest, HasSubstr("trials: 3"));
  EXPECT_THAT(manifest, Not(HasSubstr("seed:")));
  EXPECT_THAT(manifest, Not(HasSubstr("controller_config:")));
  // 2 of the 3 trials succeed: the double nearest 2/3, read back exactly.
  EXPECT_EQ(nlohmann::json::parse(readFile(record / "summary.json"))["summary"]["success_rate"].get<double>(), 2.0 / 3.0);

  const RunResult exported = run("export-out " + quote(record) + " --out " + quote(dir_ / "again.txt"));
  ASSERT_EQ(exported.exit_code, 0) << exported.output;
  EXPECT_EQ(readFile(dir_ / "again.txt"), harnessText());
}

TEST_F(BarnCompare, ImportedRecordWorksWithTheRecordTools) {
  const fs::path record = dir_ / "gazebo";
  ASSERT_EQ(importText(harnessText(), record).exit_code, 0);
  const RunResult plot = run("plot scores " + quote(record) + " -o " + quote(dir_ / "scores.png"));
  EXPECT_EQ(plot.exit_code, 0) << plot.output;
  EXPECT_TRUE(fs::exists(dir_ / "scores.png"));
  const RunResult resume = run("run --resume " + quote(record));
  EXPECT_EQ(resume.exit_code, 2) << resume.output;
  EXPECT_THAT(resume.output, HasSubstr("import-out"));
}

TEST_F(BarnCompare, ImportOfBadInputExitsTwoAndWritesNothing) {
  const fs::path record = dir_ / "bad";
  // A malformed second line.
  RunResult r = importText("3 1 0 0 30.0 0.2\n3 1 0 0 thirty 0.2\n", record);
  EXPECT_EQ(r.exit_code, 2) << r.output;
  EXPECT_THAT(r.output, HasSubstr("bad_out.txt:2: time: 'thirty'"));
  EXPECT_FALSE(fs::exists(record));
  // A world the folder does not hold.
  r = importText("3 1 0 0 30.0 0.2\n999 1 0 0 30.0 0.2\n", record);
  EXPECT_EQ(r.exit_code, 2) << r.output;
  EXPECT_THAT(r.output, HasSubstr("bad_out.txt:2: world_idx: world 999 is not in the world folder"));
  EXPECT_FALSE(fs::exists(record));
  // NaN, an unknown protocol, a missing file.
  r = importText("3 1 0 0 30.0 nan\n", record);
  EXPECT_EQ(r.exit_code, 2) << r.output;
  EXPECT_THAT(r.output, HasSubstr(":1: nav_metric"));
  r = importText("3 1 0 0 30.0 0.2\n", record, "--protocol barn2099");
  EXPECT_EQ(r.exit_code, 2) << r.output;
  EXPECT_THAT(r.output, HasSubstr("barn2099"));
  r = run("import-out " + quote(dir_ / "missing.txt") + " --world-dir " + quote(kWorlds) + " --out " + quote(record));
  EXPECT_EQ(r.exit_code, 2) << r.output;
  EXPECT_THAT(r.output, HasSubstr("missing.txt"));
  EXPECT_FALSE(fs::exists(record));
  // An existing record is never overwritten.
  ASSERT_EQ(importText(harnessText(), record).exit_code, 0);
  r = importText(harnessText(), record);
  EXPECT_EQ(r.exit_code, 2) << r.output;
  EXPECT_THAT(r.output, HasSubstr("already holds a run record"));
}

TEST_F(BarnCompare, ImportWarnsWhenNavMetricIsNotTheScore) {
  // 5.0 is neither the score nor AT / OT: reported, not fatal.
  const RunResult r = importText("3 1 0 0 30.0000 5.0000\n", dir_ / "odd");
  EXPECT_EQ(r.exit_code, 0) << r.output;
  EXPECT_THAT(r.output, HasSubstr("nav_metric differs from the recomputed barn2023 score (k = 4) by more than 1e-3 on 1 of 1 lines"));
}

TEST_F(BarnCompare, CompareOfARecordWithItself) {
  const fs::path record = dir_ / "gazebo";
  ASSERT_EQ(importText(harnessText(), record).exit_code, 0);
  const RunResult r = run("compare " + quote(record) + " " + quote(record) + " --bootstrap 500 --seed 3");
  EXPECT_EQ(r.exit_code, 0) << r.output;
  EXPECT_THAT(r.output, HasSubstr("2 common worlds"));
  EXPECT_THAT(r.output, HasSubstr("+0.0000   [+0.0000, +0.0000]"));
  EXPECT_THAT(r.output, HasSubstr("disagree 0"));
  EXPECT_THAT(r.output, HasSubstr("(500 resamples of the worlds, seed 3)"));
  const RunResult json = run("compare " + quote(record) + " " + quote(record) + " --json");
  EXPECT_EQ(json.exit_code, 0) << json.output;
  EXPECT_EQ(nlohmann::json::parse(json.output)["score_difference"], nlohmann::json::parse(R"({"estimate": 0, "low": 0, "high": 0})"));
  // Deterministic for a seed.
  EXPECT_EQ(run("compare " + quote(record) + " " + quote(record) + " --json").output, json.output);
}

TEST_F(BarnCompare, ComparePlotsByExtension) {
  const fs::path a = dir_ / "a", b = dir_ / "b";
  ASSERT_EQ(importText(harnessText(), a).exit_code, 0);
  ASSERT_EQ(importText("3 1 0 0 25.0000 0.0000\n5 0 1 0 3.0000 0.0000\n", b).exit_code, 0);
  for (const std::string extension : {".png", ".pdf", ".svg"}) {
    const fs::path plot = dir_ / ("paired" + extension);
    const RunResult r = run("compare " + quote(a) + " " + quote(b) + " -o " + quote(plot));
    ASSERT_EQ(r.exit_code, 0) << r.output;
    EXPECT_THAT(r.output, HasSubstr("disagree 1"));
    const std::string bytes = readFile(plot);
    ASSERT_GT(bytes.size(), 1000u) << plot;
    if (extension == ".png") {
      EXPECT_EQ(bytes.substr(1, 3), "PNG");
    } else if (extension == ".pdf") {
      EXPECT_EQ(bytes.substr(0, 5), "%PDF-");
    } else {
      EXPECT_THAT(bytes.substr(0, 200), HasSubstr("<svg"));
    }
  }
  const RunResult bad = run("compare " + quote(a) + " " + quote(b) + " -o " + quote(dir_ / "paired.jpg"));
  EXPECT_EQ(bad.exit_code, 2) << bad.output;
  EXPECT_THAT(bad.output, HasSubstr("paired.jpg"));
  EXPECT_FALSE(fs::exists(dir_ / "paired.jpg"));
}

TEST_F(BarnCompare, CompareOfBadInputExitsTwo) {
  const fs::path a = dir_ / "a", other = dir_ / "other";
  ASSERT_EQ(importText(harnessText(), a).exit_code, 0);
  ASSERT_EQ(importText("7 1 0 0 25.0000 0.0000\n", other).exit_code, 0);
  RunResult r = run("compare " + quote(a) + " " + quote(other));
  EXPECT_EQ(r.exit_code, 2) << r.output;
  EXPECT_THAT(r.output, HasSubstr("no world in common"));
  r = run("compare " + quote(a) + " " + quote(dir_ / "nothing"));
  EXPECT_EQ(r.exit_code, 2) << r.output;
  EXPECT_THAT(r.output, HasSubstr("nothing"));
  r = run("compare " + quote(a) + " " + quote(a) + " --bootstrap 0");
  EXPECT_EQ(r.exit_code, 2) << r.output;
}

// The Gazebo reference run: the official harness's DWA on the 25 official test worlds below
// 150, 10 trials each: success 0.960, collision 0.020, timeout 0.020 on them.
TEST_F(BarnCompare, GazeboReferenceDwaImportsWithItsPublishedRates) {
  const fs::path file = externalData("BARN_GAZEBO_DWA_OUT");
  const fs::path dataset = externalData("BARN_DATASET_DIR");
  if (file.empty() || !fs::exists(file) || !fs::is_directory(dataset / "grid_files"))
    GTEST_SKIP() << "set BARN_GAZEBO_DWA_OUT (the official DWA results of worlds 0-149) and BARN_DATASET_DIR to run this test";
  const fs::path worlds = dir_ / "official";
  const RunResult imported_worlds = run("import-barn " + quote(dataset) + " --out " + quote(worlds));
  ASSERT_EQ(imported_worlds.exit_code, 0) << imported_worlds.output;
  const fs::path record = dir_ / "dwa";
  const RunResult r = run("import-out " + quote(file) + " --world-dir " + quote(worlds) + " --out " + quote(record) +
                          " --controller-label gazebo:dwa");
  ASSERT_EQ(r.exit_code, 0) << r.output;
  const nlohmann::json summary = nlohmann::json::parse(readFile(record / "summary.json"))["summary"];
  EXPECT_EQ(summary["worlds"], 25);
  EXPECT_EQ(summary["episodes"], 250);
  EXPECT_THAT(r.output, HasSubstr("Avg Success    0.9600"));
  EXPECT_THAT(r.output, HasSubstr("Avg Collision  0.0200"));
  EXPECT_THAT(r.output, HasSubstr("Avg Timeout    0.0200"));
  // That file's nav_metric column is AT / OT for the successes (the 2022 run.py), which the
  // check recognises on every one of the 240 successful lines.
  EXPECT_THAT(r.output, HasSubstr("240 of them hold success * AT / OT"));
}

}  // namespace
