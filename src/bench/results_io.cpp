#include "barn/bench/results_io.hpp"

#include <algorithm>
#include <array>
#include <charconv>
#include <cmath>
#include <limits>
#include <sstream>

#include "barn/core/errors.hpp"
#include "barn/core/text_io.hpp"

namespace barn::bench {

namespace {

// Trajectory files keep one sample per line: a separator in a label becomes ';'.
std::string sanitise(std::string text) {
  for (char& ch : text)
    if (ch == ',' || ch == '\n' || ch == '\r' || ch == '|' || ch == '"') ch = ';';
  return text;
}

// ---------------------------------------------------------------------------------------------
// episodes.csv's columns. One table gives the header, the row writer and the row parser, so a
// column is added in one place. Text is written per RFC 4180: a field holding a comma or a
// double quote is put in double quotes, its quotes doubled; anything else as it is.

// Reads one field of one row; its errors name where the row is and the column.
class FieldReader {
 public:
  FieldReader(const std::string& where, std::string_view column) : where_(where), column_(column) {}

  [[noreturn]] void fail(const std::string& what) const {
    throw core::InputError(where_ + ": " + std::string(column_) + ": " + what);
  }

  // Decimal digits only (no sign, space or "0x"), read exactly: a value past the range is an
  // error, never wrapped or saturated.
  std::uint64_t whole(std::string_view text, std::uint64_t max) const {
    std::uint64_t v = 0;
    const char* end = text.data() + text.size();
    const auto [ptr, ec] = std::from_chars(text.data(), end, v);
    if (text.empty() || ec != std::errc() || ptr != end || v > max)
      fail("'" + std::string(text) + "' is not a whole number from 0 to " + std::to_string(max));
    return v;
  }

  // Finite, or "nan" where a value may be unknown (an imported record's path, speed and
  // simulated time); never infinite.
  double number(std::string_view text, bool may_be_unknown = false) const {
    double v = 0.0;
    if (!core::parseDouble(text, v) || std::isinf(v) || (std::isnan(v) && !may_be_unknown))
      fail("'" + std::string(text) + "' is not a finite number");
    return v;
  }

 private:
  const std::string& where_;
  std::string_view column_;
};

struct EpisodeColumn {
  std::string_view name;
  std::string (*write)(const EpisodeResult& r);  // the field's text, before quoting
  void (*read)(const FieldReader& field, std::string_view text, EpisodeResult& r);
};

constexpr std::uint64_t kMaxId = 1'000'000'000;  // as a manifest's world ids

template <double EpisodeResult::*kMember>
std::string writeNumber(const EpisodeResult& r) {
  return core::formatDouble(r.*kMember);
}
// `kMayBeUnknown`: "nan" reads (unknown, in an imported record).
template <double EpisodeResult::*kMember, bool kMayBeUnknown = false>
void readNumber(const FieldReader& field, std::string_view text, EpisodeResult& r) {
  r.*kMember = field.number(text, kMayBeUnknown);
}

const std::array<EpisodeColumn, 14> kEpisodeColumns = {{
    {"world", [](const EpisodeResult& r) { return std::to_string(r.world_id); },
     [](const FieldReader& f, std::string_view t, EpisodeResult& r) { r.world_id = static_cast<int>(f.whole(t, kMaxId)); }},
    {"trial", [](const EpisodeResult& r) { return std::to_string(r.trial); },
     [](const FieldReader& f, std::string_view t, EpisodeResult& r) { r.trial = static_cast<int>(f.whole(t, kMaxId)); }},
    {"seed", [](const EpisodeResult& r) { return std::to_string(r.seed); },
     [](const FieldReader& f, std::string_view t, EpisodeResult& r) {
       r.seed = f.whole(t, std::numeric_limits<std::uint64_t>::max());
     }},
    {"outcome", [](const EpisodeResult& r) { return std::string(toString(r.outcome)); },
     [](const FieldReader& f, std::string_view t, EpisodeResult& r) {
       for (Outcome o : {Outcome::Success, Outcome::Collision, Outcome::Timeout, Outcome::Error})
         if (t == toString(o)) {
           r.outcome = o;
           return;
         }
       f.fail("'" + std::string(t) + "' is not success/collision/timeout/error");
     }},
    {"time_s", writeNumber<&EpisodeResult::actual_time>, readNumber<&EpisodeResult::actual_time>},
    {"score", writeNumber<&EpisodeResult::score>, readNumber<&EpisodeResult::score>},
    {"optimal_time_s", writeNumber<&EpisodeResult::optimal_time>, readNumber<&EpisodeResult::optimal_time>},
    {"path_length_m", writeNumber<&EpisodeResult::path_length>, readNumber<&EpisodeResult::path_length, true>},
    {"mean_speed_mps", writeNumber<&EpisodeResult::mean_speed>, readNumber<&EpisodeResult::mean_speed, true>},
    {"sim_time_s", writeNumber<&EpisodeResult::sim_time>, readNumber<&EpisodeResult::sim_time, true>},
    // The collision's point; both empty without a collision.
    {"collision_x", [](const EpisodeResult& r) { return r.collision ? core::formatDouble(r.collision->point.x()) : std::string(); },
     [](const FieldReader& f, std::string_view t, EpisodeResult& r) {
       if (t.empty()) return;
       r.collision.emplace();
       r.collision->point.x() = f.number(t);
     }},
    {"collision_y", [](const EpisodeResult& r) { return r.collision ? core::formatDouble(r.collision->point.y()) : std::string(); },
     [](const FieldReader& f, std::string_view t, EpisodeResult& r) {  // read after collision_x
       if (!r.collision) {
         if (!t.empty()) f.fail("'" + std::string(t) + "' without a collision_x");
         return;
       }
       r.collision->point.y() = f.number(t);  // an empty y beside an x is not a number
     }},
    // NAME:COUNT|NAME:COUNT in order of first entry; a '|' in a name becomes ';'.
    {"states",
     [](const EpisodeResult& r) {
       std::string text;
       for (std::size_t i = 0; i < r.state_entries.size(); ++i) {
         std::string name = r.state_entries[i].first;
         std::replace(name.begin(), name.end(), '|', ';');
         text += (i ? "|" : "") + name + ":" + std::to_string(r.state_entries[i].second);
       }
       return text;
     },
     [](const FieldReader& f, std::string_view t, EpisodeResult& r) {
       if (t.empty()) return;
       for (std::size_t start = 0;;) {
         const std::size_t bar = t.find('|', start);
         const std::string_view item = t.substr(start, bar == std::string_view::npos ? std::string_view::npos : bar - start);
         const std::size_t colon = item.rfind(':');  // a ':' in a name is kept: the count is after the last
         if (colon == std::string_view::npos) f.fail("'" + std::string(item) + "' is not NAME:COUNT");
         if (colon == 0 || colon > kMaxStateLabelBytes)
           f.fail("a label of " + std::to_string(colon) + " bytes (1 to " + std::to_string(kMaxStateLabelBytes) + ")");
         if (r.state_entries.size() == kMaxStateLabels) f.fail("more than " + std::to_string(kMaxStateLabels) + " labels");
         r.state_entries.emplace_back(std::string(item.substr(0, colon)),
                                      static_cast<int>(f.whole(item.substr(colon + 1), std::numeric_limits<int>::max())));
         if (bar == std::string_view::npos) return;
         start = bar + 1;
       }
     }},
    {"error", [](const EpisodeResult& r) { return r.error; },
     [](const FieldReader&, std::string_view t, EpisodeResult& r) { r.error = std::string(t); }},
}};

// RFC 4180: quoted if it holds a comma or a double quote. A line break becomes ';', so that a
// row is one line (a journal is appended and read back line by line).
void appendField(std::string& row, const std::string& text) {
  const bool quoted = text.find_first_of(",\"") != std::string::npos;
  if (quoted) row += '"';
  for (char ch : text) {
    if (ch == '"') row += '"';
    row += ch == '\n' || ch == '\r' ? ';' : ch;
  }
  if (quoted) row += '"';
}

// The fields of one row (RFC 4180, as appendField writes them).
std::vector<std::string> splitFields(std::string_view row, const std::string& where) {
  std::vector<std::string> fields;
  std::size_t at = 0;
  while (true) {
    std::string field;
    if (at < row.size() && row[at] == '"') {
      for (++at;; ++at) {
        if (at == row.size()) throw core::InputError(where + ": a quoted field is not closed");
        if (row[at] == '"') {
          if (at + 1 < row.size() && row[at + 1] == '"') ++at;  // a doubled quote
          else break;
        }
        field += row[at];
      }
      ++at;  // past the closing quote
      if (at < row.size() && row[at] != ',')
        throw core::InputError(where + ": text after the closing quote of field " + std::to_string(fields.size() + 1));
    } else {
      const std::size_t comma = std::min(row.find(',', at), row.size());
      field = row.substr(at, comma - at);
      if (field.find('"') != std::string::npos)
        throw core::InputError(where + ": a double quote in unquoted field " + std::to_string(fields.size() + 1));
      at = comma;
    }
    fields.push_back(std::move(field));
    if (at == row.size()) return fields;
    ++at;  // past the comma
  }
}

}  // namespace

std::vector<std::string> episodeColumnNames() {
  std::vector<std::string> names;
  for (const EpisodeColumn& column : kEpisodeColumns) names.emplace_back(column.name);
  return names;
}

std::string episodesCsvHeader() {
  std::string header;
  for (const EpisodeColumn& column : kEpisodeColumns) (header += header.empty() ? "" : ",") += column.name;
  return header + "\n";
}

std::string episodeCsvRow(const EpisodeResult& r) {
  std::string row;
  for (std::size_t i = 0; i < kEpisodeColumns.size(); ++i) {
    if (i) row += ',';
    appendField(row, kEpisodeColumns[i].write(r));
  }
  return row + "\n";
}

std::string episodesCsv(const std::vector<EpisodeResult>& results) {
  std::string text = episodesCsvHeader();
  for (const auto& r : results) text += episodeCsvRow(r);
  return text;
}

EpisodeResult parseEpisodeRow(const std::string& line, const std::string& where) {
  const std::vector<std::string> fields = splitFields(line, where);
  if (fields.size() != kEpisodeColumns.size())
    throw core::InputError(where + ": expected " + std::to_string(kEpisodeColumns.size()) + " columns, got " +
                           std::to_string(fields.size()));
  EpisodeResult r;
  for (std::size_t i = 0; i < kEpisodeColumns.size(); ++i)
    kEpisodeColumns[i].read(FieldReader(where, kEpisodeColumns[i].name), fields[i], r);
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
