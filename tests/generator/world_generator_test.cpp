#include "generator/world_generator.hpp"

#include <gtest/gtest.h>

#include "barn/core/world_file.hpp"
#include "generator/cspace.hpp"

namespace barn::generator {
namespace {

TEST(WorldGenerator, SameSeedGivesTheSameWorld) {
  std::optional<core::WorldSpec> a, b;
  std::uint64_t seed = 1;
  for (; !a; ++seed) a = generateWorld({0.2, 3}, seed, 0);
  b = generateWorld({0.2, 3}, seed - 1, 0);
  ASSERT_TRUE(b);
  EXPECT_EQ(core::formatWorldFile(*a), core::formatWorldFile(*b));
}

TEST(WorldGenerator, AcceptedWorldsSatisfyBarnsRules) {
  int accepted = 0;
  for (std::uint64_t seed = 100; seed < 160; ++seed) {
    const auto world = generateWorld({0.20, 3}, seed, 0);
    if (!world) continue;
    ++accepted;
    EXPECT_EQ(world->seed, seed);
    EXPECT_EQ(world->start_cell.col, 0);
    EXPECT_EQ(world->goal_cell.col, 29);
    const core::Grid cspace = dilateCspace(world->grid);
    EXPECT_EQ(cspace.at(world->start_cell), 0);
    EXPECT_EQ(cspace.at(world->goal_cell), 0);
    for (int c = 0; c < 30; ++c) EXPECT_EQ(world->grid.at(0, c) + world->grid.at(29, c), 2);
    ASSERT_GE(world->path.size(), 31u);  // at least 30 columns plus the duplicated start
    EXPECT_EQ(world->path[0], world->path[1]);
    EXPECT_EQ(world->path.back(), world->goal_cell);
    for (const auto& cell : world->path) EXPECT_EQ(cspace.at(cell), 0);
  }
  // About 6 in 10 attempts survive at fill 0.20 / smoothing 3 (measured over 340 seeds);
  // 60 attempts give 35 +- 4, so fewer than 20 means the rejection rules changed.
  EXPECT_GT(accepted, 20);
  EXPECT_LT(accepted, 60);  // some worlds must be rejected
}

TEST(WorldGenerator, SweepFollowsBarnsOrderAndNormalisesOverTheSet) {
  SweepConfig config;
  config.worlds_per_set = 2;
  const auto worlds = generateSweep(config);
  ASSERT_EQ(worlds.size(), 24u);  // 4 fills x 3 smoothings x 2
  EXPECT_EQ(worlds[0].fill_pct, 0.15);
  EXPECT_EQ(worlds[0].smooth_iter, 2);
  EXPECT_EQ(worlds[2].smooth_iter, 3);
  EXPECT_EQ(worlds[6].fill_pct, 0.20);
  EXPECT_EQ(worlds[23].fill_pct, 0.30);
  EXPECT_EQ(worlds[23].smooth_iter, 4);
  for (int i = 0; i < 24; ++i) EXPECT_EQ(worlds[static_cast<std::size_t>(i)].id, i);
  double mean_z = 0.0;
  for (const auto& w : worlds) mean_z += w.norm_metrics.tortuosity;
  EXPECT_NEAR(mean_z / 24.0, 0.0, 1e-12);  // z-scores over the set have mean 0
}

}  // namespace
}  // namespace barn::generator
