#include "barn/bench/compare.hpp"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <limits>
#include <map>
#include <numeric>
#include <set>
#include <stdexcept>

#include "barn/core/errors.hpp"
#include "barn/core/rng.hpp"

namespace barn::bench {

namespace {

constexpr double kNaN = std::numeric_limits<double>::quiet_NaN();

double mean(const std::vector<double>& v) {
  return v.empty() ? kNaN : std::accumulate(v.begin(), v.end(), 0.0) / static_cast<double>(v.size());
}

// Quantile p of sorted values, linear interpolation between order statistics (h = (n-1) p).
double quantile(const std::vector<double>& sorted, double p) {
  const double h = (static_cast<double>(sorted.size()) - 1.0) * p;
  const std::size_t lo = static_cast<std::size_t>(std::floor(h));
  const std::size_t hi = std::min(lo + 1, sorted.size() - 1);
  return sorted[lo] + (h - static_cast<double>(lo)) * (sorted[hi] - sorted[lo]);
}

std::string fmt(const char* format, double v) {
  if (!std::isfinite(v)) return "n/a";
  char buffer[64];
  std::snprintf(buffer, sizeof buffer, format, v);
  return buffer;
}

}  // namespace

std::vector<double> averageRanks(const std::vector<double>& values) {
  const std::size_t n = values.size();
  std::vector<std::size_t> order(n);
  std::iota(order.begin(), order.end(), std::size_t{0});
  std::stable_sort(order.begin(), order.end(), [&](std::size_t i, std::size_t j) { return values[i] < values[j]; });
  std::vector<double> ranks(n);
  for (std::size_t i = 0; i < n;) {
    std::size_t j = i;
    while (j + 1 < n && values[order[j + 1]] == values[order[i]]) ++j;
    const double rank = 0.5 * static_cast<double>(i + j) + 1.0;  // mean of ranks i+1 .. j+1
    for (std::size_t k = i; k <= j; ++k) ranks[order[k]] = rank;
    i = j + 1;
  }
  return ranks;
}

double spearman(const std::vector<double>& x, const std::vector<double>& y) {
  if (x.size() != y.size() || x.size() < 2) return kNaN;
  const std::vector<double> rx = averageRanks(x), ry = averageRanks(y);
  const double mx = mean(rx), my = mean(ry);
  double sxy = 0.0, sxx = 0.0, syy = 0.0;
  for (std::size_t i = 0; i < rx.size(); ++i) {
    sxy += (rx[i] - mx) * (ry[i] - my);
    sxx += (rx[i] - mx) * (rx[i] - mx);
    syy += (ry[i] - my) * (ry[i] - my);
  }
  if (sxx == 0.0 || syy == 0.0) return kNaN;
  return sxy / std::sqrt(sxx * syy);
}

BootstrapInterval bootstrapMean(const std::vector<double>& values, int resamples, std::uint64_t seed, double level) {
  if (values.empty()) throw std::invalid_argument("bootstrapMean: no values");
  if (resamples < 1) throw std::invalid_argument("bootstrapMean: resamples must be >= 1");
  core::Rng rng(seed);
  const std::size_t n = values.size();
  std::vector<double> means(static_cast<std::size_t>(resamples));
  for (double& m : means) {
    double sum = 0.0;
    for (std::size_t i = 0; i < n; ++i) sum += values[rng.below(n)];
    m = sum / static_cast<double>(n);
  }
  std::sort(means.begin(), means.end());
  BootstrapInterval interval;
  interval.estimate = mean(values);
  interval.low = quantile(means, 0.5 * (1.0 - level));
  interval.high = quantile(means, 0.5 * (1.0 + level));
  return interval;
}

BootstrapInterval bootstrapRatioOfMeans(const std::vector<double>& numerator, const std::vector<double>& denominator,
                                        int resamples, std::uint64_t seed, double level) {
  if (numerator.empty() || numerator.size() != denominator.size())
    throw std::invalid_argument("bootstrapRatioOfMeans: needs pairs");
  if (resamples < 1) throw std::invalid_argument("bootstrapRatioOfMeans: resamples must be >= 1");
  core::Rng rng(seed);
  const std::size_t n = numerator.size();
  std::vector<double> ratios(static_cast<std::size_t>(resamples));
  for (double& r : ratios) {
    double top = 0.0, bottom = 0.0;
    for (std::size_t i = 0; i < n; ++i) {
      const std::size_t k = rng.below(n);
      top += numerator[k];
      bottom += denominator[k];
    }
    r = top / bottom;
  }
  std::sort(ratios.begin(), ratios.end());
  BootstrapInterval interval;
  interval.estimate = mean(numerator) / mean(denominator);
  interval.low = quantile(ratios, 0.5 * (1.0 - level));
  interval.high = quantile(ratios, 0.5 * (1.0 + level));
  return interval;
}

Comparison compareResults(const std::vector<EpisodeResult>& a, const std::vector<EpisodeResult>& b, int resamples,
                          std::uint64_t seed) {
  // Only the worlds' means and rates are compared here, not their intervals.
  constexpr double kUnbounded = std::numeric_limits<double>::infinity();
  const std::vector<WorldStats> all_a = perWorldStats(a, kUnbounded), all_b = perWorldStats(b, kUnbounded);
  std::map<int, const WorldStats*> in_b;
  for (const auto& w : all_b) in_b.emplace(w.world_id, &w);
  Comparison c;
  c.resamples = resamples;
  c.seed = seed;
  std::set<int> common;
  for (const auto& w : all_a) {
    const auto it = in_b.find(w.world_id);
    if (it == in_b.end()) {
      c.only_a.push_back(w.world_id);
      continue;
    }
    common.insert(w.world_id);
    c.a.push_back(w);
    c.b.push_back(*it->second);
  }
  for (const auto& w : all_b)
    if (!common.count(w.world_id)) c.only_b.push_back(w.world_id);
  if (c.a.empty()) throw core::InputError("compare: the records have no world in common");

  std::vector<double> score_diff, success_diff, collision_diff, timeout_diff, rate_a, rate_b, time_a, time_b;
  for (std::size_t i = 0; i < c.a.size(); ++i) {
    const WorldStats& wa = c.a[i];
    const WorldStats& wb = c.b[i];
    score_diff.push_back(wb.mean_score - wa.mean_score);
    success_diff.push_back(wb.success_rate - wa.success_rate);
    const double collisions_a = wa.collisions / static_cast<double>(wa.trials);
    const double collisions_b = wb.collisions / static_cast<double>(wb.trials);
    const double timeouts_a = wa.timeouts / static_cast<double>(wa.trials);
    const double timeouts_b = wb.timeouts / static_cast<double>(wb.trials);
    collision_diff.push_back(collisions_b - collisions_a);
    timeout_diff.push_back(timeouts_b - timeouts_a);
    c.collision_a += collisions_a;
    c.collision_b += collisions_b;
    c.timeout_a += timeouts_a;
    c.timeout_b += timeouts_b;
    rate_a.push_back(wa.success_rate);
    rate_b.push_back(wb.success_rate);
    c.score_a += wa.mean_score;
    c.score_b += wb.mean_score;
    c.success_a += wa.success_rate;
    c.success_b += wb.success_rate;
    if (wa.successes > 0 && wb.successes > 0) {
      time_a.push_back(wa.mean_success_time);
      time_b.push_back(wb.mean_success_time);
    }
    if (wa.mostlySucceeds() && wb.mostlySucceeds()) ++c.both_succeed;
    else if (!wa.mostlySucceeds() && !wb.mostlySucceeds()) ++c.both_fail;
    else c.disagree.push_back(wa.world_id);
  }
  const double n = static_cast<double>(c.a.size());
  c.score_a /= n;
  c.score_b /= n;
  c.success_a /= n;
  c.success_b /= n;
  c.collision_a /= n;
  c.collision_b /= n;
  c.timeout_a /= n;
  c.timeout_b /= n;
  // The same seed for both: the same resampled worlds for the two differences.
  c.score_difference = bootstrapMean(score_diff, resamples, seed);
  c.success_difference = bootstrapMean(success_diff, resamples, seed);
  c.collision_difference = bootstrapMean(collision_diff, resamples, seed);
  c.timeout_difference = bootstrapMean(timeout_diff, resamples, seed);
  constexpr double kNaN = std::numeric_limits<double>::quiet_NaN();
  c.time_ratio = time_a.empty() ? BootstrapInterval{kNaN, kNaN, kNaN} : bootstrapRatioOfMeans(time_b, time_a, resamples, seed);
  c.time_ratio_worlds = static_cast<int>(time_a.size());
  c.spearman_time = spearman(time_a, time_b);
  c.spearman_time_worlds = static_cast<int>(time_a.size());
  c.spearman_success = spearman(rate_a, rate_b);
  return c;
}

std::string comparisonReport(const Comparison& c, const std::string& label_a, const std::string& label_b) {
  std::string out;
  char line[512];
  std::snprintf(line, sizeof line, "A = %s\nB = %s\n", label_a.c_str(), label_b.c_str());
  out += line;
  const auto idList = [](const std::vector<int>& ids) {
    std::string text;
    for (int id : ids) text += (text.empty() ? "" : ", ") + std::to_string(id);
    return text;
  };
  std::snprintf(line, sizeof line, "%zu common worlds", c.a.size());
  out += line;
  if (!c.only_a.empty()) out += "; only in A (not compared): " + idList(c.only_a);
  if (!c.only_b.empty()) out += "; only in B (not compared): " + idList(c.only_b);
  out += "\n\n";
  out += "world |  A s/c/t/e  time_s   score |  B s/c/t/e  time_s   score\n";
  for (std::size_t i = 0; i < c.a.size(); ++i) {
    const auto cell = [](const WorldStats& w) {
      char text[128];
      const std::string counts = std::to_string(w.successes) + "/" + std::to_string(w.collisions) + "/" +
                                 std::to_string(w.timeouts) + "/" + std::to_string(w.errors);
      std::snprintf(text, sizeof text, "%11s %7s  %6.4f", counts.c_str(), fmt("%.2f", w.mean_success_time).c_str(),
                    w.mean_score);
      return std::string(text);
    };
    std::snprintf(line, sizeof line, "%5d |%s |%s%s\n", c.a[i].world_id, cell(c.a[i]).c_str(),
                  cell(c.b[i]).c_str(), c.a[i].mostlySucceeds() != c.b[i].mostlySucceeds() ? "  disagree" : "");
    out += line;
  }
  out += "  (s/c/t/e: successes/collisions/timeouts/errors; time_s: mean AT of successes)\n\n";
  const double level = 95.0;
  std::snprintf(line, sizeof line,
                "aggregate over the common worlds      A        B     B - A   [%.0f %% bootstrap interval]\n"
                "  score                          %7.4f  %7.4f  %+8.4f   [%+.4f, %+.4f]\n"
                "  success rate                   %7.3f  %7.3f  %+8.3f   [%+.3f, %+.3f]\n"
                "  collision rate                 %7.3f  %7.3f  %+8.3f   [%+.3f, %+.3f]\n"
                "  timeout rate                   %7.3f  %7.3f  %+8.3f   [%+.3f, %+.3f]\n",
                level, c.score_a, c.score_b, c.score_difference.estimate, c.score_difference.low,
                c.score_difference.high, c.success_a, c.success_b, c.success_difference.estimate,
                c.success_difference.low, c.success_difference.high, c.collision_a, c.collision_b,
                c.collision_difference.estimate, c.collision_difference.low, c.collision_difference.high, c.timeout_a,
                c.timeout_b, c.timeout_difference.estimate, c.timeout_difference.low, c.timeout_difference.high);
  out += line;
  std::snprintf(line, sizeof line,
                "  mean successful time, B / A   %s   [%s, %s]  (%d worlds where both succeed)\n"
                "  (%d resamples of the worlds, seed %llu)\n\n",
                fmt("%.3f", c.time_ratio.estimate).c_str(), fmt("%.3f", c.time_ratio.low).c_str(),
                fmt("%.3f", c.time_ratio.high).c_str(), c.time_ratio_worlds, c.resamples,
                static_cast<unsigned long long>(c.seed));
  out += line;
  std::snprintf(line, sizeof line,
                "majority outcome (success in more than half of the trials)\n"
                "  both mostly succeed %d, both mostly fail %d, disagree %zu\n",
                c.both_succeed, c.both_fail, c.disagree.size());
  out += line;
  if (!c.disagree.empty()) out += "  disagreeing worlds: " + idList(c.disagree) + "\n";
  out += "\nSpearman rank correlation across worlds\n";
  std::snprintf(line, sizeof line, "  mean successful time  %s  (%d worlds where both succeed)\n",
                fmt("%+.3f", c.spearman_time).c_str(), c.spearman_time_worlds);
  out += line;
  std::snprintf(line, sizeof line, "  success rate          %s  (%zu worlds)\n", fmt("%+.3f", c.spearman_success).c_str(),
                c.a.size());
  out += line;
  return out;
}

}  // namespace barn::bench
