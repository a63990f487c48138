#pragma once
/// Two run records over their common worlds, as a fidelity engineer compares them: per-world
/// outcomes, the paired difference of the aggregates with a bootstrap interval over worlds,
/// majority-outcome agreement and rank correlations. It reports; it does not judge.

#include <cstdint>
#include <string>
#include <vector>

#include "barn/bench/episode.hpp"
#include "barn/bench/report.hpp"

namespace barn::bench {

/// Ranks 1..n of `values`, tied values sharing the mean of their ranks.
std::vector<double> averageRanks(const std::vector<double>& values);

/// Spearman's rank correlation: Pearson's correlation of the average ranks. NaN if the
/// lengths differ, there are fewer than 2 values, or either side is constant.
double spearman(const std::vector<double>& x, const std::vector<double>& y);

/// A point estimate and its percentile bootstrap interval.
struct BootstrapInterval {
  double estimate = 0.0;
  double low = 0.0;
  double high = 0.0;
};

/// Mean of `values` and the percentile interval of its bootstrap distribution at `level`:
/// `resamples` times, draw values.size() values with replacement (core::Rng(seed).below) and
/// take their mean; the bounds are the (1 - level) / 2 and (1 + level) / 2 quantiles of those
/// means (linear interpolation between order statistics). Deterministic for a seed.
/// `values` must not be empty and resamples >= 1 (std::invalid_argument otherwise).
BootstrapInterval bootstrapMean(const std::vector<double>& values, int resamples, std::uint64_t seed,
                                double level = 0.95);

/// The ratio of the means of `numerator` and `denominator` (paired values) and its percentile
/// bootstrap interval: pairs resampled as bootstrapMean resamples values (the same draws for a
/// seed and a length). Both must have the same non-zero length.
BootstrapInterval bootstrapRatioOfMeans(const std::vector<double>& numerator, const std::vector<double>& denominator,
                                        int resamples, std::uint64_t seed, double level = 0.95);

/// A and B over their common worlds.
struct Comparison {
  std::vector<WorldStats> a, b;  // same worlds, ascending id
  std::vector<int> only_a, only_b;  // worlds of one record only (not compared)
  // Aggregates over the common worlds (report_test.py's means over worlds).
  double score_a = 0.0, score_b = 0.0;
  double success_a = 0.0, success_b = 0.0;
  double collision_a = 0.0, collision_b = 0.0;
  double timeout_a = 0.0, timeout_b = 0.0;
  BootstrapInterval score_difference;      // B - A, paired per world
  BootstrapInterval success_difference;    // B - A
  BootstrapInterval collision_difference;  // B - A
  BootstrapInterval timeout_difference;    // B - A
  // B's mean successful time over A's, over the worlds where both succeed at least once (each
  // world's mean over its successful trials; the ratio of their means over those worlds).
  BootstrapInterval time_ratio;
  int time_ratio_worlds = 0;
  int resamples = 0;
  std::uint64_t seed = 0;
  // Majority outcomes.
  int both_succeed = 0;
  int both_fail = 0;
  std::vector<int> disagree;  // world ids
  // Rank correlations across worlds.
  double spearman_time = 0.0;  // of mean successful times, over worlds where both succeed at least once
  int spearman_time_worlds = 0;
  double spearman_success = 0.0;  // of success rates, over all common worlds
};

/// Compares two records' episodes. InputError if they have no world in common; `resamples`
/// must be >= 1.
Comparison compareResults(const std::vector<EpisodeResult>& a, const std::vector<EpisodeResult>& b, int resamples,
                          std::uint64_t seed);

/// The printed report: per-world table, aggregates with intervals, agreement, correlations.
std::string comparisonReport(const Comparison& c, const std::string& label_a, const std::string& label_b);

}  // namespace barn::bench
