#pragma once
/// Scores and tables of a finished run, as the official report_test.py computes them.

#include <string>
#include <vector>

#include "barn/bench/episode.hpp"

namespace barn::bench {

/// report_test.py: every rate and the score are means over worlds of the per-world mean over
/// trials; the average time is the mean over worlds of the mean AT of successful trials
/// (worlds without a success do not count).
struct RunSummary {
  int worlds = 0;
  int episodes = 0;
  double score = 0.0;
  double success_rate = 0.0;
  double collision_rate = 0.0;
  double timeout_rate = 0.0;
  double error_rate = 0.0;
  double avg_success_time = 0.0;  // [s] NaN if no world had a success
  double sim_time = 0.0;          // [s] simulated in total
};

RunSummary summarise(const std::vector<EpisodeResult>& results);

/// The run's results over one group of worlds (a difficulty bucket).
struct BucketSummary {
  std::string group;   // "params" or a metric name ("norm_closest_wall", ...)
  std::string bucket;  // "fill 0.15 / smooth 2", "Q1 [-1.23, -0.45]", ...
  RunSummary summary;
};

/// Breakdown by difficulty: per generator parameter set (fill x smoothing) and per quartile of
/// each normalised metric (quartile edges over the run's worlds). Worlds without results are
/// skipped.
std::vector<BucketSummary> difficultyBreakdown(const std::vector<EpisodeResult>& results,
                                               const std::vector<core::WorldSpec>& worlds);

/// One world's results over its trials.
struct WorldStats {
  int world_id = 0;
  int trials = 0;
  int successes = 0;
  int collisions = 0;
  int timeouts = 0;
  int errors = 0;
  double success_rate = 0.0;
  double mean_score = 0.0;
  double score_ci_low = 0.0;   // 95 % interval of mean_score: mean -+ t(0.975, n - 1) sd / sqrt(n)
  double score_ci_high = 0.0;  //   (Student's t; NaN with a single trial)
  double mean_success_time = 0.0;  // [s] mean AT of successful trials; NaN without a success
  /// Majority outcome: more than half of the trials succeeded.
  bool mostlySucceeds() const { return 2 * successes > trials; }
};

/// Per-world statistics, ascending world id.
/// `max_score`: the protocol's maximum score, which bounds each world's interval (as 0 does
/// from below).
std::vector<WorldStats> perWorldStats(const std::vector<EpisodeResult>& results, double max_score);

/// What the worlds are: "barnbench-generated", "official BARN (imported)" or "mixed".
std::string worldSetName(const std::vector<core::WorldSpec>& worlds);

/// summary.json: the world set, the overall summary, the per-world scores and the breakdown.
/// Deterministic: no times or hosts.
std::string summaryJson(const std::string& world_set, const RunSummary& summary, const std::vector<WorldStats>& per_world,
                        const std::vector<BucketSummary>& breakdown);

/// The breakdown as a printed table.
std::string breakdownTable(const std::vector<BucketSummary>& breakdown);

/// The printed summary table.
std::string summaryTable(const RunSummary& summary, const std::string& title);

}  // namespace barn::bench
