// Comparing two records (bench/compare.hpp): ranks, Spearman, the bootstrap interval and the
// comparison of a record with itself.

#include "barn/bench/compare.hpp"

#include <gmock/gmock.h>
#include <gtest/gtest.h>

#include <cmath>

#include "barn/core/errors.hpp"

namespace barn::bench {
namespace {

EpisodeResult episode(int world, int trial, Outcome outcome, double time, double score) {
  EpisodeResult r;
  r.world_id = world;
  r.trial = trial;
  r.outcome = outcome;
  r.actual_time = time;
  r.score = outcome == Outcome::Success ? score : 0.0;
  return r;
}

// Six worlds x 4 trials with varied success rates and times.
std::vector<EpisodeResult> sampleRun() {
  std::vector<EpisodeResult> results;
  for (int w = 0; w < 6; ++w) {
    for (int t = 0; t < 4; ++t) {
      const Outcome outcome = t < 4 - w % 4 ? Outcome::Success : (t % 2 ? Outcome::Collision : Outcome::Timeout);
      results.push_back(episode(6 * w, t, outcome, 20.0 + 3.0 * w + t, 0.25 - 0.02 * w - 0.01 * t));
    }
  }
  return results;
}

TEST(Compare, AverageRanksShareTies) {
  EXPECT_EQ(averageRanks({10.0, 30.0, 20.0}), (std::vector<double>{1.0, 3.0, 2.0}));
  // 2 and 2 take ranks 2 and 3: both 2.5. The three 5s take 4, 5, 6: all 5.
  EXPECT_EQ(averageRanks({2.0, 1.0, 5.0, 2.0, 5.0, 5.0}), (std::vector<double>{2.5, 1.0, 5.0, 2.5, 5.0, 5.0}));
}

TEST(Compare, SpearmanOnHandComputedExamples) {
  // No ties: x = 1..5, y = 2 1 4 3 5 -> d = -1 1 -1 1 0, sum d^2 = 4,
  // rho = 1 - 6 * 4 / (5 * (25 - 1)) = 1 - 24 / 120 = 0.8.
  EXPECT_NEAR(spearman({1, 2, 3, 4, 5}, {2, 1, 4, 3, 5}), 0.8, 1e-12);
  // A tie: x = 1 2 2 3 -> ranks 1 2.5 2.5 4; y = 10 20 30 40 -> ranks 1 2 3 4; both mean 2.5.
  // Deviations: x -1.5 0 0 1.5, y -1.5 -0.5 0.5 1.5.
  // sxy = 2.25 + 0 + 0 + 2.25 = 4.5; sxx = 4.5; syy = 2.25 + 0.25 + 0.25 + 2.25 = 5.
  // rho = 4.5 / sqrt(4.5 * 5) = 4.5 / sqrt(22.5) = 3 / sqrt(10) = 0.948683...
  EXPECT_NEAR(spearman({1, 2, 2, 3}, {10, 20, 30, 40}), 3.0 / std::sqrt(10.0), 1e-12);
  EXPECT_NEAR(spearman({1, 2, 3}, {30, 20, 10}), -1.0, 1e-12);
  // Undefined: too short, constant, or of different lengths.
  EXPECT_TRUE(std::isnan(spearman({1}, {2})));
  EXPECT_TRUE(std::isnan(spearman({1, 1, 1}, {1, 2, 3})));
  EXPECT_TRUE(std::isnan(spearman({1, 2}, {1, 2, 3})));
}

TEST(Compare, BootstrapIntervalContainsTheEstimateAndIsDeterministic) {
  const std::vector<double> values = {0.1, -0.05, 0.2, 0.0, 0.03, 0.12, -0.02, 0.07, 0.3, -0.1};
  const BootstrapInterval a = bootstrapMean(values, 10000, 42);
  EXPECT_NEAR(a.estimate, 0.065, 1e-12);
  EXPECT_LT(a.low, a.estimate);
  EXPECT_GT(a.high, a.estimate);
  // A 95 % interval of a mean is narrower than the data's range.
  EXPECT_GT(a.low, -0.1);
  EXPECT_LT(a.high, 0.3);
  const BootstrapInterval again = bootstrapMean(values, 10000, 42);
  EXPECT_EQ(again.low, a.low);
  EXPECT_EQ(again.high, a.high);
  const BootstrapInterval other = bootstrapMean(values, 10000, 43);
  EXPECT_TRUE(other.low != a.low || other.high != a.high);
  // Constant data: every resample has the same mean.
  const BootstrapInterval constant = bootstrapMean({0.5, 0.5, 0.5}, 100, 1);
  EXPECT_EQ(constant.low, 0.5);
  EXPECT_EQ(constant.high, 0.5);
  EXPECT_THROW(bootstrapMean({}, 10, 1), std::invalid_argument);
  EXPECT_THROW(bootstrapMean({1.0}, 0, 1), std::invalid_argument);
}

TEST(Compare, PerWorldStatsCountOutcomesAndMeanSuccessfulTime) {
  const std::vector<EpisodeResult> results = {episode(4, 0, Outcome::Success, 20.0, 0.2),
                                              episode(4, 1, Outcome::Collision, 5.0, 0.0),
                                              episode(4, 2, Outcome::Success, 30.0, 0.1),
                                              episode(2, 0, Outcome::Timeout, 100.0, 0.0)};
  const std::vector<WorldStats> stats = perWorldStats(results, 0.25);
  ASSERT_EQ(stats.size(), 2u);
  EXPECT_EQ(stats[0].world_id, 2);
  EXPECT_TRUE(std::isnan(stats[0].mean_success_time));
  EXPECT_FALSE(stats[0].mostlySucceeds());
  EXPECT_EQ(stats[1].successes, 2);
  EXPECT_EQ(stats[1].collisions, 1);
  EXPECT_DOUBLE_EQ(stats[1].mean_success_time, 25.0);
  EXPECT_DOUBLE_EQ(stats[1].mean_score, 0.1);
  EXPECT_DOUBLE_EQ(stats[1].success_rate, 2.0 / 3.0);
  EXPECT_TRUE(stats[1].mostlySucceeds());
}

TEST(Compare, ARecordComparedWithItself) {
  const Comparison c = compareResults(sampleRun(), sampleRun(), 2000, 7);
  EXPECT_EQ(c.a.size(), 6u);
  EXPECT_TRUE(c.only_a.empty());
  EXPECT_TRUE(c.only_b.empty());
  EXPECT_EQ(c.score_difference.estimate, 0.0);
  EXPECT_EQ(c.score_difference.low, 0.0);
  EXPECT_EQ(c.score_difference.high, 0.0);
  EXPECT_EQ(c.success_difference.estimate, 0.0);
  EXPECT_EQ(c.success_difference.low, 0.0);
  EXPECT_EQ(c.success_difference.high, 0.0);
  EXPECT_TRUE(c.disagree.empty());
  EXPECT_EQ(c.both_succeed + c.both_fail, 6);
  EXPECT_EQ(c.spearman_time_worlds, 6);
  EXPECT_DOUBLE_EQ(c.spearman_time, 1.0);
  EXPECT_DOUBLE_EQ(c.spearman_success, 1.0);
  const std::string report = comparisonReport(c, "A", "B");
  EXPECT_THAT(report, ::testing::HasSubstr("disagree 0"));
}

TEST(Compare, DifferencesAgreementAndCommonWorlds) {
  // A: worlds 0 and 6 succeed, world 12 fails; B: world 0 succeeds faster, 6 fails, 12
  // succeeds, and B has a world 18 that A lacks.
  const std::vector<EpisodeResult> a = {episode(0, 0, Outcome::Success, 30, 0.2), episode(6, 0, Outcome::Success, 40, 0.1),
                                        episode(12, 0, Outcome::Timeout, 100, 0)};
  const std::vector<EpisodeResult> b = {episode(0, 0, Outcome::Success, 20, 0.25), episode(6, 0, Outcome::Collision, 5, 0),
                                        episode(12, 0, Outcome::Success, 50, 0.1), episode(18, 0, Outcome::Success, 9, 0.25)};
  const Comparison c = compareResults(a, b, 1000, 3);
  EXPECT_EQ(c.a.size(), 3u);
  EXPECT_EQ(c.only_b, (std::vector<int>{18}));
  // Per-world score differences 0.05, -0.1, 0.1: mean 0.05 / 3.
  EXPECT_NEAR(c.score_difference.estimate, 0.05 / 3.0, 1e-12);
  EXPECT_NEAR(c.score_a, 0.1, 1e-12);
  EXPECT_NEAR(c.score_b, 0.35 / 3.0, 1e-12);
  EXPECT_NEAR(c.success_difference.estimate, 0.0, 1e-12);
  EXPECT_LE(c.score_difference.low, c.score_difference.estimate);
  EXPECT_GE(c.score_difference.high, c.score_difference.estimate);
  EXPECT_EQ(c.both_succeed, 1);
  EXPECT_EQ(c.both_fail, 0);
  EXPECT_EQ(c.disagree, (std::vector<int>{6, 12}));
  EXPECT_EQ(c.spearman_time_worlds, 1);  // only world 0 has successes on both sides
  EXPECT_TRUE(std::isnan(c.spearman_time));
  // Collision rates A 0, 0, 0 and B 0, 1, 0: B - A = 1 / 3; timeouts A 0, 0, 1 and B 0, 0, 0.
  EXPECT_NEAR(c.collision_a, 0.0, 1e-12);
  EXPECT_NEAR(c.collision_b, 1.0 / 3.0, 1e-12);
  EXPECT_NEAR(c.collision_difference.estimate, 1.0 / 3.0, 1e-12);
  EXPECT_NEAR(c.timeout_a, 1.0 / 3.0, 1e-12);
  EXPECT_NEAR(c.timeout_difference.estimate, -1.0 / 3.0, 1e-12);
  // Mean successful times where both succeed: world 0 only, 20 / 30.
  EXPECT_EQ(c.time_ratio_worlds, 1);
  EXPECT_NEAR(c.time_ratio.estimate, 2.0 / 3.0, 1e-12);
  EXPECT_NEAR(c.time_ratio.low, 2.0 / 3.0, 1e-12);  // one world: every resample is that world
}

TEST(Compare, BootstrapRatioOfMeansOfProportionalPairsIsTheirFactor) {
  // B = 1.5 A world by world: every resample's ratio of means is 1.5.
  const std::vector<double> a = {10.0, 20.0, 35.0, 12.5}, b = {15.0, 30.0, 52.5, 18.75};
  const BootstrapInterval r = bootstrapRatioOfMeans(b, a, 500, 9);
  EXPECT_NEAR(r.estimate, 1.5, 1e-12);
  EXPECT_NEAR(r.low, 1.5, 1e-12);
  EXPECT_NEAR(r.high, 1.5, 1e-12);
  // Not proportional: the interval brackets the estimate (77.5 / 115 for these).
  const BootstrapInterval s = bootstrapRatioOfMeans({10.0, 40.0, 20.0, 7.5}, {20.0, 30.0, 40.0, 25.0}, 2000, 9);
  EXPECT_NEAR(s.estimate, 77.5 / 115.0, 1e-12);
  EXPECT_LT(s.low, s.estimate);
  EXPECT_GT(s.high, s.estimate);
  EXPECT_THROW(bootstrapRatioOfMeans({1.0}, {1.0, 2.0}, 10, 1), std::invalid_argument);
}

TEST(Compare, NoCommonWorldIsAnInputError) {
  EXPECT_THROW(compareResults({episode(0, 0, Outcome::Success, 30, 0.2)}, {episode(6, 0, Outcome::Success, 30, 0.2)}, 10, 1),
               core::InputError);
}

}  // namespace
}  // namespace barn::bench
