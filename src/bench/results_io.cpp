#include "barn/bench/results_io.hpp"

#include <charconv>
#include <cmath>
#include <limits>
#include <sstream>

#include "barn/core/errors.hpp"
#include "barn/core/text_io.hpp"

namespace barn::bench {

namespace {

constexpr int kColumns = 14;

std::string sanitise(std::string text) {
  for (char& ch : text)
    if (ch == ',' || ch == '\n' || ch == '\r' || ch == '|' || ch == '"') ch = ';';
  return text;
}

std::vector<std::string> splitFields(const std::string& line) {
  std::vector<std::string> fields;
  std::size_t start = 0;
  while (true) {
    const std::size_t comma = line.find(',', start);
    fields.push_back(line.substr(start, comma == std::string::npos ? std::string::npos : comma - start));
    if (comma == std::string::npos) return fields;
    start = comma + 1;
  }
}

}  // namespace

std::string episodesCsvHeader() {
  return "world,trial,seed,outcome,time_s,score,optimal_time_s,path_length_m,mean_speed_mps,sim_time_s,"
         "collision_x,collision_y,states,error\n";
}

std::string episodeCsvRow(const EpisodeResult& r) {
  std::string row = std::to_string(r.world_id) + "," + std::to_string(r.trial) + "," + std::to_string(r.seed) + "," +
                    std::string(toString(r.outcome)) + "," + core::formatDouble(r.actual_time) + "," +
                    core::formatDouble(r.score) + "," + core::formatDouble(r.optimal_time) + "," +
                    core::formatDouble(r.path_length) + "," + core::formatDouble(r.mean_speed) + "," +
                    core::formatDouble(r.sim_time) + ",";
  if (r.collision) row += core::formatDouble(r.collision->point.x()) + "," + core::formatDouble(r.collision->point.y());
  else row += ",";
  row += ",";
  for (std::size_t i = 0; i < r.state_entries.size(); ++i)
    row += (i ? "|" : "") + sanitise(r.state_entries[i].first) + ":" + std::to_string(r.state_entries[i].second);
  row += "," + sanitise(r.error) + "\n";
  return row;
}

std::string episodesCsv(const std::vector<EpisodeResult>& results) {
  std::string text = episodesCsvHeader();
  for (const auto& r : results) text += episodeCsvRow(r);
  return text;
}

EpisodeResult parseEpisodeRow(const std::string& line, const std::string& where) {
  const std::vector<std::string> f = splitFields(line);
  const auto fail = [&](const std::string& what) { throw core::InputError(where + ": " + what); };
  if (static_cast<int>(f.size()) != kColumns) fail("expected " + std::to_string(kColumns) + " columns, got " + std::to_string(f.size()));
  EpisodeResult r;
  // Decimal digits only (no sign, space or "0x"), read exactly: a value past the range is an
  // error, never wrapped or saturated.
  const auto whole = [&](const std::string& text, const char* name, std::uint64_t max) {
    std::uint64_t v = 0;
    const auto end = text.data() + text.size();
    const auto [ptr, ec] = std::from_chars(text.data(), end, v);
    if (text.empty() || ec != std::errc() || ptr != end || v > max)
      fail(std::string(name) + ": '" + text + "' is not a whole number from 0 to " + std::to_string(max));
    return v;
  };
  // Finite, or "nan" where a value may be unknown (an imported record's path, speed and
  // simulated time); never infinite.
  const auto number = [&](const std::string& text, const char* name, bool may_be_unknown = false) {
    double v = 0.0;
    if (!core::parseDouble(text, v) || std::isinf(v) || (std::isnan(v) && !may_be_unknown))
      fail(std::string(name) + ": '" + text + "' is not a finite number");
    return v;
  };
  constexpr std::uint64_t kMaxId = 1'000'000'000;  // as a manifest's world ids
  r.world_id = static_cast<int>(whole(f[0], "world", kMaxId));
  r.trial = static_cast<int>(whole(f[1], "trial", kMaxId));
  r.seed = whole(f[2], "seed", std::numeric_limits<std::uint64_t>::max());
  if (f[3] == "success") r.outcome = Outcome::Success;
  else if (f[3] == "collision") r.outcome = Outcome::Collision;
  else if (f[3] == "timeout") r.outcome = Outcome::Timeout;
  else if (f[3] == "error") r.outcome = Outcome::Error;
  else fail("outcome: '" + f[3] + "' is not success/collision/timeout/error");
  r.actual_time = number(f[4], "time_s");
  r.score = number(f[5], "score");
  r.optimal_time = number(f[6], "optimal_time_s");
  r.path_length = number(f[7], "path_length_m", true);
  r.mean_speed = number(f[8], "mean_speed_mps", true);
  r.sim_time = number(f[9], "sim_time_s", true);
  if (!f[10].empty() || !f[11].empty()) {
    sim::CollisionInfo info;
    info.point = {number(f[10], "collision_x"), number(f[11], "collision_y")};
    r.collision = info;
  }
  if (!f[12].empty()) {
    std::size_t start = 0;
    while (start <= f[12].size()) {
      const std::size_t bar = f[12].find('|', start);
      const std::string item = f[12].substr(start, bar == std::string::npos ? std::string::npos : bar - start);
      const std::size_t colon = item.rfind(':');
      if (colon == std::string::npos) fail("states: '" + item + "' is not NAME:COUNT");
      if (colon == 0 || colon > kMaxStateLabelBytes)
        fail("states: a label of " + std::to_string(colon) + " bytes (1 to " + std::to_string(kMaxStateLabelBytes) + ")");
      if (r.state_entries.size() == kMaxStateLabels)
        fail("states: more than " + std::to_string(kMaxStateLabels) + " labels");
      r.state_entries.emplace_back(item.substr(0, colon),
                                   static_cast<int>(whole(item.substr(colon + 1), "states", std::numeric_limits<int>::max())));
      if (bar == std::string::npos) break;
      start = bar + 1;
    }
  }
  r.error = f[13];
  return r;
}

std::vector<EpisodeResult> parseEpisodesCsv(const std::string& text, const std::string& where, bool journal) {
  std::vector<EpisodeResult> results;
  std::size_t start = 0;
  int line_number = 0;
  while (start < text.size()) {
    const std::size_t end = text.find('\n', start);
    if (end == std::string::npos) {
      if (journal) break;  // a row cut short by an interruption
      throw core::InputError(where + ":" + std::to_string(line_number + 1) + ": the last line is cut short (no newline)");
    }
    const std::string line = text.substr(start, end - start);
    start = end + 1;
    ++line_number;
    if (line_number == 1) {
      if (line + "\n" != episodesCsvHeader()) throw core::InputError(where + ": not an episodes.csv (unexpected header)");
      continue;
    }
    results.push_back(parseEpisodeRow(line, where + ":" + std::to_string(line_number)));
  }
  if (line_number == 0 && (!text.empty() || !journal)) throw core::InputError(where + ": not an episodes.csv (no header line)");
  return results;
}

std::vector<EpisodeResult> readEpisodesCsv(const std::filesystem::path& path, bool allow_missing) {
  std::error_code ec;
  if (allow_missing && !std::filesystem::exists(path, ec)) return {};
  return parseEpisodesCsv(core::readTextFile(path), path.string(), /*journal=*/true);
}

std::string trajectoryCsv(const EpisodeResult& result) {
  std::ostringstream out;
  out << "time_s,x,y,yaw,cmd_linear,cmd_angular,state,params\n";
  for (const auto& s : result.trajectory) {
    out << core::formatDouble(s.time) << "," << core::formatDouble(s.pose.x) << "," << core::formatDouble(s.pose.y) << ","
        << core::formatDouble(s.pose.yaw) << "," << core::formatDouble(s.command.linear) << ","
        << core::formatDouble(s.command.angular) << "," << sanitise(s.state) << "," << sanitise(s.parameters) << "\n";
  }
  return out.str();
}

std::vector<TrajectorySample> readTrajectoryCsv(const std::filesystem::path& path) {
  return parseTrajectoryCsv(core::readTextFile(path), path.string());
}

std::vector<TrajectorySample> parseTrajectoryCsv(const std::string& text, const std::string& path) {
  constexpr std::string_view kHeader = "time_s,x,y,yaw,cmd_linear,cmd_angular,state";
  std::vector<TrajectorySample> samples;
  std::size_t start = 0;
  int line_number = 0;
  bool has_params = false;
  while (start < text.size()) {
    const std::size_t end = text.find('\n', start);
    if (end == std::string::npos) break;  // a line cut short
    const std::string line = text.substr(start, end - start);
    start = end + 1;
    const std::string where = path + ":" + std::to_string(++line_number);
    if (line_number == 1) {
      has_params = line == std::string(kHeader) + ",params";
      if (!has_params && line != kHeader) throw core::InputError(path + ": not a trajectory file (unexpected header)");
      continue;
    }
    std::vector<std::string> f;
    for (std::size_t at = 0;;) {
      const std::size_t comma = line.find(',', at);
      f.push_back(line.substr(at, comma == std::string::npos ? std::string::npos : comma - at));
      if (comma == std::string::npos) break;
      at = comma + 1;
    }
    if (f.size() != (has_params ? 8u : 7u)) throw core::InputError(where + ": expected " + (has_params ? "8" : "7") + " fields");
    double v[6];
    for (int i = 0; i < 6; ++i)
      if (!core::parseDouble(f[static_cast<std::size_t>(i)], v[i])) throw core::InputError(where + ": field " + std::to_string(i + 1) + " is not a number");
    samples.push_back({v[0], {v[1], v[2], v[3]}, {v[4], v[5]}, f[6], has_params ? f[7] : std::string()});
  }
  return samples;
}


}  // namespace barn::bench
