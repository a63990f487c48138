#pragma once
/// episodes.csv: one row per (world, trial), one line per row, its columns defined once (a
/// table in results_io.cpp gives the header, the writer and the parser). Numbers are written as
/// the shortest text that reads back as the same double, so resume and merge see the numbers
/// that were run. A row read back is the same EpisodeResult except for what it does not hold:
///   - of the collision, only its point: CollisionInfo::time, rect_index and pose read back as
///     their defaults (0, -1, the zero pose);
///   - the trajectory (kept apart, in trajectories/);
///   - in the error text and state labels, a line break becomes ';' (a row is one line), and
///     in a state label a '|' (the list's separator) becomes ';'.
/// Text holding a comma or a double quote is quoted per RFC 4180 (quotes doubled); a record
/// written before quoting existed has no quotes and reads the same.

#include <filesystem>
#include <string>
#include <vector>

#include "barn/bench/episode.hpp"

namespace barn::bench {

/// The column names in order: world, trial, seed, outcome, time_s, ... (docs/records.md).
std::vector<std::string> episodeColumnNames();
/// The header line (with newline).
std::string episodesCsvHeader();
/// One row (with newline).
std::string episodeCsvRow(const EpisodeResult& result);
/// Header plus rows in the given order.
std::string episodesCsv(const std::vector<EpisodeResult>& results);

/// Parses one row (a line, without its newline); InputError naming `where` and the column on a
/// malformed row: a quoted field not closed or followed by more text, a quote inside an
/// unquoted field, a column missing or extra, a collision_x without a collision_y or the
/// reverse, a world id or trial that is not a whole number in [0, 10^9], a seed that is not a
/// decimal unsigned 64-bit number, a number that is not finite (path, speed and simulated time
/// may be "nan": unknown, in an imported record), a state label longer than
/// kMaxStateLabelBytes or more than kMaxStateLabels of them (what an episode can record).
EpisodeResult parseEpisodeRow(const std::string& line, const std::string& where);
/// Parses an episodes file's text (header plus rows), `where` naming it. With `journal`, a
/// last line without its newline (cut short by an interruption) is left out; otherwise it is
/// an error, as is anything that is not an episodes file.
std::vector<EpisodeResult> parseEpisodesCsv(const std::string& text, const std::string& where, bool journal);
/// Reads a journal (parseEpisodesCsv with `journal`). A missing file gives an empty list
/// only if `allow_missing`. A complete record is read with readCompleteRecord (run_record.hpp).
std::vector<EpisodeResult> readEpisodesCsv(const std::filesystem::path& path, bool allow_missing = false);

/// One episode's trajectory record: time, world pose, command, state and the stack parameters
/// set, per control tick.
std::string trajectoryCsv(const EpisodeResult& result);
/// Reads a trajectory file back (files written before the params column read too);
/// InputError naming the file and line on a malformed one.
std::vector<TrajectorySample> readTrajectoryCsv(const std::filesystem::path& path);
/// The same from the file's text; `where` names it in errors.
std::vector<TrajectorySample> parseTrajectoryCsv(const std::string& text, const std::string& where);

}  // namespace barn::bench
