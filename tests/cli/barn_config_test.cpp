// barn config: a record's effective controller config, given back to `barn run --config`,
// runs the same controller (byte-identical episodes.csv); folders with no config of their own
// exit 2 saying what to give instead.

#include <gmock/gmock.h>
#include <gtest/gtest.h>

#include <filesystem>
#include <string>

#include "barn/bench/run_record.hpp"
#include "cli_runner.hpp"

namespace {

using namespace barn::test;
using testing::AllOf;
using testing::HasSubstr;

const fs::path kWorlds = fs::path(BARN_SOURCE_DIR) / "worlds";

class BarnConfig : public testing::Test {
 protected:
  void SetUp() override {
    ASSERT_TRUE(fs::exists(kBarn)) << kBarn << " not built";
    dir_ = uniqueTempPath("barn_config_test");
    fs::create_directories(dir_);
  }
  void TearDown() override {
    std::error_code ec;
    fs::remove_all(dir_, ec);
  }
  /// Runs `barn <args>` and expects exit 0.
  void ok(const std::string& args) {
    const RunResult r = run(args);
    ASSERT_EQ(r.exit_code, 0) << args << "\n" << r.output;
  }
  /// The controller_config recorded in `record`'s manifest.
  static std::string recordedConfig(const fs::path& record) {
    return barn::bench::readManifest(record / barn::bench::kManifestFile).controller_config;
  }
  fs::path dir_;
};

TEST_F(BarnConfig, RunWithTheRecordsConfigGivesTheSameEpisodes) {
  const fs::path first = dir_ / "R";
  const fs::path again = dir_ / "R2";
  const fs::path config = dir_ / "c.yaml";
  ok("run --controller pure_pursuit --worlds 0:300:150 --out " + quote(first));
  ok("config " + quote(first) + " --out " + quote(config));
  EXPECT_EQ(readFile(config), recordedConfig(first));
  // Printed, it is the same text.
  const RunResult printed = run("config " + quote(first));
  ASSERT_EQ(printed.exit_code, 0) << printed.output;
  EXPECT_EQ(printed.output, readFile(config));

  ok("run --config " + quote(config) + " --controller pure_pursuit --worlds 0:300:150 --out " + quote(again));
  EXPECT_EQ(readFile(again / "episodes.csv"), readFile(first / "episodes.csv"));
  EXPECT_EQ(recordedConfig(again), recordedConfig(first));
}

TEST_F(BarnConfig, ASweepCellsConfigCarriesItsSweptValue) {
  // The cell's speed differs from pure_pursuit's default, so a config that lost it would show
  // in the episodes.
  const fs::path sweep = dir_ / "S";
  ok("sweep --controller pure_pursuit --param speed=0.3,0.5 --worlds 0 --out " + quote(sweep));
  const fs::path cell = sweep / "cell_0_speed=0.3";
  ASSERT_TRUE(fs::exists(cell / barn::bench::kManifestFile));
  const fs::path config = dir_ / "cell.yaml";
  ok("config " + quote(cell) + " --out " + quote(config));
  EXPECT_THAT(readFile(config), HasSubstr("speed: 0.3"));

  const fs::path rerun = dir_ / "rerun";
  const fs::path plain = dir_ / "plain";
  ok("run --config " + quote(config) + " --controller pure_pursuit --worlds 0 --out " + quote(rerun));
  ok("run --controller pure_pursuit --worlds 0 --out " + quote(plain));
  EXPECT_EQ(readFile(rerun / "episodes.csv"), readFile(cell / "episodes.csv"));
  EXPECT_NE(readFile(plain / "episodes.csv"), readFile(cell / "episodes.csv"));

  // The sweep folder itself has no one config.
  const RunResult r = run("config " + quote(sweep));
  EXPECT_EQ(r.exit_code, 2) << r.output;
  EXPECT_THAT(r.output, AllOf(HasSubstr("sweep folder"), HasSubstr("give a cell folder"), HasSubstr("cell_0_speed=0.3")));
}

TEST_F(BarnConfig, AControllerNameListsItsFieldsWithUnitsFromTheSchema) {
  const RunResult r = run("config dwa");
  ASSERT_EQ(r.exit_code, 0) << r.output;
  EXPECT_THAT(r.output, HasSubstr("key"));
  // configs/controllers/dwa.yaml's value, DwaConfig's unit, range and meaning; columns aligned.
  EXPECT_THAT(r.output, testing::ContainsRegex("\nmax_vel_x +0.5 +m/s +> 0 +fastest forward speed\n"));
  EXPECT_THAT(r.output, testing::ContainsRegex("\nacc_lim_theta +20 +rad/s\\^2 +> 0 "));
}

TEST_F(BarnConfig, FoldersWithoutAConfigOfTheirOwnExitTwo) {
  const fs::path empty = dir_ / "empty";
  fs::create_directories(empty);
  RunResult r = run("config " + quote(empty));
  EXPECT_EQ(r.exit_code, 2) << r.output;
  EXPECT_THAT(r.output, HasSubstr("no manifest.yaml"));

  r = run("config " + quote(dir_ / "missing"));
  EXPECT_EQ(r.exit_code, 2) << r.output;
  EXPECT_THAT(r.output, HasSubstr("no such record folder"));

  // An imported harness file: nothing was run, so there is no controller config.
  const fs::path harness = dir_ / "out.txt";
  writeFile(harness, "3 0 1 0 12.2500 0.0000\n");
  const fs::path imported = dir_ / "imported";
  const RunResult import = run("import-out " + quote(harness) + " --world-dir " + quote(kWorlds) + " --out " + quote(imported));
  ASSERT_EQ(import.exit_code, 0) << import.output;
  r = run("config " + quote(imported));
  EXPECT_EQ(r.exit_code, 2) << r.output;
  EXPECT_THAT(r.output, AllOf(HasSubstr("imported"), HasSubstr("nothing was run")));

  // --out naming a folder is refused before anything is written.
  const fs::path record = dir_ / "R";
  ASSERT_EQ(run("run --controller straight --worlds 0 --out " + quote(record)).exit_code, 0);
  r = run("config " + quote(record) + " --out " + quote(empty));
  EXPECT_EQ(r.exit_code, 2) << r.output;
  EXPECT_THAT(r.output, HasSubstr("--out"));
}

}  // namespace
