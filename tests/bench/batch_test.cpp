#include "barn/bench/batch.hpp"

#include <gmock/gmock.h>
#include <gtest/gtest.h>

#include <algorithm>
#include <atomic>
#include <filesystem>
#include <memory>
#include <set>
#include <stdexcept>
#include <string>
#include <utility>
#include <vector>

#include "barn/bench/results_io.hpp"
#include "barn/core/config.hpp"
#include "barn/core/world_file.hpp"

namespace barn::bench {
namespace {

using ::testing::HasSubstr;

const std::vector<int> kWorldIds = {0, 6, 12, 18};

std::vector<core::WorldSpec> loadTestWorlds() {
  std::vector<core::WorldSpec> worlds;
  for (int id : kWorldIds)
    worlds.push_back(core::readWorldFile(std::filesystem::path(BARN_SOURCE_DIR) / "worlds" / core::worldFileName(id)));
  return worlds;
}

// 4 real worlds x 2 trials with the pure_pursuit fixture.
BatchSpec pursuitSpec() {
  BatchSpec spec;
  spec.worlds = loadTestWorlds();
  spec.trials = 2;
  spec.seed = 2024;
  spec.make_controller = controllers::makeControllerFactory(core::ConfigNode::parseString("type: pure_pursuit", "test"));
  return spec;
}

struct ProgressCall {
  int world_id;
  int trial;
  std::size_t done;
  std::size_t total;
};

// One serial and one two-thread batch, shared by the tests (each takes a fraction of a second).
class BatchTest : public ::testing::Test {
 protected:
  static void SetUpTestSuite() {
    serial_ = runBatch(pursuitSpec(), {.jobs = 1}, [](const EpisodeResult& r, std::size_t done, std::size_t total) {
      serial_calls_.push_back({r.world_id, r.trial, done, total});
    });
    parallel_ = runBatch(pursuitSpec(), {.jobs = 2}, [](const EpisodeResult& r, std::size_t done, std::size_t total) {
      parallel_calls_.push_back({r.world_id, r.trial, done, total});
    });
  }

  inline static std::vector<EpisodeResult> serial_;
  inline static std::vector<EpisodeResult> parallel_;
  inline static std::vector<ProgressCall> serial_calls_;
  inline static std::vector<ProgressCall> parallel_calls_;
};

TEST_F(BatchTest, ResultsAreOrderedByWorldThenTrial) {
  // 4 worlds x 2 trials = 8 episodes: index = 2 * world position + trial.
  ASSERT_EQ(serial_.size(), 8u);
  ASSERT_EQ(parallel_.size(), 8u);
  for (std::size_t i = 0; i < serial_.size(); ++i) {
    EXPECT_EQ(serial_[i].world_id, kWorldIds[i / 2]) << i;
    EXPECT_EQ(serial_[i].trial, static_cast<int>(i % 2)) << i;
    EXPECT_EQ(parallel_[i].world_id, kWorldIds[i / 2]) << i;
    EXPECT_EQ(parallel_[i].trial, static_cast<int>(i % 2)) << i;
  }
}

TEST_F(BatchTest, EveryEpisodeRanWithoutAnError) {
  for (const EpisodeResult& r : serial_) {
    EXPECT_NE(r.outcome, Outcome::Error) << "world " << r.world_id << ": " << r.error;
    EXPECT_GT(r.sim_time, 0.0);
    EXPECT_GT(r.optimal_time, 0.0);
  }
}

TEST_F(BatchTest, OneThreadAndTwoThreadsGiveByteIdenticalCsv) {
  const std::string serial = episodesCsv(serial_);
  EXPECT_EQ(serial, episodesCsv(parallel_));
  // Header plus 8 rows.
  EXPECT_EQ(std::count(serial.begin(), serial.end(), '\n'), 9);
}

TEST_F(BatchTest, EachEpisodeUsesItsOwnSeed) {
  std::set<std::uint64_t> seeds;
  for (const EpisodeResult& r : serial_) {
    EXPECT_EQ(r.seed, episodeSeed(2024, r.world_id, r.trial));
    seeds.insert(r.seed);
  }
  EXPECT_EQ(seeds.size(), 8u);  // distinct for every (world, trial)
}

TEST_F(BatchTest, ProgressIsReportedOncePerEpisodeCountingUp) {
  for (const auto* calls : {&serial_calls_, &parallel_calls_}) {
    ASSERT_EQ(calls->size(), 8u);
    std::set<std::pair<int, int>> episodes;
    for (std::size_t i = 0; i < calls->size(); ++i) {
      EXPECT_EQ((*calls)[i].done, i + 1);
      EXPECT_EQ((*calls)[i].total, 8u);
      episodes.insert({(*calls)[i].world_id, (*calls)[i].trial});
    }
    EXPECT_EQ(episodes.size(), 8u);  // each (world, trial) exactly once
  }
}

TEST(EpisodeSeed, DependsOnRunSeedWorldAndTrialOnly) {
  EXPECT_EQ(episodeSeed(7, 12, 3), episodeSeed(7, 12, 3));
  EXPECT_NE(episodeSeed(7, 12, 3), episodeSeed(7, 12, 4));
  EXPECT_NE(episodeSeed(7, 12, 3), episodeSeed(7, 13, 3));
  EXPECT_NE(episodeSeed(7, 12, 3), episodeSeed(8, 12, 3));
  // Swapping world and trial must not collide.
  EXPECT_NE(episodeSeed(7, 1, 2), episodeSeed(7, 2, 1));
  std::set<std::uint64_t> seeds;
  for (int world = 0; world < 300; ++world)
    for (int trial = 0; trial < 10; ++trial) seeds.insert(episodeSeed(0, world, trial));
  EXPECT_EQ(seeds.size(), 3000u);
}

TEST(Batch, APolicyForAnotherLidarFailsTheRunBeforeAnyEpisode) {
  BatchSpec spec;
  spec.worlds = {core::readWorldFile(std::filesystem::path(BARN_SOURCE_DIR) / "worlds" / core::worldFileName(0))};
  spec.make_controller = controllers::makeControllerFactory(
      core::ConfigNode::parseFile(std::filesystem::path(BARN_SOURCE_DIR) / "configs" / "controllers" / "lflh.yaml"));
  spec.episode.lidar.beams = 360;
  std::size_t episodes = 0;
  try {
    runBatch(spec, {}, [&](const EpisodeResult&, std::size_t, std::size_t) { ++episodes; });
    FAIL() << "a 720-beam policy on a 360-beam LiDAR must be an input error";
  } catch (const core::InputError& e) {
    EXPECT_THAT(std::string(e.what()), HasSubstr("reads 720 beams but the LiDAR gives 360"));
  }
  EXPECT_EQ(episodes, 0u);
}

TEST(Batch, AStopFlagAlreadySetStartsNoEpisode) {
  const std::atomic<bool> stop{true};
  EXPECT_TRUE(runBatch(pursuitSpec(), {.jobs = 2, .stop = &stop}).empty());
}

TEST(Batch, FactoryThatThrowsGivesErrorRowsNotACrash) {
  BatchSpec spec;
  spec.worlds = {core::readWorldFile(std::filesystem::path(BARN_SOURCE_DIR) / "worlds" / core::worldFileName(0))};
  spec.trials = 2;
  spec.make_controller = []() -> std::unique_ptr<controllers::Controller> {
    throw std::runtime_error("cannot load weights");
  };
  const std::vector<EpisodeResult> results = runBatch(spec, {.jobs = 2});
  ASSERT_EQ(results.size(), 2u);
  for (int trial = 0; trial < 2; ++trial) {
    const EpisodeResult& r = results[static_cast<std::size_t>(trial)];
    EXPECT_EQ(r.outcome, Outcome::Error);
    EXPECT_THAT(r.error, HasSubstr("cannot load weights"));
    EXPECT_EQ(r.world_id, 0);
    EXPECT_EQ(r.trial, trial);
  }
}

}  // namespace
}  // namespace barn::bench
