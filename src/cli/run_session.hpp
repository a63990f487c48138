#pragma once
/// A run record being executed (fresh, resumed, or one cell of a sweep), and executing several
/// of them in one parallel pool. The CLI's run, regress and sweep commands share this.

#include <cstdint>
#include <filesystem>
#include <utility>
#include <string>
#include <vector>

#include "barn/bench/batch.hpp"
#include "barn/bench/run_record.hpp"
#include "barn/bench/world_selection.hpp"
#include "barn/core/config.hpp"
#include "commands.hpp"

namespace barn::cli {

/// An exclusive lock on a record folder (flock on its `.barn.lock`), held while one barn
/// process writes the record: a second `barn run --out` or `--resume` on the same folder gets a
/// clear error instead of silently losing one run's results. Released when destroyed (or when
/// the process dies).
class RecordLock {
 public:
  RecordLock() = default;
  /// Takes the lock on `dir` (created if missing); InputError naming the holder if taken.
  explicit RecordLock(const std::filesystem::path& dir);
  RecordLock(RecordLock&& other) noexcept : fd_(std::exchange(other.fd_, -1)) {}
  RecordLock& operator=(RecordLock&& other) noexcept;
  RecordLock(const RecordLock&) = delete;
  RecordLock& operator=(const RecordLock&) = delete;
  ~RecordLock();

 private:
  int fd_ = -1;
};

struct Session {
  RecordLock lock;                             // held from before the folder is looked at
  std::filesystem::path dir;                   // the record folder
  bench::RunManifest manifest;
  std::vector<core::WorldSpec> worlds;
  bench::BatchSpec spec;
  std::vector<bench::EpisodeResult> previous;  // finished in earlier sessions (resume)
};


/// A new record in `dir` (which must not hold one): everything validated, nothing written yet.
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
