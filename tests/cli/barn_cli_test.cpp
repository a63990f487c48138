// CLI smoke tests: run the real `barn` executable and check exit codes, messages and files.
//
// Exit codes (src/cli/main.cpp): 0 ok, 1 the run or check failed, 2 bad usage or bad input.

#include <gmock/gmock.h>
#include <gtest/gtest.h>

#include <sys/wait.h>

#include <algorithm>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <random>
#include <sstream>
#include <string>
#include <vector>

#include <nlohmann/json.hpp>

#include "cli_runner.hpp"
#include "tests/external_data.hpp"

namespace {

using namespace barn::test;

namespace fs = std::filesystem;
using testing::AllOf;
using testing::ContainsRegex;
using testing::HasSubstr;
using testing::Not;

const fs::path kRepo = BARN_SOURCE_DIR;
const fs::path kWorlds = kRepo / "worlds";
const fs::path kWorld0 = kWorlds / "world_000.yaml";
const fs::path kDatasetDir = barn::test::externalData("BARN_DATASET_DIR");







/// Names of the files in `dir` but the writer's lock (.barn.lock), sorted; empty if `dir` does
/// not exist.
std::vector<std::string> fileNames(const fs::path& dir) {
  std::vector<std::string> names;
  std::error_code ec;
  if (!fs::is_directory(dir, ec)) return names;
  for (const auto& entry : fs::directory_iterator(dir))
    if (entry.path().filename() != ".barn.lock") names.push_back(entry.path().filename().string());
  std::sort(names.begin(), names.end());
  return names;
}

/// The committed set: world_*.yaml and index.csv (README.md and the like are not generated).
std::vector<std::string> generatedNames(const fs::path& dir) {
  std::vector<std::string> names;
  for (const std::string& name : fileNames(dir)) {
    if ((name.rfind("world_", 0) == 0 && name.size() > 5 && name.substr(name.size() - 5) == ".yaml") || name == "index.csv")
      names.push_back(name);
  }
  return names;
}

/// `text` with only the first line equal to `line` removed.
std::string removeFirstLine(const std::string& text, const std::string& line) {
  const std::size_t at = text.find(line + "\n");
  if (at == std::string::npos) return text;
  return text.substr(0, at) + text.substr(at + line.size() + 1);
}

class BarnCli : public testing::Test {
 protected:
  void SetUp() override {
    ASSERT_TRUE(fs::exists(kBarn)) << kBarn << " not built";
    dir_ = uniqueTempPath("barn_cli_test");
    fs::create_directories(dir_);
  }
  void TearDown() override {
    std::error_code ec;
    fs::remove_all(dir_, ec);
  }

  /// Writes `text` (an edited world file) into the temp folder as `name`; returns its path.
  fs::path editedWorld(const std::string& name, const std::string& text) {
    const fs::path path = dir_ / name;
    writeFile(path, text);
    return path;
  }

  fs::path dir_;
};

// ---------------------------------------------------------------------------------------------
// Usage

TEST_F(BarnCli, HelpExitsZeroAndListsTheSubcommands) {
  const RunResult r = run("--help");
  EXPECT_EQ(r.exit_code, 0) << r.output;
  EXPECT_THAT(r.output, AllOf(HasSubstr("generate"), HasSubstr("import-barn"), HasSubstr("world")));
}

TEST_F(BarnCli, EverySubcommandHasHelp) {
  // Each help names an option only that subcommand has, so a fallback to the top-level help fails.
  const std::vector<std::pair<std::string, std::string>> cases = {
      {"generate --help", "--check"},
      {"import-barn --help", "--verify"},
      {"world --help", "render"},
      {"world info --help", "--json"},
      {"world render --help", "--output"},
  };
  for (const auto& [args, option] : cases) {
    const RunResult r = run(args);
    EXPECT_EQ(r.exit_code, 0) << args << "\n" << r.output;
    EXPECT_THAT(r.output, AllOf(HasSubstr("Usage"), HasSubstr(option))) << args;
  }
}

TEST_F(BarnCli, MissingSubcommandIsAUsageError) {
  const RunResult r = run("");
  EXPECT_EQ(r.exit_code, 2) << r.output;
  EXPECT_THAT(r.output, HasSubstr("subcommand"));
  // `world` alone needs info or render.
  EXPECT_EQ(run("world").exit_code, 2);
}

TEST_F(BarnCli, UnknownOptionIsAUsageErrorNamingIt) {
  const RunResult r = run("world info " + quote(kWorld0) + " --bogus");
  EXPECT_EQ(r.exit_code, 2) << r.output;
  EXPECT_THAT(r.output, HasSubstr("--bogus"));
  EXPECT_EQ(run("--bogus").exit_code, 2);
  EXPECT_EQ(run("generate --bogus").exit_code, 2);
}

// ---------------------------------------------------------------------------------------------
// world info

TEST_F(BarnCli, WorldInfoJsonHasEveryField) {
  const RunResult r = run("world info " + quote(kWorld0) + " --json");
  ASSERT_EQ(r.exit_code, 0) << r.output;
  const nlohmann::json json = nlohmann::json::parse(r.output);
  for (const char* key : {"id", "seed", "grid", "start_cell", "goal_cell", "path", "path_length_m", "optimal_time_s",
                          "metrics", "norm_metrics"})
    EXPECT_TRUE(json.contains(key)) << "key " << key;
  for (const char* key : {"closest_wall", "avg_visibility", "dispersion", "characteristic_dimension", "tortuosity"})
    EXPECT_TRUE(json["metrics"].contains(key) && json["norm_metrics"].contains(key)) << "key " << key;
  // The values are world_000.yaml's: id 0, start (19, 0), L = 10.7058766... m under barn2023.
  EXPECT_EQ(json["id"], 0);
  EXPECT_EQ(json["start_cell"], nlohmann::json::array({19, 0}));
  EXPECT_NEAR(json["path_length_m"].get<double>(), 10.7058766, 1e-7);
}

TEST_F(BarnCli, WorldInfoOnAMissingFileNamesIt) {
  const fs::path missing = dir_ / "no_such_world.yaml";
  const RunResult r = run("world info " + quote(missing));
  EXPECT_EQ(r.exit_code, 2) << r.output;
  EXPECT_THAT(r.output, HasSubstr(missing.string()));
}

TEST_F(BarnCli, WorldFileWithAnUnknownKeyIsRejected) {
  const fs::path file = editedWorld("colour.yaml", readFile(kWorld0) + "colour: red\n");
  const RunResult r = run("world info " + quote(file));
  EXPECT_EQ(r.exit_code, 2) << r.output;
  EXPECT_THAT(r.output, AllOf(HasSubstr("colour"), HasSubstr("unknown key"), HasSubstr("colour.yaml")));
}

TEST_F(BarnCli, WorldFileWithTwentyNineGridRowsIsRejected) {
  // Row 3 of world_000 ("000000000001000000000000000000") occurs once; deleting it leaves 29.
  const std::string text = readFile(kWorld0);
  const std::string edited = removeFirstLine(text, "  - \"000000000001000000000000000000\"");
  ASSERT_EQ(edited.size() + 37, text.size());  // '  - "' + 30 digits + '"' + newline = 4 + 1 + 30 + 1 + 1
  const RunResult r = run("world info " + quote(editedWorld("short_grid.yaml", edited)));
  EXPECT_EQ(r.exit_code, 2) << r.output;
  EXPECT_THAT(r.output, AllOf(HasSubstr("grid"), HasSubstr("29")));
}

TEST_F(BarnCli, WorldFileWithTheStartInsideAnObstacleIsRejected) {
  // Row 0 is always a full wall, so cell (0, 0) is '1'. The path still starts at (19, 0), which
  // is a second error; the message must name start_cell.
  const std::string edited = replaceLine(readFile(kWorld0), "start_cell:", "start_cell: [0, 0]");
  const RunResult r = run("world info " + quote(editedWorld("start_in_wall.yaml", edited)));
  EXPECT_EQ(r.exit_code, 2) << r.output;
  EXPECT_THAT(r.output, AllOf(HasSubstr("start_cell"), HasSubstr("obstacle")));
}

TEST_F(BarnCli, WorldFileWithANonIntegerIdIsRejected) {
  const std::string edited = replaceLine(readFile(kWorld0), "id:", "id: abc");
  const RunResult r = run("world info " + quote(editedWorld("bad_id.yaml", edited)));
  EXPECT_EQ(r.exit_code, 2) << r.output;
  EXPECT_THAT(r.output, AllOf(HasSubstr("id"), HasSubstr("abc")));
}

TEST_F(BarnCli, WorldFileErrorsAreAllReportedAtOnce) {
  std::string edited = replaceLine(readFile(kWorld0), "id:", "id: abc");
  edited += "colour: red\n";
  const RunResult r = run("world info " + quote(editedWorld("two_errors.yaml", edited)));
  EXPECT_EQ(r.exit_code, 2) << r.output;
  EXPECT_THAT(r.output, AllOf(HasSubstr("abc"), HasSubstr("colour")));
}

TEST_F(BarnCli, WorldFileWithAListAsAKeyIsAnInputErrorNamingFileAndLine) {
  // yaml-cpp cannot convert the key [1] to a name; this used to escape as "yaml-cpp: bad
  // conversion" with exit code 1 and no file name.
  const std::string text = readFile(kWorld0);
  const int last_line = static_cast<int>(std::count(text.begin(), text.end(), '\n'));
  const RunResult r = run("world info " + quote(editedWorld("list_key.yaml", text + "[1]: 2\n")));
  EXPECT_EQ(r.exit_code, 2) << r.output;
  EXPECT_THAT(r.output, AllOf(HasSubstr("list_key.yaml: line " + std::to_string(last_line + 1) + ":"),
                              HasSubstr("is a list or a map"), Not(HasSubstr("bad conversion"))));
}

TEST_F(BarnCli, WorldInfoOnADeviceIsRefused) {
  const RunResult r = run("world info /dev/zero");
  EXPECT_EQ(r.exit_code, 2) << r.output;
  EXPECT_THAT(r.output, HasSubstr("/dev/zero: not a regular file"));
}

// ---------------------------------------------------------------------------------------------
// world render

TEST_F(BarnCli, WorldRenderWritesAPng) {
  const fs::path png = dir_ / "w.png";
  const RunResult r = run("world render " + quote(kWorld0) + " -o " + quote(png));
  EXPECT_EQ(r.exit_code, 0) << r.output;
  ASSERT_TRUE(fs::exists(png)) << r.output;
  EXPECT_EQ(readFile(png).substr(0, 8), std::string("\x89PNG\r\n\x1a\n", 8));
}

// ---------------------------------------------------------------------------------------------
// generate (each run regenerates all 300 worlds, ~3.5 s)

TEST_F(BarnCli, CommittedWorldsRegenerateByteForByte) {
  const RunResult r = run("generate --check --out " + quote(kWorlds));
  EXPECT_EQ(r.exit_code, 0) << r.output;
  EXPECT_THAT(r.output, Not(HasSubstr("differs")));
  EXPECT_THAT(r.output, Not(HasSubstr("missing")));
}

TEST_F(BarnCli, GenerateCheckFailsOnAChangedWorldAndNamesIt) {
  // Without this, a --check that never compared would pass the test above too.
  const fs::path copy = dir_ / "worlds";
  fs::create_directories(copy);
  for (const std::string& name : generatedNames(kWorlds)) fs::copy_file(kWorlds / name, copy / name);
  writeFile(copy / "world_007.yaml", readFile(copy / "world_007.yaml") + "\n");
  fs::remove(copy / "world_123.yaml");
  const RunResult r = run("generate --check --out " + quote(copy));
  EXPECT_EQ(r.exit_code, 1) << r.output;
  EXPECT_THAT(r.output, ContainsRegex("differs: .*world_007\\.yaml"));
  EXPECT_THAT(r.output, ContainsRegex("missing: .*world_123\\.yaml"));
  EXPECT_THAT(r.output, Not(HasSubstr("world_008.yaml")));
}

TEST_F(BarnCli, GenerateWritesTheCommittedSet) {
  const fs::path out = dir_ / "generated";
  const RunResult r = run("generate --out " + quote(out));
  ASSERT_EQ(r.exit_code, 0) << r.output;
  const std::vector<std::string> expected = generatedNames(kWorlds);
  ASSERT_EQ(expected.size(), 301u);  // 300 world_*.yaml + index.csv
  // Exactly these files: nothing missing, nothing extra (no staging folder left behind).
  ASSERT_EQ(fileNames(out), expected);
  int differing = 0;
  for (const std::string& name : expected) {
    const bool same = readFile(out / name) == readFile(kWorlds / name);
    EXPECT_TRUE(same) << name << " differs from worlds/" << name;
    differing += !same;
  }
  EXPECT_EQ(differing, 0);
}

TEST_F(BarnCli, GenerateNeverLeavesAMixedWorldFolder) {
  // A smaller set over a larger one: refused without --force; with it, no old file stays.
  const fs::path out = dir_ / "generated";
  ASSERT_EQ(run("generate --worlds-per-set 2 --out " + quote(out)).exit_code, 0);
  ASSERT_EQ(fileNames(out).size(), 25u);
  const RunResult refused = run("generate --worlds-per-set 1 --out " + quote(out));
  EXPECT_EQ(refused.exit_code, 2) << refused.output;
  EXPECT_THAT(refused.output, HasSubstr("already holds a world set"));
  EXPECT_EQ(fileNames(out).size(), 25u);
  const RunResult forced = run("generate --worlds-per-set 1 --force --out " + quote(out));
  ASSERT_EQ(forced.exit_code, 0) << forced.output;
  EXPECT_EQ(fileNames(out).size(), 13u);  // 12 worlds + index.csv, nothing of the old set
}

// ---------------------------------------------------------------------------------------------
// import-barn (needs a copy of the original dataset: BARN_DATASET_DIR)

class BarnCliDataset : public BarnCli {
 protected:
  void SetUp() override {
    BarnCli::SetUp();
    if (!fs::is_directory(kDatasetDir / "grid_files"))
      GTEST_SKIP() << "set BARN_DATASET_DIR to a copy of the original BARN dataset to run the import-barn tests";
  }

  /// A dataset folder with worlds 0, 1 and 2 copied from the original dataset, and `truncated`
  /// (a grid file name) cut to half its size.
  fs::path fakeDataset(const std::string& truncated) {
    const fs::path fake = dir_ / "dataset";
    for (const char* folder : {"grid_files", "path_files", "metrics_files", "cspace_files"}) {
      fs::create_directories(fake / folder);
      const std::string stem = std::string(folder).substr(0, std::string(folder).size() - 6);  // "grid_files" -> "grid"
      for (int id = 0; id < 3; ++id) {
        const std::string name = stem + "_" + std::to_string(id) + ".npy";
        fs::copy_file(kDatasetDir / folder / name, fake / folder / name);
      }
    }
    const fs::path cut = fake / "grid_files" / truncated;
    const std::string bytes = readFile(cut);
    writeFile(cut, bytes.substr(0, bytes.size() / 2));  // 7280 -> 3640 bytes: header intact, data short
    return fake;
  }
};

TEST_F(BarnCliDataset, ImportOfATruncatedFirstGridFailsAndWritesNothing) {
  const fs::path out = dir_ / "out";
  const RunResult r = run("import-barn " + quote(fakeDataset("grid_0.npy")) + " --out " + quote(out));
  EXPECT_EQ(r.exit_code, 2) << r.output;
  EXPECT_THAT(r.output, HasSubstr("grid_0.npy"));
  EXPECT_THAT(fileNames(out), testing::IsEmpty());
}

TEST_F(BarnCliDataset, ImportOfATruncatedLastGridFailsAndWritesNothing) {
  // Worlds 0 and 1 are fine here: an importer that wrote world by world would leave them behind.
  const fs::path out = dir_ / "out";
  const RunResult r = run("import-barn " + quote(fakeDataset("grid_2.npy")) + " --out " + quote(out));
  EXPECT_EQ(r.exit_code, 2) << r.output;
  EXPECT_THAT(r.output, HasSubstr("grid_2.npy"));
  EXPECT_THAT(fileNames(out), testing::IsEmpty());
}

TEST_F(BarnCliDataset, ImportOfAFolderWithoutGridsIsAnInputError) {
  const RunResult r = run("import-barn " + quote(dir_) + " --out " + quote(dir_ / "out"));
  EXPECT_EQ(r.exit_code, 2) << r.output;
  EXPECT_THAT(r.output, HasSubstr("grid_files"));
}

TEST_F(BarnCliDataset, ImportWithVerifyReproducesEveryPathOfTheDataset) {
  const std::size_t worlds = fileNames(kDatasetDir / "grid_files").size();
  ASSERT_EQ(worlds, 150u) << "the dataset copy given holds worlds 0-149";
  const fs::path out = dir_ / "imported";
  const RunResult r = run("import-barn " + quote(kDatasetDir) + " --out " + quote(out) + " --verify");
  EXPECT_EQ(r.exit_code, 0) << r.output;
  EXPECT_THAT(r.output, ContainsRegex("A\\* paths identical[[:space:]]+150/150"));
  EXPECT_THAT(r.output, ContainsRegex("metrics equal[^\n]*150/150"));
  EXPECT_THAT(r.output, Not(HasSubstr("MISMATCH")));
  // 150 world files + index.csv.
  EXPECT_EQ(generatedNames(out).size(), 151u);
  EXPECT_EQ(fileNames(out).size(), 151u);
}

}  // namespace
