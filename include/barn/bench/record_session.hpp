#pragma once
/// The life of a run record on disk (run_record.hpp says what the files hold), shared by every
/// front end: `barn run`, `sweep`, `regress` and `merge`, and the Python module.
///
///   createRecord / openRecord   a new record (checked, locked, nothing written yet) or one to
///                               finish (its manifest and journal read back and checked)
///   pendingEpisodes             what is left to run (this shard's episodes minus the journaled)
///   RecordJournal               stamps the manifest with where it runs, journals each finished
///                               episode as it comes, then completes the record or leaves it
///                               resumable
///   mergeShardRecords           the shards of one run into the record a single run writes
///
/// Who runs the episodes is up to the front end (the C++ batch, Python processes): the record
/// only sees their rows, so every front end writes the same bytes.

#include <cstddef>
#include <filesystem>
#include <optional>
#include <fstream>
#include <string>
#include <utility>
#include <vector>

#include "barn/bench/run_record.hpp"
#include "barn/core/text_io.hpp"

namespace barn::bench {

/// An exclusive lock on a record folder (flock on its `.barn.lock`), held while one process
/// writes the record: a second writer of the same folder gets a clear error instead of silently
/// losing one run's results. Released when destroyed (or when the process dies).
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

/// A record this process writes: its folder (locked), manifest, worlds, and the episodes that
/// earlier sessions finished (resume).
struct RecordSession {
  RecordLock lock;
  std::filesystem::path dir;
  RunManifest manifest;
  std::vector<core::WorldSpec> worlds;
  std::vector<EpisodeResult> previous;
};

/// At most this many episodes in one record (its bookkeeping is set up before the first one
/// runs); beyond it, shards split the run across processes.
inline constexpr std::size_t kMaxEpisodesPerRecord = 1'000'000;

/// InputError if `dir` already holds a run record (a quick answer before the work of
/// createRecord, which checks again under the lock).
void checkNoRecord(const std::filesystem::path& dir);

/// A new record of `manifest` (its shard fields set) in `dir`, which must not hold one.
/// Everything is checked before the folder is created and locked; nothing is written yet.
RecordSession createRecord(RunManifest manifest, std::vector<core::WorldSpec> worlds, const std::filesystem::path& dir);

/// The record in `dir`, to finish: locked, its manifest read, its worlds loaded (and checked
/// against the digest), and, if incomplete, its journal read and checked row by row.
RecordSession openRecord(const std::filesystem::path& dir);

/// Episode indices (world position x trials + trial) of the record still to run: its shard's
/// episodes, in order, minus those finished before.
std::vector<std::size_t> pendingEpisodes(const RecordSession& session);

/// Journals one session of a record: construction stamps the manifest with where it runs
/// (version, commit, host, threads, start time) and rewrites it with the journal of the rows
/// finished before (an interrupted write may have left half a line); append() adds each
/// finished episode; finish() completes the record or leaves it resumable.
class RecordJournal {
 public:
  /// `pending`: the episodes this session will run (pendingEpisodes).
  RecordJournal(RecordSession& session, std::size_t pending, int threads);

  /// Appends a finished episode's row and flushes it; false (errno set) if that failed, after
  /// which nothing more can be kept.
  bool append(const EpisodeResult& result);

  /// Closes the journal. If `finished` and the earlier rows hold every episode, writes the
  /// complete record (episodes.csv, summary.json, the manifest marked complete) and returns
  /// its episodes as written; else writes the manifest with what is done, for a later resume,
  /// and returns nothing. `trajectories`, if given, go to trajectories/ first. `wall_time_s`
  /// adds to the manifest's.
  std::optional<std::vector<EpisodeResult>> finish(std::vector<EpisodeResult> finished, double wall_time_s,
              const std::optional<std::vector<core::FileContent>>& trajectories = std::nullopt);

 private:
  RecordSession& session_;
  std::ofstream journal_;
};

/// Merges the complete shard records of one run (`barn run --shard K/N`) into `out` (which
/// must not hold a record): byte-identical to the record a single run writes. Returns the
/// merged manifest; InputError if a shard is missing, incomplete, twice, or of another run.
RunManifest mergeShardRecords(const std::vector<std::filesystem::path>& shards, const std::filesystem::path& out);

/// Facts about where this process runs, for the manifest: `git rev-parse HEAD` of the source
/// tree barnbench was built from (with "-dirty" if it has changes) or "unknown", the host
/// name, and the current UTC time (ISO 8601).
std::string gitCommit();
std::string hostName();
std::string utcNow();

}  // namespace barn::bench
