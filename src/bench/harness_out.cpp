#include "barn/bench/harness_out.hpp"

#include <algorithm>
#include <charconv>
#include <cmath>
#include <limits>
#include <map>

#include "barn/core/errors.hpp"
#include "barn/core/text_io.hpp"

namespace barn::bench {

namespace {

std::vector<std::string> splitWhitespace(const std::string& line) {
  std::vector<std::string> fields;
  std::size_t i = 0;
  while (i < line.size()) {
    while (i < line.size() && (line[i] == ' ' || line[i] == '\t' || line[i] == '\r')) ++i;
    const std::size_t start = i;
    while (i < line.size() && line[i] != ' ' && line[i] != '\t' && line[i] != '\r') ++i;
    if (i > start) fields.push_back(line.substr(start, i - start));
  }
  return fields;
}

// "%.4f" through to_chars: the same digits as printf in the C locale, whatever the locale is.
std::string fixed4(double value) {
  char buffer[400];
  const auto result = std::to_chars(buffer, buffer + sizeof buffer, value, std::chars_format::fixed, 4);
  return std::string(buffer, result.ptr);
}

}  // namespace

std::vector<HarnessLine> parseHarnessOut(const std::string& text, const std::string& where) {
  std::vector<HarnessLine> lines;
  std::size_t start = 0;
  int number = 0;
  while (start < text.size()) {
    std::size_t end = text.find('\n', start);
    if (end == std::string::npos) end = text.size();
    const std::string line = text.substr(start, end - start);
    start = end + 1;
    ++number;
    const std::vector<std::string> f = splitWhitespace(line);
    if (f.empty()) continue;
    const std::string at = where + ":" + std::to_string(number);
    const auto fail = [&](const std::string& field, const std::string& what) {
      throw core::InputError(at + ": " + field + ": " + what);
    };
    if (f.size() != 6)
      fail("line", "expected 6 fields 'world_idx success collided timeout time nav_metric', got " +
                       std::to_string(f.size()));
    HarnessLine h;
    h.line = number;
    {
      const auto result = std::from_chars(f[0].data(), f[0].data() + f[0].size(), h.world_id);
      if (result.ec != std::errc{} || result.ptr != f[0].data() + f[0].size() || h.world_id < 0)
        fail("world_idx", "'" + f[0] + "' is not a world id (an integer >= 0)");
    }
    const char* flag_names[3] = {"success", "collided", "timeout"};
    bool* flags[3] = {&h.success, &h.collided, &h.timeout};
    for (int k = 0; k < 3; ++k) {
      const std::string& v = f[static_cast<std::size_t>(k) + 1];
      if (v != "0" && v != "1") fail(flag_names[k], "'" + v + "' is not 0 or 1");
      *flags[k] = v == "1";
    }
    if (h.success && (h.collided || h.timeout))
      fail("success", "set together with collided/timeout (run.py never writes that)");
    if (!core::parseDouble(f[4], h.time) || !std::isfinite(h.time) || h.time < 0.0)
      fail("time", "'" + f[4] + "' is not a finite number >= 0");
    if (!core::parseDouble(f[5], h.nav_metric) || !std::isfinite(h.nav_metric))
      fail("nav_metric", "'" + f[5] + "' is not a finite number");
    lines.push_back(h);
  }
  if (lines.empty()) throw core::InputError(where + ": no result lines");
  return lines;
}

Outcome harnessOutcome(const HarnessLine& line) {
  if (line.success) return Outcome::Success;
  if (line.collided) return Outcome::Collision;
  return Outcome::Timeout;  // the timeout flag, or (not from run.py) no flag at all
}

HarnessImport importHarnessLines(const std::vector<HarnessLine>& lines, const std::vector<core::WorldSpec>& worlds,
                                 const core::Protocol& protocol, const std::string& where) {
  std::map<int, const core::WorldSpec*> by_id;
  for (const auto& w : worlds) by_id.emplace(w.id, &w);
  const double nan = std::numeric_limits<double>::quiet_NaN();
  HarnessImport out;
  std::map<int, int> trials;
  for (const HarnessLine& h : lines) {
    const auto it = by_id.find(h.world_id);
    if (it == by_id.end())
      throw core::InputError(where + ":" + std::to_string(h.line) + ": world_idx: world " + std::to_string(h.world_id) +
                             " is not in the world folder");
    EpisodeResult r;
    r.world_id = h.world_id;
    r.trial = trials[h.world_id]++;
    r.seed = 0;
    r.outcome = harnessOutcome(h);
    r.actual_time = h.time;
    r.optimal_time = core::optimalTime(it->second->path, protocol);
    r.score = core::barnScore(r.outcome == Outcome::Success, r.actual_time, r.optimal_time, protocol);
    r.path_length = nan;
    r.mean_speed = nan;
    r.sim_time = nan;
    out.results.push_back(r);
    out.unflagged += !h.success && !h.collided && !h.timeout;

    ++out.check.lines;
    // run.py writes the score on its edition's scale: the protocol's own clip.
    const double expected = core::barnScore(h.success, h.time, r.optimal_time, protocol);
    const double difference = std::abs(h.nav_metric - expected);
    if (difference > 1e-3) {
      ++out.check.score_mismatches;
      const double ratio = h.success ? h.time / r.optimal_time : 0.0;
      if (std::abs(h.nav_metric - ratio) <= 1e-3 * std::max(1.0, ratio)) ++out.check.ratio_matches;
    }
    if (difference > out.check.max_score_difference) {
      out.check.max_score_difference = difference;
      out.check.worst_line = h.line;
    }
  }
  for (const auto& [id, n] : trials) {
    out.world_ids.push_back(id);
    out.max_trials = std::max(out.max_trials, n);
    out.min_trials = out.min_trials == 0 ? n : std::min(out.min_trials, n);
  }
  return out;
}

std::string harnessLine(const EpisodeResult& r) {
  const bool success = r.outcome == Outcome::Success;
  const bool collided = r.outcome == Outcome::Collision;
  const bool timeout = r.outcome == Outcome::Timeout;
  return std::to_string(r.world_id) + " " + (success ? "1" : "0") + " " + (collided ? "1" : "0") + " " +
         (timeout ? "1" : "0") + " " + fixed4(r.actual_time) + " " + fixed4(r.score) + "\n";
}

std::string harnessOut(const std::vector<EpisodeResult>& results) {
  std::string text;
  for (const auto& r : results) text += harnessLine(r);
  return text;
}

}  // namespace barn::bench
