#pragma once
/// Run records executed by the CLI (fresh, resumed, or the cells of a sweep), several in one
/// parallel pool: the record's life is bench::RecordSession's; this adds the C++ batch, the
/// progress line, Ctrl-C and the printed summaries. The run, regress and sweep commands share it.

#include <cstdint>
#include <filesystem>
#include <string>
#include <vector>

#include "barn/bench/batch.hpp"
#include "barn/bench/record_session.hpp"
#include "barn/bench/run_record.hpp"
#include "barn/bench/world_selection.hpp"
#include "barn/controllers/registry.hpp"
#include "barn/core/config.hpp"
#include "commands.hpp"

namespace barn::cli {

/// A record to write (bench::RecordSession) and what its episodes need here besides the
/// record: the C++ controller factory and the episode config (pendingBatch makes the batch).
struct Session {
  bench::RecordSession record;
  controllers::ControllerFactory make_controller;
  bench::EpisodeConfig episode;
  std::string plant_warning;  // bench::plantMismatch of the controller on this plant ("" if none)
};

/// A new record in `dir` (which must not hold one): everything validated, nothing written yet.
/// An empty `dir` validates only (barn run --check): no record is created.
Session newSession(const std::string& controller_name, const core::ConfigNode& controller_config,
                   const bench::EpisodeConfig& episode, const bench::LoadedWorlds& worlds,
                   const std::string& worlds_spec, int trials, std::uint64_t seed, int shard_index, int shard_count,
                   const std::filesystem::path& dir);

/// The record in `dir`, to finish (its manifest and journal read back).
Session resumedSession(const std::filesystem::path& dir);

/// Runs what is left of every session's record in one parallel pool (Ctrl-C keeps what has
/// finished) and completes each record. 0 all complete, 1 interrupted or an episode error.
int executeSessions(const std::vector<Session*>& sessions, const SessionOptions& options, bool print_summaries);

}  // namespace barn::cli
