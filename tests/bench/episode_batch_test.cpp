#include "barn/bench/episode_batch.hpp"

#include <gmock/gmock.h>
#include <gtest/gtest.h>

#include <cmath>
#include <filesystem>
#include <set>
#include <vector>

#include "barn/core/world_file.hpp"
#include "empty_world.hpp"

namespace barn::bench {
namespace {

using ::testing::HasSubstr;

std::vector<core::WorldSpec> realWorlds() {
  std::vector<core::WorldSpec> worlds;
  for (int id : {1, 2, 3, 4, 5})
    worlds.push_back(core::readWorldFile(std::filesystem::path(BARN_SOURCE_DIR) / "worlds" / core::worldFileName(id)));
  return worlds;
}

// Everything one step writes, for comparing two batches.
struct Snapshot {
  std::vector<float> scan;
  std::vector<double> pose, plan_end, reward, final_pose;
  std::vector<std::uint8_t> terminated, truncated, ended;
  std::vector<std::int32_t> world, final_world;
  std::vector<std::uint64_t> seed;
  bool operator==(const Snapshot&) const = default;
};

Snapshot snapshot(const EpisodeBatch& b) {
  return {b.observation.scan, b.observation.pose,  b.observation.plan_end, b.reward, b.final_observation.pose,
          b.terminated,       b.truncated,          b.ended,                b.info.world, b.final_info.world,
          b.info.seed};
}

// A fixed, deterministic policy: forward with a weave that differs per sub-environment.
std::vector<double> actionsAt(int step, int n) {
  std::vector<double> a(2 * static_cast<std::size_t>(n));
  for (int i = 0; i < n; ++i) {
    a[2 * static_cast<std::size_t>(i)] = 0.8;
    a[2 * static_cast<std::size_t>(i) + 1] = 0.6 * std::sin(0.3 * step + i);
  }
  return a;
}

std::vector<Snapshot> runBatch(int threads, int steps) {
  EpisodeBatchConfig c;
  c.num_envs = 8;
  c.dt = 0.2;
  c.max_steps = 40;
  c.global_plan = controllers::GlobalPlanConfig{};
  c.threads = threads;
  EpisodeBatch batch(realWorlds(), c);
  batch.reset(7);
  std::vector<Snapshot> out{snapshot(batch)};
  for (int s = 0; s < steps; ++s) {
    batch.step(actionsAt(s, c.num_envs).data());
    out.push_back(snapshot(batch));
  }
  return out;
}

TEST(EpisodeBatch, EightSubEnvironmentsGiveTheSameBatchesOnOneOrTwoThreads) {
  // 60 steps of 0.2 s with max_steps 40: every sub-environment ends (collides or is cut at 40
  // steps) and restarts at least once, so autoresets are compared too.
  const std::vector<Snapshot> one = runBatch(1, 60);
  const std::vector<Snapshot> two = runBatch(2, 60);
  ASSERT_EQ(one.size(), two.size());
  int ends = 0;
  for (std::size_t k = 0; k < one.size(); ++k) {
    EXPECT_TRUE(one[k] == two[k]) << "step " << k;
    for (std::uint8_t e : one[k].ended) ends += e;
  }
  EXPECT_GE(ends, 8);
}

TEST(EpisodeBatch, SeedsAndWorldsFollowTheResetSeedTheIndexAndTheEpisodeCountOnly) {
  EpisodeBatchConfig c;
  c.num_envs = 3;
  c.dt = 0.1;
  EpisodeBatch batch(realWorlds(), c);
  batch.reset(11);
  for (int i = 0; i < 3; ++i) {
    const std::size_t r = static_cast<std::size_t>(i);
    EXPECT_EQ(batch.info.seed[r], episodeSeedOf(11, i, 0));
    EXPECT_EQ(batch.info.world[r], realWorlds()[worldIndexOf(11, i, 0, 5)].id);
  }
  // Another sub-environment count leaves sub-environment 0's episodes unchanged.
  EpisodeBatchConfig wide = c;
  wide.num_envs = 5;
  EpisodeBatch other(realWorlds(), wide);
  other.reset(11);
  EXPECT_EQ(other.info.seed[0], batch.info.seed[0]);
  EXPECT_EQ(other.observation.scan[100], batch.observation.scan[100]);
  // Over many draws the sampler visits every world of the list.
  std::set<std::size_t> seen;
  for (std::uint64_t k = 0; k < 200; ++k) seen.insert(worldIndexOf(3, 0, k, 5));
  EXPECT_EQ(seen.size(), 5u);
}

TEST(EpisodeBatch, AnEndedEpisodeKeepsItsLastObservationAndResultAndTheNextOneStarts) {
  // The empty world, straight ahead at 1 m/s in steps of 0.5 s: the goal 10 m ahead is reached.
  EpisodeBatchConfig c;
  c.num_envs = 1;
  c.dt = 0.5;
  c.reward = {1.0, 0.0, 10.0, -10.0, 0.0};
  EpisodeBatch batch({emptyWorld()}, c);
  batch.reset(3);
  const auto distance = [](const BatchObservation& o) { return std::hypot(o.goal[0] - o.pose[0], o.goal[1] - o.pose[1]); };
  const double start_distance = distance(batch.observation);
  double sum = 0.0;
  int steps = 0;
  while (!batch.ended[0]) {
    const double a[2] = {1.0, 0.0};
    batch.step(a);
    sum += batch.reward[0];
    ++steps;
    ASSERT_LT(steps, 100);
  }
  EXPECT_TRUE(batch.terminated[0]);
  EXPECT_EQ(batch.final_info.outcome[0], static_cast<std::int8_t>(BatchOutcome::Success));
  EXPECT_GT(batch.final_info.score[0], 0.0);
  EXPECT_EQ(batch.final_info.length[0], steps);
  EXPECT_DOUBLE_EQ(batch.final_info.episode_return[0], sum);
  // The progress terms add up to the drop of the distance from the first observation to the
  // last one kept (the last tick's, as Env's: at most 0.5 s before the success check), plus 10.
  const double end_distance = distance(batch.final_observation);
  EXPECT_NEAR(sum, 10.0 + start_distance - end_distance, 1e-9);
  EXPECT_LT(end_distance, 1.0 + 0.5 * 1.0);  // the success radius plus one step at 1 m/s
  EXPECT_GT(start_distance, 9.0);
  // The observation row is the new episode's first: at the start, time 0, the next seed.
  EXPECT_EQ(batch.observation.time[0], 0.0);
  EXPECT_EQ(batch.observation.pose[1], 0.0);
  EXPECT_EQ(batch.info.seed[0], episodeSeedOf(3, 0, 1));
  EXPECT_EQ(batch.info.length[0], 0);
}

TEST(EpisodeBatch, MaxStepsTruncatesAsATimeout) {
  EpisodeBatchConfig c;
  c.dt = 0.1;
  c.max_steps = 5;
  c.reward.timeout = -3.0;
  c.reward.progress = 0.0;
  EpisodeBatch batch({emptyWorld()}, c);
  batch.reset(1);
  const double stand[2] = {0.0, 0.0};
  for (int s = 0; s < 4; ++s) {
    batch.step(stand);
    EXPECT_FALSE(batch.ended[0]);
  }
  batch.step(stand);
  EXPECT_TRUE(batch.truncated[0]);
  EXPECT_FALSE(batch.terminated[0]);
  EXPECT_EQ(batch.final_info.outcome[0], static_cast<std::int8_t>(BatchOutcome::Timeout));
  EXPECT_DOUBLE_EQ(batch.reward[0], -3.0);
}

TEST(EpisodeBatch, ThePlanIsResampledAlongItsLengthAndEndsAtTheGoal) {
  // The empty world: NavFn's plan runs straight from the start (0, 0) to the goal (0, 10) in
  // the odom frame, so points every 0.5 m lie at y = 0, 0.5, 1.0, ...
  EpisodeBatchConfig c;
  c.dt = 0.05;
  c.global_plan = controllers::GlobalPlanConfig{};
  c.plan_points = 4;
  c.plan_spacing = 0.5;
  EpisodeBatch batch({emptyWorld()}, c);
  batch.reset(2);
  const std::vector<double>& p = batch.observation.plan;
  ASSERT_EQ(p.size(), 12u);
  EXPECT_GE(batch.observation.plan_stamp[0], 0.0);
  for (int k = 0; k < 4; ++k) {
    EXPECT_NEAR(p[3 * static_cast<std::size_t>(k)], 0.0, 0.06) << k;
    EXPECT_NEAR(p[3 * static_cast<std::size_t>(k) + 1], 0.5 * k, 0.06) << k;
  }
  EXPECT_NEAR(batch.observation.plan_end[0], batch.observation.goal[0], 0.06);
  EXPECT_NEAR(batch.observation.plan_end[1], batch.observation.goal[1], 0.06);
}

TEST(EpisodeBatch, BadConfigsAndUseBeforeResetAreInputErrors) {
  EpisodeBatchConfig c;
  c.num_envs = 0;
  EXPECT_THROW(EpisodeBatch({emptyWorld()}, c), core::InputError);
  c.num_envs = 1;
  c.dt = 0.013;  // not whole physics steps
  EXPECT_THROW(EpisodeBatch({emptyWorld()}, c), core::InputError);
  c.dt = 0.1;
  c.plan_points = 3;  // without a global_plan block
  try {
    EpisodeBatch b({emptyWorld()}, c);
    FAIL() << "expected an InputError";
  } catch (const core::InputError& e) {
    EXPECT_THAT(e.what(), HasSubstr("plan_points"));
  }
  c.plan_points = 0;
  EXPECT_THROW(EpisodeBatch({}, c), core::InputError);
  EpisodeBatch batch({emptyWorld()}, c);
  const double a[2] = {0.0, 0.0};
  EXPECT_THROW(batch.step(a), core::InputError);
}

}  // namespace
}  // namespace barn::bench
