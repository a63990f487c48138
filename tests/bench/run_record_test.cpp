#include "barn/bench/run_record.hpp"

#include <gmock/gmock.h>
#include <gtest/gtest.h>

#include <algorithm>
#include <cstdint>
#include <filesystem>
#include <fstream>
#include <limits>
#include <random>
#include <sstream>
#include <string>
#include <utility>
#include <vector>

#include "barn/bench/results_io.hpp"
#include "barn/controllers/registry.hpp"
#include "barn/core/config.hpp"
#include "barn/core/errors.hpp"
#include "barn/core/world_file.hpp"
#include "tests/scratch_dir.hpp"

namespace barn::bench {
namespace {

namespace fs = std::filesystem;
using ::testing::AllOf;
using ::testing::HasSubstr;

const fs::path kWorlds = fs::path(BARN_SOURCE_DIR) / "worlds";

std::string readFile(const fs::path& path) {
  std::ifstream in(path, std::ios::binary);
  std::ostringstream buffer;
  buffer << in.rdbuf();
  return buffer.str();
}

void writeFile(const fs::path& path, const std::string& content) {
  std::ofstream(path, std::ios::binary | std::ios::trunc) << content;
}


// An effective controller config as barn run records it (nested maps; a run's only kind).
std::string effectiveConfig(const std::string& yaml) {
  return controllers::effectiveControllerConfig(core::ConfigNode::parseString(yaml, "test"));
}
const std::string kControllerConfig = effectiveConfig("type: pure_pursuit\n");

constexpr char kEpisodeConfig[] = R"(protocol: barn2024
physics:
  rate: 200
robot:
  max_linear_speed: 2
lidar:
  beams: 720
  angle_min: -2.35619
)";

// Every field set to something other than its default.
RunManifest fullManifest() {
  RunManifest m;
  m.controller = "pure_pursuit";
  m.controller_config = kControllerConfig;
  m.episode_config = kEpisodeConfig;
  m.worlds_spec = "0:300:30";
  m.worlds_folder = "/data/barn worlds/set \"A\"\\v2";  // a space, quotes and a backslash
  m.world_ids = {12, 3, 7, 299, 0};
  m.worlds_digest = "7d5bf5559195d306";
  m.trials = 3;
  m.seed = std::numeric_limits<std::uint64_t>::max();  // beyond a double's 2^53
  m.shard_index = 2;
  m.shard_count = 5;
  m.episodes_total = 3;
  m.episodes_done = 2;
  m.complete = false;
  m.barnbench_version = "0.1.0";
  m.git_commit = "1d04ae207e6448d32720f7c45e13471baa8d2954-dirty";
  m.host = "node-17: gpu";  // a colon, as some cluster host names have
  m.threads = 16;
  m.started = "2026-11-22T00:27:30Z";
  m.wall_time_s = 0.1 + 0.2;  // 0.30000000000000004: exact round trip needed
  m.sim_time_s = 353.07000000000164;
  return m;
}

void expectSameManifest(const RunManifest& a, const RunManifest& b) {
  EXPECT_EQ(a.controller, b.controller);
  EXPECT_EQ(a.controller_config, b.controller_config);
  EXPECT_EQ(a.episode_config, b.episode_config);
  EXPECT_EQ(a.worlds_spec, b.worlds_spec);
  EXPECT_EQ(a.worlds_folder, b.worlds_folder);
  EXPECT_EQ(a.world_ids, b.world_ids);
  EXPECT_EQ(a.worlds_digest, b.worlds_digest);
  EXPECT_EQ(a.trials, b.trials);
  EXPECT_EQ(a.seed, b.seed);
  EXPECT_EQ(a.shard_index, b.shard_index);
  EXPECT_EQ(a.shard_count, b.shard_count);
  EXPECT_EQ(a.episodes_total, b.episodes_total);
  EXPECT_EQ(a.episodes_done, b.episodes_done);
  EXPECT_EQ(a.complete, b.complete);
  EXPECT_EQ(a.barnbench_version, b.barnbench_version);
  EXPECT_EQ(a.git_commit, b.git_commit);
  EXPECT_EQ(a.host, b.host);
  EXPECT_EQ(a.threads, b.threads);
  EXPECT_EQ(a.started, b.started);
  EXPECT_EQ(a.wall_time_s, b.wall_time_s);
  EXPECT_EQ(a.sim_time_s, b.sim_time_s);
}

RunManifest roundTrip(const RunManifest& m) {
  const test::ScratchDir dir("barn_run_record_test");
  const fs::path file = dir.path() / kManifestFile;
  writeFile(file, formatManifest(m, dir.path()));
  return readManifest(file);
}

// ---------------------------------------------------------------------------------------------
// formatManifest / readManifest

TEST(Manifest, RoundTripsEveryField) {
  const RunManifest m = fullManifest();
  expectSameManifest(roundTrip(m), m);
}

TEST(Manifest, RoundTripsACompleteWholeRun) {
  RunManifest m = fullManifest();
  m.shard_index = 0;
  m.shard_count = 0;
  m.complete = true;
  m.episodes_done = m.episodes_total;
  m.seed = 0;
  expectSameManifest(roundTrip(m), m);
}

TEST(Manifest, ConfigsAreNestedMapsInTheFileAndReadBackAsTheRunsText) {
  const test::ScratchDir dir("barn_run_record_test");
  const std::string text = formatManifest(fullManifest(), dir.path());
  const core::ConfigNode file = core::ConfigNode::parseString(text, "manifest");
  EXPECT_TRUE(file.child("controller_config").isMap()) << text;
  EXPECT_TRUE(file.child("episode_config").child("physics").isMap()) << text;
  EXPECT_THAT(text, HasSubstr("controller_config:\n  type: pure_pursuit\n  pure_pursuit:\n"));
  // Byte for byte, so a resumed run rebuilds the same controller and merge compares equal text.
  const RunManifest back = roundTrip(fullManifest());
  EXPECT_EQ(back.controller_config, kControllerConfig);
  EXPECT_EQ(back.episode_config, std::string(kEpisodeConfig));
}

TEST(Manifest, ConfigsWrittenAsTextByEarlierVersionsReadTheSame) {
  // Records written before configs were maps hold them as YAML text (a literal block, or a
  // quoted string where a block could not hold the text), paths relative to the record.
  const test::ScratchDir dir("barn_run_record_test");
  const std::string map_form = formatManifest(fullManifest(), dir.path());
  std::string text_form = map_form;
  const auto block = [](const std::string& yaml) {
    std::string out = "|\n";
    std::istringstream lines(yaml);
    for (std::string line; std::getline(lines, line);) out += "  " + line + "\n";
    return out;
  };
  const std::size_t at = text_form.find("controller_config:\n");
  const std::size_t end = text_form.find("episode_config:\n");
  const std::size_t after = text_form.find("worlds_spec:");
  ASSERT_TRUE(at != std::string::npos && end != std::string::npos && after != std::string::npos);
  text_form = text_form.substr(0, at) + "controller_config: " + block(kControllerConfig) + "episode_config: \"" +
              "protocol: barn2024\\nphysics:\\n  rate: 200\\nrobot:\\n  max_linear_speed: 2\\nlidar:\\n  beams: 720\\n" +
              "  angle_min: -2.35619\\n\"\n" + text_form.substr(after);
  const RunManifest back = parseManifest(text_form, dir.path(), "old/manifest.yaml");
  expectSameManifest(back, fullManifest());
  EXPECT_EQ(formatManifest(back, dir.path()), map_form);  // written back in the map form
}

TEST(Manifest, AnyStringReadsBackExactly) {
  // Characters YAML takes for line breaks or cannot hold raw: a newline, a tab, a control
  // character, NEL, LS (U+2028), PS, a BOM, in a quoted field.
  RunManifest m = fullManifest();
  m.worlds_spec = std::string("a\nb\tc\x01 d\xc2\x85") + "e\xe2\x80\xa8" + "f\xe2\x80\xa9g\xef\xbb\xbfh\x7f\"\\";
  m.host = "\xc3\xa9t\xc3\xa9";  // UTF-8 is kept as it is
  const RunManifest back = roundTrip(m);
  EXPECT_EQ(back.worlds_spec, m.worlds_spec);
  EXPECT_EQ(back.host, m.host);
}

TEST(Manifest, FormatIsStableAcrossARoundTrip) {
  const test::ScratchDir dir("barn_run_record_test");
  const std::string text = formatManifest(fullManifest(), dir.path());
  EXPECT_EQ(formatManifest(roundTrip(fullManifest()), dir.path()), text);
}

TEST(Manifest, PathsAreWrittenRelativeToTheRecordAndReadBackWhereverItIs) {
  // A record beside its worlds and policy: its manifest names them relative to itself, so the
  // tree copied elsewhere reads back the copies' paths.
  const test::ScratchDir tree("barn_run_record_test");
  const fs::path record = tree.path() / "results" / "run";
  fs::create_directories(record);
  RunManifest m = fullManifest();
  m.worlds_folder = (tree.path() / "worlds").string();
  fs::create_directories(tree.path() / "configs");
  fs::copy_file(fs::path(BARN_SOURCE_DIR) / "configs" / "policies" / "lflh_1ms.policy", tree.path() / "configs" / "a.policy");
  m.controller_config = effectiveConfig("type: lflh\nlflh:\n  policy: " + (tree.path() / "configs" / "a.policy").string() +
                                        "\n  rate: 25\n");
  writeFile(record / kManifestFile, formatManifest(m, record));
  const std::string text = readFile(record / kManifestFile);
  EXPECT_EQ(text.find(tree.path().string()), std::string::npos) << text;
  EXPECT_THAT(text, HasSubstr("worlds_folder: \"../../worlds\""));
  EXPECT_THAT(text, HasSubstr("policy: ../../configs/a.policy"));
  expectSameManifest(readManifest(record / kManifestFile), m);

  const test::ScratchDir elsewhere("barn_run_record_test");
  fs::copy(tree.path(), elsewhere.path(), fs::copy_options::recursive);
  const RunManifest moved = readManifest(elsewhere.path() / "results" / "run" / kManifestFile);
  EXPECT_EQ(moved.worlds_folder, (elsewhere.path() / "worlds").string());
  EXPECT_THAT(moved.controller_config, HasSubstr("policy: " + (elsewhere.path() / "configs" / "a.policy").string() + "\n"));
  EXPECT_THAT(moved.controller_config, HasSubstr("rate: 25\n"));
}

TEST(Manifest, RealEffectiveConfigsRoundTrip) {
  // The texts a real run records: the shipped configs' effective configs.
  RunManifest m = fullManifest();
  m.controller_config = controllers::effectiveControllerConfig(
      core::ConfigNode::parseFile(fs::path(BARN_SOURCE_DIR) / "configs" / "controllers" / "inventec_fi.yaml"));
  m.episode_config = core::writeConfig(
      core::readConfig<EpisodeConfig>(core::ConfigNode::parseFile(fs::path(BARN_SOURCE_DIR) / "configs" / "sim" / "barn.yaml")));
  ASSERT_FALSE(m.controller_config.empty());
  ASSERT_FALSE(m.episode_config.empty());
  expectSameManifest(roundTrip(m), m);
}

TEST(Manifest, CommittedBaselineManifestsReadAndWriteBackTheSame) {
  // Written by earlier versions, configs as YAML text: they must still read, to the configs'
  // text as it was, and write back (as maps) to a manifest that reads the same and writes the
  // same bytes again (the relative worlds folder comes back absolute, then relative again).
  const fs::path baseline = fs::path(BARN_SOURCE_DIR) / "results" / "baseline";
  int checked = 0;
  for (const auto& entry : fs::directory_iterator(baseline)) {
    const fs::path file = entry.path() / kManifestFile;
    if (!fs::exists(file)) continue;
    const RunManifest old = readManifest(file);
    const core::ConfigNode old_file = core::ConfigNode::parseFile(file);
    std::string old_text;
    ASSERT_TRUE(old_file.child("controller_config").read(old_text)) << file;
    // results/baseline/NAME/../../../configs is the source tree's configs folder.
    const std::string relative_configs = "../../../configs/";
    for (std::size_t at = old_text.find(relative_configs); at != std::string::npos; at = old_text.find(relative_configs))
      old_text.replace(at, relative_configs.size(), (fs::path(BARN_SOURCE_DIR) / "configs").string() + "/");
    EXPECT_EQ(old.controller_config, old_text) << file;
    ASSERT_TRUE(old_file.child("episode_config").read(old_text)) << file;
    EXPECT_EQ(old.episode_config, old_text) << file;
    const std::string written = formatManifest(old, entry.path());
    const RunManifest back = parseManifest(written, entry.path(), file.string());
    expectSameManifest(back, old);
    EXPECT_EQ(experimentDifference(back, old), "");
    EXPECT_EQ(formatManifest(back, entry.path()), written) << file;
    ++checked;
  }
  EXPECT_GT(checked, 0);
}

// An imported record as earlier versions wrote it: no controller_config or seed lines, the
// source lines after trials, and no sim_time_s (unknown).
constexpr char kImportedManifest[] = R"(# barnbench run record; `barn run --resume` and `barn merge` read it back.
controller: "ext"
episode_config: |
  protocol: barn2023
worlds_spec: "0,6"
worlds_folder: "./worlds"
world_ids: [0, 6]
worlds_digest: "00000000000000aa"
trials: 1
source: "out.txt"
source_digest: "00000000000000bb"
shard_index: 0
shard_count: 0
episodes_total: 2
episodes_done: 2
complete: true
barnbench_version: "0.1.0"
git_commit: "abc"
host: "vm"
threads: 1
started: "2026-11-22T00:27:30Z"
wall_time_s: 0
)";

TEST(Manifest, ImportedRecordHasNoSeedOrControllerConfigAndWritesBackTheSameButForTheConfigMap) {
  const test::ScratchDir dir("barn_run_record_test");
  const fs::path file = dir.path() / kManifestFile;
  writeFile(file, kImportedManifest);
  const RunManifest m = readManifest(file);
  EXPECT_EQ(m.source, "out.txt");
  EXPECT_EQ(m.source_digest, "00000000000000bb");
  EXPECT_EQ(m.worlds_folder, (dir.path() / "worlds").string());
  EXPECT_EQ(m.world_ids, (std::vector<int>{0, 6}));
  EXPECT_EQ(m.sim_time_s, 0.0);
  RunManifest unknown_sim_time = m;
  unknown_sim_time.sim_time_s = std::numeric_limits<double>::quiet_NaN();  // left out
  std::string expected = kImportedManifest;
  const std::string old_config = "episode_config: |\n";
  expected.replace(expected.find(old_config), old_config.size(), "episode_config:\n");
  EXPECT_EQ(formatManifest(unknown_sim_time, dir.path()), expected);
}

TEST(Manifest, ARunRecordHasNoSourceLines) {
  const test::ScratchDir dir("barn_run_record_test");
  const std::string text = formatManifest(fullManifest(), dir.path());
  EXPECT_THAT(text, HasSubstr("\nseed: 18446744073709551615\n"));
  EXPECT_EQ(text.find("source"), std::string::npos) << text;
}

TEST(Manifest, AWorldIdThatIsNotAWholeNumberIsAnErrorNamingTheField) {
  const test::ScratchDir dir("barn_run_record_test");
  const fs::path file = dir.path() / kManifestFile;
  for (const std::string ids : {"[0, 1e300]", "[0, -1]", "[2.5]", "[a]", "[]"}) {
    std::string text = formatManifest(fullManifest(), dir.path());
    const std::string line = "world_ids: [12, 3, 7, 299, 0]";
    text.replace(text.find(line), line.size(), "world_ids: " + ids);
    writeFile(file, text);
    try {
      readManifest(file);
      ADD_FAILURE() << ids << ": expected an InputError";
    } catch (const core::InputError& e) {
      EXPECT_THAT(e.what(), HasSubstr(file.string() + ": world_ids: ")) << ids;
    }
  }
}

TEST(Manifest, ANegativeEpisodeCountIsAnErrorNamingTheField) {
  const test::ScratchDir dir("barn_run_record_test");
  const fs::path file = dir.path() / kManifestFile;
  std::string text = formatManifest(fullManifest(), dir.path());
  text.replace(text.find("episodes_done: 2"), 16, "episodes_done: -2");
  writeFile(file, text);
  try {
    readManifest(file);
    FAIL() << "expected an InputError";
  } catch (const core::InputError& e) {
    EXPECT_THAT(e.what(), HasSubstr("episodes_done: "));
  }
}

TEST(Manifest, MissingControllerIsAnErrorNamingFileAndField) {
  const test::ScratchDir dir("barn_run_record_test");
  const fs::path file = dir.path() / kManifestFile;
  RunManifest m = fullManifest();
  m.controller = "";
  writeFile(file, formatManifest(m, dir.path()));
  try {
    readManifest(file);
    FAIL() << "expected an InputError";
  } catch (const core::InputError& e) {
    EXPECT_THAT(e.what(), AllOf(HasSubstr(file.string()), HasSubstr("controller")));
  }
}

TEST(Manifest, UnknownKeyIsAnErrorNamingIt) {
  const test::ScratchDir dir("barn_run_record_test");
  const fs::path file = dir.path() / kManifestFile;
  writeFile(file, formatManifest(fullManifest(), dir.path()) + "tirals: 4\n");
  try {
    readManifest(file);
    FAIL() << "expected an InputError";
  } catch (const core::InputError& e) {
    EXPECT_THAT(e.what(), HasSubstr("tirals"));
  }
}

TEST(Manifest, ShardIndexBeyondCountIsAnError) {
  const test::ScratchDir dir("barn_run_record_test");
  const fs::path file = dir.path() / kManifestFile;
  RunManifest m = fullManifest();
  m.shard_index = 6;  // of 5
  writeFile(file, formatManifest(m, dir.path()));
  try {
    readManifest(file);
    FAIL() << "expected an InputError";
  } catch (const core::InputError& e) {
    EXPECT_THAT(e.what(), HasSubstr("shard_index"));
  }
}

// ---------------------------------------------------------------------------------------------
// experimentDifference

TEST(ExperimentDifference, IsEmptyForTheSameExperiment) {
  EXPECT_EQ(experimentDifference(fullManifest(), fullManifest()), "");
}

TEST(ExperimentDifference, NamesEachDifferingField) {
  const RunManifest base = fullManifest();
  const std::vector<std::pair<std::string, void (*)(RunManifest&)>> cases = {
      {"controller", [](RunManifest& m) { m.controller = "straight"; }},
      {"controller_config", [](RunManifest& m) { m.controller_config += "extra: 1\n"; }},
      {"episode_config", [](RunManifest& m) { m.episode_config = "protocol: barn2023\n"; }},
      {"world_ids", [](RunManifest& m) { m.world_ids = {12, 3, 7, 299}; }},
      {"world_ids", [](RunManifest& m) { m.world_ids = {3, 12, 7, 299, 0}; }},  // same ids, other order
      {"worlds_digest", [](RunManifest& m) { m.worlds_digest = "0000000000000000"; }},
      {"trials", [](RunManifest& m) { m.trials = 4; }},
      {"seed", [](RunManifest& m) { m.seed = 1; }},
      {"source", [](RunManifest& m) { m.source = "out.txt"; }},
      {"source_digest", [](RunManifest& m) { m.source_digest = "00000000000000bb"; }},
  };
  for (const auto& [field, change] : cases) {
    RunManifest other = base;
    change(other);
    EXPECT_EQ(experimentDifference(base, other), field);
    EXPECT_EQ(experimentDifference(other, base), field);
  }
}

TEST(ExperimentDifference, NamesTheFirstDifferingField) {
  RunManifest other = fullManifest();
  other.seed = 1;
  other.trials = 9;
  other.episode_config = "protocol: barn2023\n";
  // Order: controller, controller_config, episode_config, world_ids, worlds_digest, trials, seed.
  EXPECT_EQ(experimentDifference(fullManifest(), other), "episode_config");
}

TEST(ExperimentDifference, IgnoresWhereAndHowItRanAndWhichShard) {
  RunManifest other = fullManifest();
  other.host = "another-node";
  other.threads = 1;
  other.wall_time_s = 1234.5;
  other.sim_time_s = 99.0;
  other.started = "2027-01-01T00:00:00Z";
  other.git_commit = "0000000";
  other.barnbench_version = "9.9.9";
  other.shard_index = 5;
  other.shard_count = 5;
  other.episodes_total = 100;
  other.episodes_done = 0;
  other.complete = true;
  // The worlds are identified by ids and digest: another checkout (cluster node) may keep
  // them in another folder.
  other.worlds_folder = "/elsewhere/worlds";
  EXPECT_EQ(experimentDifference(fullManifest(), other), "");
}

// ---------------------------------------------------------------------------------------------
// sortResults

EpisodeResult episode(int world, int trial) {
  EpisodeResult r;
  r.world_id = world;
  r.trial = trial;
  return r;
}

std::vector<std::pair<int, int>> keys(const std::vector<EpisodeResult>& results) {
  std::vector<std::pair<int, int>> out;
  for (const auto& r : results) out.emplace_back(r.world_id, r.trial);
  return out;
}

TEST(SortResults, OrdersByTheWorldIdsOrderThenTrial) {
  std::vector<EpisodeResult> results = {episode(7, 1), episode(3, 0), episode(12, 1), episode(7, 0),
                                        episode(3, 1), episode(12, 0)};
  sortResults(results, {12, 3, 7});
  // The run order {12, 3, 7}, not numeric order {3, 7, 12}.
  const std::vector<std::pair<int, int>> expected = {{12, 0}, {12, 1}, {3, 0}, {3, 1}, {7, 0}, {7, 1}};
  EXPECT_EQ(keys(results), expected);
}

TEST(SortResults, TrialsSortNumericallyNotAsText) {
  std::vector<EpisodeResult> results;
  for (int t : {10, 2, 1, 0, 11}) results.push_back(episode(5, t));
  sortResults(results, {5});
  const std::vector<std::pair<int, int>> expected = {{5, 0}, {5, 1}, {5, 2}, {5, 10}, {5, 11}};
  EXPECT_EQ(keys(results), expected);
}

TEST(SortResults, GivesTheSameOrderWhateverTheInputOrder) {
  std::vector<EpisodeResult> results;
  for (int w : {12, 3, 7})
    for (int t = 0; t < 3; ++t) results.push_back(episode(w, t));
  const std::vector<std::pair<int, int>> sorted = keys(results);
  std::mt19937 rng(7);
  for (int i = 0; i < 20; ++i) {
    std::shuffle(results.begin(), results.end(), rng);
    sortResults(results, {12, 3, 7});
    EXPECT_EQ(keys(results), sorted);
  }
}

// ---------------------------------------------------------------------------------------------
// worldsDigest and loadManifestWorlds

TEST(WorldsDigest, IsSixteenHexDigitsAndDeterministic) {
  const std::vector<core::WorldSpec> worlds = {core::readWorldFile(kWorlds / "world_000.yaml"),
                                               core::readWorldFile(kWorlds / "world_001.yaml")};
  const std::string digest = worldsDigest(worlds);
  EXPECT_THAT(digest, ::testing::MatchesRegex("[0-9a-f]{16}"));
  EXPECT_EQ(worldsDigest(worlds), digest);
}

TEST(WorldsDigest, ChangesWhenOneWorldsGridChanges) {
  std::vector<core::WorldSpec> worlds = {core::readWorldFile(kWorlds / "world_000.yaml"),
                                         core::readWorldFile(kWorlds / "world_001.yaml"),
                                         core::readWorldFile(kWorlds / "world_002.yaml")};
  const std::string before = worldsDigest(worlds);
  // One cell of the middle world flipped (row 15, column 15).
  auto& cell = worlds[1].grid.at(15, 15);
  cell = cell ? 0 : 1;
  EXPECT_NE(worldsDigest(worlds), before);
  cell = cell ? 0 : 1;
  EXPECT_EQ(worldsDigest(worlds), before);
}

TEST(WorldsDigest, DependsOnTheOrderAndTheSelection) {
  const core::WorldSpec a = core::readWorldFile(kWorlds / "world_000.yaml");
  const core::WorldSpec b = core::readWorldFile(kWorlds / "world_001.yaml");
  EXPECT_NE(worldsDigest({a, b}), worldsDigest({b, a}));
  EXPECT_NE(worldsDigest({a, b}), worldsDigest({a}));
}

class ManifestWorlds : public testing::Test {
 protected:
  void SetUp() override {
    for (int id : {0, 1, 2}) fs::copy_file(kWorlds / core::worldFileName(id), dir_.path() / core::worldFileName(id));
    manifest_.controller = "pure_pursuit";
    manifest_.worlds_folder = dir_.path().string();
    manifest_.world_ids = {2, 0};
    manifest_.worlds_digest = worldsDigest({core::readWorldFile(dir_.path() / core::worldFileName(2)),
                                            core::readWorldFile(dir_.path() / core::worldFileName(0))});
  }
  test::ScratchDir dir_{"barn_run_record_test"};
  RunManifest manifest_;
};

TEST_F(ManifestWorlds, LoadsTheRunsWorldsInRunOrder) {
  const auto worlds = loadManifestWorlds(manifest_);
  ASSERT_EQ(worlds.size(), 2u);
  EXPECT_EQ(worlds[0].id, 2);
  EXPECT_EQ(worlds[1].id, 0);
}

TEST_F(ManifestWorlds, ChangedWorldFileIsAnError) {
  core::WorldSpec w = core::readWorldFile(dir_.path() / core::worldFileName(0));
  w.grid.at(15, 15) = w.grid.at(15, 15) ? 0 : 1;
  writeFile(dir_.path() / core::worldFileName(0), core::formatWorldFile(w));
  try {
    loadManifestWorlds(manifest_);
    FAIL() << "expected an InputError";
  } catch (const core::InputError& e) {
    EXPECT_THAT(e.what(), HasSubstr("changed"));
  }
}

TEST_F(ManifestWorlds, MissingWorldIsAnErrorNamingIt) {
  fs::remove(dir_.path() / core::worldFileName(2));
  try {
    loadManifestWorlds(manifest_);
    FAIL() << "expected an InputError";
  } catch (const core::InputError& e) {
    EXPECT_THAT(e.what(), HasSubstr("world 2"));
  }
}

TEST_F(ManifestWorlds, BrokenFileOfAWorldOutsideTheRunDoesNotMatter) {
  // A run with --keep-going skipped world_001.yaml (broken); resuming or merging it must
  // still find its own worlds 2 and 0.
  const std::string text = readFile(dir_.path() / core::worldFileName(1));
  writeFile(dir_.path() / core::worldFileName(1), text.substr(0, text.find("grid:")));
  std::vector<core::WorldSpec> worlds;
  EXPECT_NO_THROW(worlds = loadManifestWorlds(manifest_));
  EXPECT_EQ(worlds.size(), 2u);
}

// ---------------------------------------------------------------------------------------------
// writeCompleteRecord

TEST_F(ManifestWorlds, WriteCompleteRecordSortsMarksCompleteAndRemovesTheJournal) {
  const test::ScratchDir out("barn_run_record_test");
  manifest_.trials = 2;
  manifest_.episodes_total = 4;
  writeFile(out.path() / kJournalFile, episodesCsvHeader());
  std::vector<EpisodeResult> results = {episode(0, 1), episode(2, 1), episode(0, 0), episode(2, 0)};
  for (auto& r : results) {
    r.outcome = Outcome::Success;
    r.sim_time = 10.0;
  }
  writeCompleteRecord(RecordWriter(out.path()), manifest_, results, loadManifestWorlds(manifest_));
  EXPECT_FALSE(fs::exists(out.path() / kJournalFile));
  EXPECT_TRUE(fs::exists(out.path() / kSummaryFile));
  const RunManifest m = readManifest(out.path() / kManifestFile);
  EXPECT_TRUE(m.complete);
  EXPECT_EQ(m.episodes_done, 4u);
  EXPECT_EQ(m.sim_time_s, 40.0);  // 4 episodes x 10 s
  const auto rows = readEpisodesCsv(out.path() / kEpisodesFile);
  const std::vector<std::pair<int, int>> expected = {{2, 0}, {2, 1}, {0, 0}, {0, 1}};
  EXPECT_EQ(keys(rows), expected);
}

}  // namespace
}  // namespace barn::bench
