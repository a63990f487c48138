// barn regress and barn sweep through the real executable.

#include <gmock/gmock.h>
#include <gtest/gtest.h>

#include <sys/wait.h>

#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <random>
#include <sstream>
#include <string>

#include "cli_runner.hpp"

namespace {

namespace fs = std::filesystem;
using ::testing::HasSubstr;

fs::path tempPath(const std::string& stem) { return barn::test::uniqueTempPath(stem); }
using barn::test::run;
using barn::test::RunResult;

class Regress : public ::testing::Test {
 protected:
  void SetUp() override {
    dir_ = tempPath("barn_regress");
    baseline_ = dir_ / "baseline";
    // A reference run: pure pursuit on 5 worlds (fast and deterministic).
    const RunResult made = run("run --controller pure_pursuit --worlds 0:300:60 --out '" + (baseline_ / "pure_pursuit").string() + "'");
    ASSERT_EQ(made.exit_code, 0) << made.output;
  }
  void TearDown() override { fs::remove_all(dir_); }
  std::string regress(const std::string& extra) {
    return "regress --baseline '" + baseline_.string() + "' --work '" + (dir_ / "work").string() + "' " + extra;
  }
  fs::path dir_, baseline_;
};

TEST_F(Regress, PassesOnAnUnchangedBuildWithBitIdenticalEpisodes) {
  const RunResult r = run(regress(""));
  EXPECT_EQ(r.exit_code, 0) << r.output;
  EXPECT_THAT(r.output, HasSubstr("identical ok"));
}

TEST_F(Regress, FailsOnADeliberateRegression) {
  // Pure pursuit at 2 m/s cuts corners and collides: score and success drop.
  const RunResult r = run(regress("--set pure_pursuit.speed=2.0"));
  EXPECT_EQ(r.exit_code, 1) << r.output;
  EXPECT_THAT(r.output, HasSubstr("FAIL"));
  EXPECT_THAT(r.output, HasSubstr("REGRESSION"));
}

TEST_F(Regress, UpdateRewritesTheBaseline) {
  ASSERT_EQ(run(regress("--set pure_pursuit.speed=2.0 --update")).exit_code, 0);
  const RunResult after = run(regress("--set pure_pursuit.speed=2.0"));
  EXPECT_EQ(after.exit_code, 0) << after.output;
}

TEST_F(Regress, NamesAMissingReferenceRun) {
  const RunResult r = run(regress("--controllers nosuch"));
  EXPECT_EQ(r.exit_code, 2);
  EXPECT_THAT(r.output, HasSubstr("no reference run 'nosuch'"));
}

TEST(Sweep, RunsTheGridAndWritesTheTableAndHeatMaps) {
  const fs::path out = tempPath("barn_sweep");
  const RunResult r = run("sweep --controller pure_pursuit --param speed=0.3,0.5 --param lookahead=0.3,0.6 --worlds 0:300:100 --out '" +
                          out.string() + "'");
  ASSERT_EQ(r.exit_code, 0) << r.output;
  std::ifstream csv(out / "sweep.csv");
  std::string line;
  int rows = 0;
  std::getline(csv, line);
  EXPECT_THAT(line, HasSubstr("speed,lookahead,score,success_rate"));
  while (std::getline(csv, line)) ++rows;
  EXPECT_EQ(rows, 4);  // 2 x 2 cells
  for (const char* png : {"heatmap_score.png", "heatmap_success.png", "heatmap_collision.png"})
    EXPECT_TRUE(fs::exists(out / png)) << png;
  // Every cell is a complete run record.
  int records = 0;
  for (const auto& entry : fs::directory_iterator(out))
    if (fs::exists(entry.path() / "manifest.yaml") && fs::exists(entry.path() / "episodes.csv")) ++records;
  EXPECT_EQ(records, 4);
  fs::remove_all(out);
}

TEST(Sweep, OneKeyDrawsLinePlotsInTheChosenFormat) {
  const fs::path out = tempPath("barn_sweep_line");
  const RunResult r = run("sweep --controller pure_pursuit --param speed=0.3,0.5 --worlds 0:300:100 --trials 2 --figures svg "
                          "--out '" + out.string() + "'");
  ASSERT_EQ(r.exit_code, 0) << r.output;
  for (const char* figure : {"line_score.svg", "line_success.svg", "line_collision.svg"}) {
    const std::string text = barn::test::readFile(out / figure);
    EXPECT_THAT(text.substr(0, 200), HasSubstr("<svg")) << figure;
    EXPECT_GT(text.size(), 3000u) << figure;
  }
  EXPECT_FALSE(fs::exists(out / "heatmap_score.svg")) << "one key: no one-row heat map";
  EXPECT_FALSE(fs::exists(out / "line_score.png"));
  fs::remove_all(out);
}

TEST(Sweep, RefusesAnUnknownFigureFormat) {
  const fs::path out = tempPath("barn_sweep_bad_figures");
  const RunResult r = run("sweep --controller pure_pursuit --param speed=0.3 --figures jpg --out '" + out.string() + "'");
  EXPECT_EQ(r.exit_code, 2) << r.output;
  EXPECT_THAT(r.output, HasSubstr("jpg"));
  EXPECT_FALSE(fs::exists(out));
}

TEST(Sweep, ResumesAnInterruptedSweepToTheSameTable) {
  const fs::path whole = tempPath("barn_sweep_whole");
  const fs::path parts = tempPath("barn_sweep_parts");
  const std::string grid = "--controller pure_pursuit --param speed=0.3,0.5 --worlds 0:300:50 ";
  ASSERT_EQ(run("sweep " + grid + "--out '" + whole.string() + "'").exit_code, 0);
  const RunResult stopped = run("sweep " + grid + "--out '" + parts.string() + "' --stop-after 3");
  EXPECT_EQ(stopped.exit_code, 1) << stopped.output;
  const RunResult resumed = run("sweep --resume '" + parts.string() + "'");
  ASSERT_EQ(resumed.exit_code, 0) << resumed.output;
  const auto read = [](const fs::path& p) {
    std::ifstream in(p);
    std::stringstream s;
    s << in.rdbuf();
    return s.str();
  };
  EXPECT_EQ(read(whole / "sweep.csv"), read(parts / "sweep.csv"));
  fs::remove_all(whole);
  fs::remove_all(parts);
}

TEST(Sweep, ShardsMergeIntoTheSameTable) {
  const fs::path whole = tempPath("barn_sweep_single");
  const fs::path a = tempPath("barn_sweep_shard1");
  const fs::path b = tempPath("barn_sweep_shard2");
  const fs::path merged = tempPath("barn_sweep_merged");
  const std::string grid = "--controller pure_pursuit --param speed=0.3,0.5 --worlds 0:300:50 ";
  ASSERT_EQ(run("sweep " + grid + "--out '" + whole.string() + "'").exit_code, 0);
  ASSERT_EQ(run("sweep " + grid + "--shard 1/2 --out '" + a.string() + "'").exit_code, 0);
  ASSERT_EQ(run("sweep " + grid + "--shard 2/2 --out '" + b.string() + "'").exit_code, 0);
  const RunResult m = run("sweep --merge '" + a.string() + "' '" + b.string() + "' --out '" + merged.string() + "'");
  ASSERT_EQ(m.exit_code, 0) << m.output;
  const auto read = [](const fs::path& p) {
    std::ifstream in(p);
    std::stringstream s;
    s << in.rdbuf();
    return s.str();
  };
  EXPECT_EQ(read(whole / "sweep.csv"), read(merged / "sweep.csv"));
  for (const auto& p : {whole, a, b, merged}) fs::remove_all(p);
}

TEST(Sweep, RejectsAMalformedParameter) {
  const RunResult r = run("sweep --controller pure_pursuit --param speed --worlds 0");
  EXPECT_EQ(r.exit_code, 2);
  EXPECT_THAT(r.output, HasSubstr("expected KEY=V1,V2"));
  const RunResult unknown = run("sweep --controller pure_pursuit --param sped=1,2 --worlds 0 --out '" +
                                tempPath("barn_sweep_bad").string() + "'");
  EXPECT_EQ(unknown.exit_code, 2);
  EXPECT_THAT(unknown.output, HasSubstr("pure_pursuit.sped"));
}

TEST_F(Regress, NeverDeletesAFolderItDidNotMake) {
  // --work pointing at the baseline itself: the reference record must survive untouched.
  const std::string before = barn::test::readFile(baseline_ / "pure_pursuit" / "episodes.csv");
  const RunResult r = run("regress --baseline '" + baseline_.string() + "' --work '" + baseline_.string() + "'");
  EXPECT_EQ(r.exit_code, 2) << r.output;
  EXPECT_THAT(r.output, HasSubstr("was not made by barn regress"));
  EXPECT_EQ(barn::test::readFile(baseline_ / "pure_pursuit" / "episodes.csv"), before);
  // Its own rerun folder it replaces on the next check.
  ASSERT_EQ(run(regress("")).exit_code, 0);
  EXPECT_EQ(run(regress("")).exit_code, 0);
}

TEST_F(Regress, RejectsANonFiniteTolerance) {
  for (const char* option : {"--tolerance nan", "--success-tolerance nan", "--tolerance inf"}) {
    const RunResult r = run(regress(option));
    EXPECT_EQ(r.exit_code, 2) << option;
    EXPECT_THAT(r.output, HasSubstr("not a finite number")) << option;
  }
}

TEST(Sweep, RejectsAKeyGivenTwice) {
  const RunResult r = run("sweep --controller pure_pursuit --param speed=0.3,0.4 --param speed=0.5 --worlds 0 --out '" +
                          tempPath("barn_sweep_twice").string() + "'");
  EXPECT_EQ(r.exit_code, 2);
  EXPECT_THAT(r.output, HasSubstr("given twice"));
}

TEST(Run, RejectsANegativeSeed) {
  const RunResult r = run("run --controller straight --worlds 0 --seed -1 --out '" + tempPath("barn_seed").string() + "'");
  EXPECT_EQ(r.exit_code, 2);
  EXPECT_THAT(r.output, HasSubstr("--seed: '-1' is not a whole number"));
}

}  // namespace
