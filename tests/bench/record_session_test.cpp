#include "barn/bench/record_session.hpp"

#include <gmock/gmock.h>
#include <gtest/gtest.h>

#include <filesystem>
#include <fstream>
#include <optional>
#include <random>
#include <sstream>
#include <string>
#include <vector>

#include "barn/bench/batch.hpp"
#include "barn/bench/results_io.hpp"
#include "barn/core/errors.hpp"

namespace barn::bench {
namespace {

namespace fs = std::filesystem;
using ::testing::HasSubstr;

std::string readFile(const fs::path& path) {
  std::ifstream in(path, std::ios::binary);
  std::ostringstream buffer;
  buffer << in.rdbuf();
  return buffer.str();
}

class RecordSessionTest : public ::testing::Test {
 protected:
  RecordSessionTest() {
    std::random_device device;
    root_ = fs::temp_directory_path() / ("barn_record_session_test_" + std::to_string(device()) + "_" + std::to_string(device()));
    fs::create_directories(root_);
    loaded_ = loadWorlds("0:3", fs::path(BARN_SOURCE_DIR) / "worlds");
  }
  ~RecordSessionTest() override {
    std::error_code ec;
    fs::remove_all(root_, ec);
  }

  // A 3 worlds x 2 trials run of seed 5 (shard 0 = whole run).
  RunManifest manifest(int shard_index = 0, int shard_count = 0) const {
    RunManifest m = newManifest("pure_pursuit", "type: pure_pursuit\n", EpisodeConfig{}, loaded_, "0:3", 2, 5);
    m.shard_index = shard_index;
    m.shard_count = shard_count;
    return m;
  }

  // The result of episode `index` (world position x trials + trial): distinct, seeded as a run.
  EpisodeResult result(std::size_t index) const {
    EpisodeResult r;
    r.world_id = loaded_.worlds[index / 2].id;
    r.trial = static_cast<int>(index % 2);
    r.seed = episodeSeed(5, r.world_id, r.trial);
    r.outcome = index % 3 == 0 ? Outcome::Timeout : Outcome::Success;
    r.actual_time = 10.0 + static_cast<double>(index);
    r.optimal_time = 5.0;
    r.score = r.outcome == Outcome::Success ? 0.2 : 0.0;
    return r;
  }

  fs::path root_;
  LoadedWorlds loaded_;
};

TEST_F(RecordSessionTest, AnInterruptedRecordResumesToTheBytesOfAnUninterruptedOne) {
  // Uninterrupted: every episode in one session.
  {
    RecordSession session = createRecord(manifest(), loaded_.worlds, root_ / "whole");
    ASSERT_EQ(pendingEpisodes(session).size(), 6u);
    RecordJournal journal(session, 6, 1);
    std::vector<EpisodeResult> all;
    for (std::size_t i = 0; i < 6; ++i) {
      ASSERT_TRUE(journal.append(result(i)));
      all.push_back(result(i));
    }
    EXPECT_TRUE(journal.finish(all, 1.0));
  }
  // Interrupted after episodes 4 and 1, then resumed.
  {
    RecordSession session = createRecord(manifest(), loaded_.worlds, root_ / "resumed");
    RecordJournal journal(session, 6, 1);
    ASSERT_TRUE(journal.append(result(4)));
    ASSERT_TRUE(journal.append(result(1)));
    EXPECT_FALSE(journal.finish({result(4), result(1)}, 1.0));
  }
  EXPECT_FALSE(fs::exists(root_ / "resumed" / kEpisodesFile));
  EXPECT_EQ(readManifest(root_ / "resumed" / kManifestFile).episodes_done, 2u);
  {
    RecordSession session = openRecord(root_ / "resumed");
    ASSERT_EQ(session.previous.size(), 2u);
    const std::vector<std::size_t> pending = pendingEpisodes(session);
    EXPECT_EQ(pending, (std::vector<std::size_t>{0, 2, 3, 5}));
    RecordJournal journal(session, pending.size(), 2);
    std::vector<EpisodeResult> rest;
    for (std::size_t i : pending) {
      ASSERT_TRUE(journal.append(result(i)));
      rest.push_back(result(i));
    }
    const std::optional<std::vector<EpisodeResult>> complete = journal.finish(rest, 1.0);
    ASSERT_TRUE(complete.has_value());
    // What finish hands back is the record as written: the earlier and the new rows, sorted.
    EXPECT_EQ(episodesCsv(*complete), readFile(root_ / "resumed" / kEpisodesFile));
  }
  for (const char* file : {kEpisodesFile, kSummaryFile})
    EXPECT_EQ(readFile(root_ / "resumed" / file), readFile(root_ / "whole" / file)) << file;
  EXPECT_FALSE(fs::exists(root_ / "resumed" / kJournalFile));
  EXPECT_TRUE(readManifest(root_ / "resumed" / kManifestFile).complete);
}

TEST_F(RecordSessionTest, ARecordIsNeverCreatedTwiceNorWrittenByTwoSessions) {
  RecordSession first = createRecord(manifest(), loaded_.worlds, root_ / "r");
  // Locked while the first session lives.
  EXPECT_THAT([&] { createRecord(manifest(), loaded_.worlds, root_ / "r"); },
              ::testing::ThrowsMessage<core::InputError>(HasSubstr("another barn process")));
  RecordJournal journal(first, 6, 1);  // writes the manifest
  EXPECT_THAT([&] { checkNoRecord(root_ / "r"); }, ::testing::ThrowsMessage<core::InputError>(HasSubstr("already holds an unfinished run")));
}

TEST_F(RecordSessionTest, AJournalRowOfAnotherExperimentIsRefusedOnResume) {
  {
    RecordSession session = createRecord(manifest(), loaded_.worlds, root_ / "r");
    RecordJournal journal(session, 6, 1);
    EpisodeResult wrong = result(0);
    wrong.seed += 1;  // not the seed (run seed, world, trial) gives
    ASSERT_TRUE(journal.append(wrong));
    journal.finish({wrong}, 0.0);
  }
  EXPECT_THAT([&] { openRecord(root_ / "r"); }, ::testing::ThrowsMessage<core::InputError>(HasSubstr("seed")));
}

TEST_F(RecordSessionTest, ShardsMergeIntoTheWholeRunsBytes) {
  {
    RecordSession session = createRecord(manifest(), loaded_.worlds, root_ / "whole");
    RecordJournal journal(session, 6, 1);
    std::vector<EpisodeResult> all;
    for (std::size_t i = 0; i < 6; ++i) all.push_back(result(i));
    ASSERT_TRUE(journal.finish(all, 0.0));
  }
  std::vector<fs::path> shards;
  for (int k = 1; k <= 2; ++k) {
    shards.push_back(root_ / ("shard_" + std::to_string(k)));
    RecordSession session = createRecord(manifest(k, 2), loaded_.worlds, shards.back());
    const std::vector<std::size_t> mine = pendingEpisodes(session);
    EXPECT_EQ(mine, shardEpisodes(6, k, 2));
    RecordJournal journal(session, mine.size(), 1);
    std::vector<EpisodeResult> rows;
    for (std::size_t i : mine) rows.push_back(result(i));
    ASSERT_TRUE(journal.finish(rows, 0.0));
  }
  EXPECT_THAT([&] { mergeShardRecords({shards[0]}, root_ / "merged"); },
              ::testing::ThrowsMessage<core::InputError>(HasSubstr("shards 2 of 2 are missing")));
  const RunManifest merged = mergeShardRecords(shards, root_ / "merged").manifest;
  EXPECT_EQ(merged.episodes_total, 6u);
  for (const char* file : {kEpisodesFile, kSummaryFile})
    EXPECT_EQ(readFile(root_ / "merged" / file), readFile(root_ / "whole" / file)) << file;
  EXPECT_THAT([&] { mergeShardRecords(shards, root_ / "merged"); },
              ::testing::ThrowsMessage<core::InputError>(HasSubstr("already holds")));
}

TEST_F(RecordSessionTest, ACompleteRecordIsReadOnlyWhenItsRowsAgreeWithItsManifest) {
  {
    RecordSession session = createRecord(manifest(), loaded_.worlds, root_ / "r");
    RecordJournal journal(session, 6, 1);
    std::vector<EpisodeResult> all;
    for (std::size_t i = 0; i < 6; ++i) all.push_back(result(i));
    ASSERT_TRUE(journal.finish(all, 0.0));
  }
  EXPECT_EQ(readCompleteRecord(root_ / "r").episodes.size(), 6u);
  const fs::path file = root_ / "r" / kEpisodesFile;
  const std::string full = readFile(file);
  const auto rewrite = [&](const std::string& text) { std::ofstream(file, std::ios::binary | std::ios::trunc) << text; };
  const auto lines = [&](int n) {  // the first n lines
    std::size_t end = 0;
    for (int i = 0; i < n; ++i) end = full.find('\n', end) + 1;
    return full.substr(0, end);
  };
  // The header and 5 of the 6 rows (worlds 0, 1, 2 x trials 0, 1): world 2 trial 1 is missing.
  rewrite(lines(6));
  EXPECT_THAT([&] { readCompleteRecord(root_ / "r"); },
              ::testing::ThrowsMessage<core::InputError>(HasSubstr("episodes.csv: 5 rows, the manifest says 6 (world 2 trial 1 missing)")));
  rewrite(lines(7) + full.substr(lines(2).size(), lines(3).size() - lines(2).size()));  // a row twice
  EXPECT_THAT([&] { readCompleteRecord(root_ / "r"); }, ::testing::ThrowsMessage<core::InputError>(HasSubstr("given twice")));
  rewrite(full.substr(0, full.size() - 1));  // the last newline lost
  EXPECT_THAT([&] { readCompleteRecord(root_ / "r"); }, ::testing::ThrowsMessage<core::InputError>(HasSubstr("cut short")));
  rewrite(full);
  std::ofstream(root_ / "r" / core::kCommitNote) << "staging .staging.tmp-1\n";
  EXPECT_THAT([&] { readCompleteRecord(root_ / "r"); }, ::testing::ThrowsMessage<core::InputError>(HasSubstr("interrupted")));
}

TEST_F(RecordSessionTest, ResumeRefusesAFileTheConfigNamesThatChanged) {
  const fs::path script = root_ / "ctrl.py";
  std::ofstream(script) << "version 1\n";
  RunManifest m = newManifest("x", "type: external\nexternal:\n  command: [python3, " + script.string() + "]\n",
                              EpisodeConfig{}, loaded_, "0:3", 2, 5);
  ASSERT_EQ(m.config_files.size(), 1u);  // the script, not python3 (no path) nor anything else
  EXPECT_EQ(m.config_files.front().path, script.string());
  {
    RecordSession session = createRecord(m, loaded_.worlds, root_ / "r");
    RecordJournal journal(session, 6, 1);
    EXPECT_FALSE(journal.finish({result(0)}, 0.0));
  }
  EXPECT_NO_THROW(openRecord(root_ / "r"));
  std::ofstream(script) << "version 2\n";
  EXPECT_THAT([&] { openRecord(root_ / "r"); },
              ::testing::ThrowsMessage<core::InputError>(HasSubstr("ctrl.py: changed since the run started")));
  fs::remove(script);
  EXPECT_THAT([&] { openRecord(root_ / "r"); }, ::testing::ThrowsMessage<core::InputError>(HasSubstr("ctrl.py: missing")));
}

TEST_F(RecordSessionTest, AJournaledEpisodeWithoutItsTrajectoryRunsAgain) {
  RunManifest m = manifest();
  m.trajectories = true;
  {
    RecordSession session = createRecord(m, loaded_.worlds, root_ / "r");
    RecordJournal journal(session, 6, 1);
    for (std::size_t i : {0u, 1u, 2u}) ASSERT_TRUE(journal.append(result(i)));
    EXPECT_FALSE(journal.finish({result(0), result(1), result(2)}, 0.0));
  }
  // Each journaled row has its file; one is lost.
  for (std::size_t i : {0u, 1u, 2u})
    EXPECT_TRUE(fs::exists(root_ / "r" / "trajectories" / trajectoryFileName(result(i).world_id, result(i).trial)));
  fs::remove(root_ / "r" / "trajectories" / trajectoryFileName(result(1).world_id, result(1).trial));
  RecordSession session = openRecord(root_ / "r");
  EXPECT_EQ(session.previous.size(), 2u);
  EXPECT_EQ(pendingEpisodes(session), (std::vector<std::size_t>{1, 3, 4, 5}));
}

}  // namespace
}  // namespace barn::bench
