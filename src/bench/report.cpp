#include "barn/bench/report.hpp"

#include <cmath>
#include <cstdio>
#include <limits>
#include <map>
#include <algorithm>
#include <set>

#include <nlohmann/json.hpp>

#include "barn/core/text_io.hpp"

namespace barn::bench {

RunSummary summarise(const std::vector<EpisodeResult>& results) {
  struct PerWorld {
    int trials = 0, successes = 0, collisions = 0, timeouts = 0, errors = 0;
    double score = 0.0, success_time = 0.0;
  };
  std::map<int, PerWorld> worlds;
  RunSummary summary;
  for (const auto& r : results) {
    PerWorld& w = worlds[r.world_id];
    ++w.trials;
    w.score += r.score;
    w.successes += r.outcome == Outcome::Success;
    w.collisions += r.outcome == Outcome::Collision;
    w.timeouts += r.outcome == Outcome::Timeout;
    w.errors += r.outcome == Outcome::Error;
    if (r.outcome == Outcome::Success) w.success_time += r.actual_time;
    summary.sim_time += r.sim_time;
  }
  summary.worlds = static_cast<int>(worlds.size());
  summary.episodes = static_cast<int>(results.size());
  if (worlds.empty()) return summary;
  int worlds_with_success = 0;
  double time_sum = 0.0;
  for (const auto& [id, w] : worlds) {
    const double n = w.trials;
    summary.score += w.score / n;
    summary.success_rate += w.successes / n;
    summary.collision_rate += w.collisions / n;
    summary.timeout_rate += w.timeouts / n;
    summary.error_rate += w.errors / n;
    if (w.successes > 0) {
      time_sum += w.success_time / w.successes;
      ++worlds_with_success;
    }
  }
  const double n = static_cast<double>(worlds.size());
  summary.score /= n;
  summary.success_rate /= n;
  summary.collision_rate /= n;
  summary.timeout_rate /= n;
  summary.error_rate /= n;
  summary.avg_success_time = worlds_with_success ? time_sum / worlds_with_success : std::numeric_limits<double>::quiet_NaN();
  return summary;
}

std::vector<BucketSummary> difficultyBreakdown(const std::vector<EpisodeResult>& results,
                                               const std::vector<core::WorldSpec>& worlds) {
  std::set<int> with_results;
  for (const auto& r : results) with_results.insert(r.world_id);
  std::vector<const core::WorldSpec*> used;
  for (const auto& w : worlds)
    if (with_results.count(w.id)) used.push_back(&w);
  const auto resultsOf = [&](const std::set<int>& ids) {
    std::vector<EpisodeResult> subset;
    for (const auto& r : results)
      if (ids.count(r.world_id)) subset.push_back(r);
    return subset;
  };

  std::vector<BucketSummary> buckets;
  // Generator parameter sets, in order of first appearance (BARN's sweep order).
  std::vector<std::pair<double, int>> params;
  for (const auto* w : used)
    if (std::find(params.begin(), params.end(), std::make_pair(w->fill_pct, w->smooth_iter)) == params.end())
      params.emplace_back(w->fill_pct, w->smooth_iter);
  for (const auto& [fill, smooth] : params) {
    std::set<int> ids;
    for (const auto* w : used)
      if (w->fill_pct == fill && w->smooth_iter == smooth) ids.insert(w->id);
    char label[64];
    std::snprintf(label, sizeof(label), "fill %.2f / smooth %d", fill, smooth);
    buckets.push_back({"params", label, summarise(resultsOf(ids))});
  }
  // Quartiles of each normalised metric: world i of the sorted list goes to quartile
  // floor(4 i / n), so ties and small sets stay deterministic.
  for (std::size_t k = 0; k < core::DifficultyMetrics::kNames.size(); ++k) {
    std::vector<const core::WorldSpec*> sorted = used;
    std::stable_sort(sorted.begin(), sorted.end(), [k](const auto* a, const auto* b) {
      return a->norm_metrics.toArray()[k] < b->norm_metrics.toArray()[k];
    });
    const std::size_t n = sorted.size();
    for (std::size_t q = 0; q < 4; ++q) {
      std::set<int> ids;
      double lo = 0.0, hi = 0.0;
      for (std::size_t i = 0; i < n; ++i) {
        if (4 * i / n != q) continue;
        const double v = sorted[i]->norm_metrics.toArray()[k];
        if (ids.empty()) lo = v;
        hi = v;
        ids.insert(sorted[i]->id);
      }
      if (ids.empty()) continue;
      char label[96];
      std::snprintf(label, sizeof(label), "Q%zu [%+.2f, %+.2f]", q + 1, lo, hi);
      buckets.push_back({"norm_" + std::string(core::DifficultyMetrics::kNames[k]), label, summarise(resultsOf(ids))});
    }
  }
  return buckets;
}

namespace {

// Members keep the order they are written in, which is the order docs/records.md lists them in.
// nlohmann writes a non-finite double as null and a finite one as the shortest text that reads
// back as the same double.
using Json = nlohmann::ordered_json;

// The members of a summary, added to `json`.
void addSummaryFields(Json& json, const RunSummary& s) {
  json["worlds"] = s.worlds;
  json["episodes"] = s.episodes;
  json["score"] = s.score;
  json["success_rate"] = s.success_rate;
  json["collision_rate"] = s.collision_rate;
  json["timeout_rate"] = s.timeout_rate;
  json["error_rate"] = s.error_rate;
  json["avg_success_time_s"] = s.avg_success_time;
  json["sim_time_s"] = s.sim_time;
}

Json worldStatsJson(const WorldStats& w) {
  const double n = w.trials;
  return Json{{"world", w.world_id},
              {"trials", w.trials},
              {"score", w.mean_score},
              {"score_ci95", Json::array({w.score_ci_low, w.score_ci_high})},
              {"success_rate", w.success_rate},
              {"collision_rate", w.collisions / n},
              {"timeout_rate", w.timeouts / n},
              {"avg_success_time_s", w.mean_success_time}};
}

}  // namespace

std::string summaryJson(const std::string& world_set, const RunSummary& summary, const std::vector<WorldStats>& per_world,
                        const std::vector<BucketSummary>& breakdown) {
  Json worlds = Json::array();
  for (const WorldStats& w : per_world) worlds.push_back(worldStatsJson(w));
  Json buckets = Json::array();
  for (const BucketSummary& bucket : breakdown) {
    Json entry{{"group", bucket.group}, {"bucket", bucket.bucket}};
    addSummaryFields(entry, bucket.summary);
    buckets.push_back(std::move(entry));
  }
  Json json{{"world_set", world_set}, {"summary", Json::object()}};
  addSummaryFields(json["summary"], summary);
  json["per_world"] = std::move(worlds);
  json["breakdown"] = std::move(buckets);
  // Text that is not UTF-8 (it cannot come from barn's own labels) is written with U+FFFD, not refused.
  return json.dump(2, ' ', false, Json::error_handler_t::replace) + "\n";
}

std::vector<WorldStats> perWorldStats(const std::vector<EpisodeResult>& results, double max_score) {
  std::map<int, WorldStats> worlds;
  std::map<int, std::vector<double>> scores;
  std::map<int, double> time_sum;
  for (const auto& r : results) {
    WorldStats& w = worlds[r.world_id];
    w.world_id = r.world_id;
    ++w.trials;
    w.successes += r.outcome == Outcome::Success;
    w.collisions += r.outcome == Outcome::Collision;
    w.timeouts += r.outcome == Outcome::Timeout;
    w.errors += r.outcome == Outcome::Error;
    scores[r.world_id].push_back(r.score);
    if (r.outcome == Outcome::Success) time_sum[r.world_id] += r.actual_time;
  }
  // Student's t(0.975, df) for df = 1 ... 30; the normal 1.96 beyond.
  static constexpr double kT975[] = {12.706, 4.303, 3.182, 2.776, 2.571, 2.447, 2.365, 2.306, 2.262, 2.228,
                                     2.201,  2.179, 2.160, 2.145, 2.131, 2.120, 2.110, 2.101, 2.093, 2.086,
                                     2.080,  2.074, 2.069, 2.064, 2.060, 2.056, 2.052, 2.048, 2.045, 2.042};
  constexpr double kNaN = std::numeric_limits<double>::quiet_NaN();
  std::vector<WorldStats> out;
  for (auto& [id, w] : worlds) {
    const std::vector<double>& s = scores[id];
    const double n = w.trials;
    double sum = 0.0;
    for (double v : s) sum += v;
    w.success_rate = w.successes / n;
    w.mean_score = sum / n;
    w.mean_success_time = w.successes ? time_sum[id] / w.successes : kNaN;
    w.score_ci_low = w.score_ci_high = kNaN;
    if (w.trials > 1) {
      double squares = 0.0;
      for (double v : s) squares += (v - w.mean_score) * (v - w.mean_score);
      const int df = w.trials - 1;
      const double half = (df <= 30 ? kT975[df - 1] : 1.96) * std::sqrt(squares / df / n);
      // A score lies in [0, max_score]: so does every bound of its mean worth stating.
      w.score_ci_low = std::max(0.0, w.mean_score - half);
      w.score_ci_high = std::min(max_score, w.mean_score + half);
    }
    out.push_back(w);
  }
  return out;
}

std::string worldSetName(const std::vector<core::WorldSpec>& worlds) {
  bool generated = false, imported = false;
  for (const auto& w : worlds) (w.source == core::WorldSource::BarnDataset ? imported : generated) = true;
  if (generated && imported) return "mixed";
  return imported ? "official BARN (imported)" : "barnbench-generated";
}

std::string breakdownTable(const std::vector<BucketSummary>& breakdown) {
  std::string table = "  by difficulty                                       worlds  score  success  collision  timeout\n";
  std::string group;
  for (const auto& b : breakdown) {
    char line[256];
    std::snprintf(line, sizeof(line), "  %-30s %-22s %5d  %.4f  %.3f    %.3f      %.3f\n",
                  b.group == group ? "" : b.group.c_str(), b.bucket.c_str(), b.summary.worlds, b.summary.score,
                  b.summary.success_rate, b.summary.collision_rate, b.summary.timeout_rate);
    table += line;
    group = b.group;
  }
  return table;
}

std::string summaryTable(const RunSummary& s, const std::string& title) {
  char buffer[1024];
  std::snprintf(buffer, sizeof(buffer),
                "%s\n"
                "  worlds %d, episodes %d\n"
                "  Avg Score      %.4f\n"
                "  Avg Success    %.4f\n"
                "  Avg Collision  %.4f\n"
                "  Avg Timeout    %.4f\n"
                "  Avg Error      %.4f\n"
                "  Avg Time       %.4f s (successful trials)\n",
                title.c_str(), s.worlds, s.episodes, s.score, s.success_rate, s.collision_rate, s.timeout_rate,
                s.error_rate, s.avg_success_time);
  return buffer;
}

}  // namespace barn::bench
