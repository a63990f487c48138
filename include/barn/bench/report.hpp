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

/// episodes.csv: one row per episode, sorted as given.
std::string episodesCsv(const std::vector<EpisodeResult>& results);

/// One episode's trajectory record: time, world pose, command and state per control tick.
std::string trajectoryCsv(const EpisodeResult& result);

/// The printed summary table.
std::string summaryTable(const RunSummary& summary, const std::string& title);

}  // namespace barn::bench
