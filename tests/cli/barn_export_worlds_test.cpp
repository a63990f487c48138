// barn export-worlds: the real executable writes the harness's files and the dataset layout,
// import-barn reads the latter back unchanged, and bad input exits 2 without writing anything.

#include <gmock/gmock.h>
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <filesystem>
#include <string>
#include <vector>

#include "barn/core/npy.hpp"
#include "barn/core/world_file.hpp"
#include "cli_runner.hpp"
#include "generator/dataset_files.hpp"
#include "generator/gazebo_world.hpp"

namespace {

using namespace barn;
using namespace barn::test;
using testing::AllOf;
using testing::HasSubstr;

const fs::path kWorlds = fs::path(BARN_SOURCE_DIR) / "worlds";

/// Every regular file below `dir`, relative to it, sorted.
std::vector<std::string> filesBelow(const fs::path& dir) {
  std::vector<std::string> names;
  std::error_code ec;
  for (const auto& entry : fs::recursive_directory_iterator(dir, ec))
    if (entry.is_regular_file() && entry.path().filename() != ".barn.lock")  // the writer's lock
      names.push_back(fs::relative(entry.path(), dir).string());
  std::sort(names.begin(), names.end());
  return names;
}

class BarnExportWorlds : public testing::Test {
 protected:
  void SetUp() override {
    ASSERT_TRUE(fs::exists(kBarn)) << kBarn << " not built";
    dir_ = uniqueTempPath("barn_export_worlds_test");
    fs::create_directories(dir_);
  }
  void TearDown() override {
    std::error_code ec;
    fs::remove_all(dir_, ec);
  }
  /// Runs `barn export-worlds <args>` and expects exit 0.
  void exportWorlds(const std::string& args) {
    const RunResult r = run("export-worlds " + args);
    ASSERT_EQ(r.exit_code, 0) << r.output;
  }
  /// Runs `barn export-worlds <args>` and expects exit 2 with a message holding `needle`.
  void expectInputError(const std::string& args, const std::string& needle) {
    const RunResult r = run("export-worlds " + args);
    EXPECT_EQ(r.exit_code, 2) << args << "\n" << r.output;
    EXPECT_THAT(r.output, HasSubstr(needle)) << args;
  }
  fs::path dir_;
};

TEST_F(BarnExportWorlds, GazeboWritesEachWorldFileAndThePathFileRunPyReads) {
  const fs::path out = dir_ / "BARN";
  exportWorlds("--worlds 0:300:50 --format gazebo --out " + quote(out));
  std::vector<std::string> expected_files;
  for (int id = 0; id < 300; id += 50) {
    const core::WorldSpec world = core::readWorldFile(kWorlds / core::worldFileName(id));
    // The written file is formatGazeboWorld's text, whose cylinders gazebo_world_test checks.
    EXPECT_EQ(readFile(out / generator::gazeboWorldFileName(id)), generator::formatGazeboWorld(world)) << "world " << id;
    const core::NpyInt64Array path = core::readNpyInt64(out / generator::datasetFile(generator::kPathFiles, id));
    ASSERT_EQ(path.shape, (std::vector<std::size_t>{world.path.size(), 2}));
    for (std::size_t i = 0; i < world.path.size(); ++i) {
      EXPECT_EQ(path.values[2 * i], world.path[i].row);
      EXPECT_EQ(path.values[2 * i + 1], world.path[i].col);
    }
    expected_files.push_back(generator::datasetFile(generator::kPathFiles, id).string());
    expected_files.push_back(generator::gazeboWorldFileName(id));
  }
  std::sort(expected_files.begin(), expected_files.end());
  EXPECT_EQ(filesBelow(out), expected_files);
}

TEST_F(BarnExportWorlds, NpyExportImportsBackWithTheSameGridsPathsAndMetrics) {
  const fs::path dataset = dir_ / "dataset";
  const fs::path imported = dir_ / "imported";
  exportWorlds("--worlds 0:300:30 --format npy --out " + quote(dataset));
  const RunResult r = run("import-barn " + quote(dataset) + " --out " + quote(imported) + " --verify");
  ASSERT_EQ(r.exit_code, 0) << r.output;
  const std::vector<core::WorldSpec> back = core::readWorldSet(imported);
  ASSERT_EQ(back.size(), 10u);
  for (const core::WorldSpec& w : back) {
    const core::WorldSpec original = core::readWorldFile(kWorlds / core::worldFileName(w.id));
    EXPECT_EQ(w.grid, original.grid) << "world " << w.id;
    EXPECT_EQ(w.path, original.path) << "world " << w.id;
    EXPECT_EQ(w.metrics.toArray(), original.metrics.toArray()) << "world " << w.id;
  }

  // The exported z-scores are over all 300 worlds, so the import also tells how the 290 it
  // lacks compare: their mean closest wall is the one of the world files not exported.
  double sum = 0.0;
  int absent = 0;
  for (const core::WorldSpec& w : core::readWorldSet(kWorlds))
    if (w.id % 30 != 0) sum += w.metrics.closest_wall, ++absent;
  ASSERT_EQ(absent, 290);
  char mean[32];
  std::snprintf(mean, sizeof(mean), "%.3f", sum / absent);
  EXPECT_THAT(r.output, HasSubstr("the 10 worlds here and the 290 not here"));
  const std::size_t row = r.output.find("closest_wall");
  ASSERT_NE(row, std::string::npos) << r.output;
  EXPECT_THAT(r.output.substr(row, r.output.find('\n', row) - row), HasSubstr(mean)) << r.output;

  // --world-dir: the imported set exported again gives the same arrays (norm_metrics aside:
  // the import z-scores over the ten worlds it imported).
  const fs::path again = dir_ / "again";
  exportWorlds("--world-dir " + quote(imported) + " --worlds all --format npy --out " + quote(again));
  for (const core::WorldSpec& w : back) {
    for (const auto kind : {generator::kGridFiles, generator::kCspaceFiles, generator::kPathFiles, generator::kMetricsFiles}) {
      const fs::path file = generator::datasetFile(kind, w.id);
      EXPECT_EQ(readFile(again / file), readFile(dataset / file)) << file;
    }
  }
}

TEST_F(BarnExportWorlds, ImportOfANonFiniteMetricExitsTwoNamingTheFileAndMetricAndWritesNothing) {
  const fs::path dataset = dir_ / "dataset";
  exportWorlds("--worlds 0:3 --format npy --out " + quote(dataset));
  const fs::path metrics = dataset / generator::datasetFile(generator::kMetricsFiles, 1);
  core::NpyFloat64Array nan_metrics{{5}, {2.0, 5.0, std::nan(""), 4.0, 1.2}};
  writeFile(metrics, core::formatNpyFloat64(nan_metrics));
  const fs::path out = dir_ / "imported";
  const RunResult r = run("import-barn " + quote(dataset) + " --out " + quote(out));
  EXPECT_EQ(r.exit_code, 2) << r.output;
  EXPECT_THAT(r.output, AllOf(HasSubstr("metrics_1.npy"), HasSubstr("dispersion")));
  EXPECT_FALSE(fs::exists(out / "index.csv"));
}

TEST_F(BarnExportWorlds, BadInputExitsTwoNamingTheFlagAndWritesNothing) {
  const fs::path out = dir_ / "out";
  expectInputError("--worlds 0:3 --format sdf --out " + quote(out), "--format");
  expectInputError("--worlds 7000 --format npy --out " + quote(out), "--worlds '7000'");
  expectInputError("--worlds 0:x --format gazebo --out " + quote(out), "--worlds");
  expectInputError("--world-dir " + quote(dir_ / "nowhere") + " --format npy --out " + quote(out), "--world-dir");
  expectInputError("--worlds 0:3 --format npy", "--out");
  expectInputError("--worlds 0:3 --out " + quote(out), "--format");
  EXPECT_FALSE(fs::exists(out));
  writeFile(dir_ / "a_file", "x");
  expectInputError("--worlds 0:3 --format npy --out " + quote(dir_ / "a_file"), "--out");
}

TEST_F(BarnExportWorlds, AnEarlierExportIsReplacedOnlyWithForceAndThenWhole) {
  const fs::path out = dir_ / "out";
  exportWorlds("--worlds 0:4 --format npy --out " + quote(out));
  writeFile(out / "notes.txt", "mine");
  const std::vector<std::string> first = filesBelow(out);
  EXPECT_EQ(first.size(), 4u * 5u + 1u);  // 4 worlds x 5 arrays, and notes.txt

  // Either format's files count as an earlier export.
  for (const std::string format : {"npy", "gazebo"}) {
    const RunResult r = run("export-worlds --worlds 0:2 --format " + format + " --out " + quote(out));
    EXPECT_EQ(r.exit_code, 2) << r.output;
    EXPECT_THAT(r.output, AllOf(HasSubstr("--out"), HasSubstr("--force")));
    EXPECT_EQ(filesBelow(out), first);
  }

  // With --force the folder holds the new export only (the user's own file stays).
  exportWorlds("--worlds 0:2 --format gazebo --out " + quote(out) + " --force");
  EXPECT_EQ(filesBelow(out), (std::vector<std::string>{"notes.txt", "path_files/path_0.npy", "path_files/path_1.npy",
                                                       "world_0.world", "world_1.world"}));
  EXPECT_EQ(readFile(out / "notes.txt"), "mine");
}

}  // namespace
