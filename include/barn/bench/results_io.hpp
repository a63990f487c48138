#pragma once
/// episodes.csv: one row per (world, trial), written with shortest round-trip numbers so a
/// row read back is the same EpisodeResult bit for bit (resume and merge rely on it).

#include <filesystem>
#include <string>
#include <vector>

#include "barn/bench/episode.hpp"

namespace barn::bench {

/// The header line (with newline).
std::string episodesCsvHeader();
/// One row (with newline). Commas and newlines in the error text are replaced by ';'.
std::string episodeCsvRow(const EpisodeResult& result);
/// Header plus rows in the given order.
std::string episodesCsv(const std::vector<EpisodeResult>& results);

/// Parses one row; InputError naming `where` on a malformed row: a column missing or extra, a
/// world id or trial that is not a whole number in [0, 10^9], a seed that is not a decimal
/// unsigned 64-bit number, a number that is not finite (path, speed and simulated time may
/// be "nan": unknown, in an imported record), a state label longer than
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
