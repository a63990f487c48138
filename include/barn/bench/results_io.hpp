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

/// Parses one row; InputError naming `where` on a malformed row.
EpisodeResult parseEpisodeRow(const std::string& line, const std::string& where);
/// Reads an episodes file (header plus rows). A missing file gives an empty list only if
/// `allow_missing`. A truncated last line (an interrupted write) is ignored.
std::vector<EpisodeResult> readEpisodesCsv(const std::filesystem::path& path, bool allow_missing = false);

/// One episode's trajectory record: time, world pose, command, state and the stack parameters
/// set, per control tick.
std::string trajectoryCsv(const EpisodeResult& result);
/// Reads a trajectory file back (files written before the params column read too);
/// InputError naming the file and line on a malformed one.
std::vector<TrajectorySample> readTrajectoryCsv(const std::filesystem::path& path);

/// The name of a trajectory file in a record's trajectories/ folder.
std::string trajectoryFileName(int world_id, int trial);

}  // namespace barn::bench
