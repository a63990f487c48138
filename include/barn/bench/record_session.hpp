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

/// A record this process writes: its folder (locked by its writer), manifest, worlds, and the
/// episodes that earlier sessions finished (resume).
struct RecordSession {
  RecordWriter writer;  // not held for a complete record opened where it cannot be locked (read-only)
  std::filesystem::path dir;
  RunManifest manifest;
  std::vector<core::WorldSpec> worlds;
  std::vector<EpisodeResult> previous;
};

/// InputError if `dir` already holds a run record, or a write into it was interrupted (a quick
/// answer before the work of createRecord, which checks again under the lock).
void checkNoRecord(const std::filesystem::path& dir);

/// InputError unless `worlds` x `trials` episodes fit one record (kMaxEpisodesPerRecord).
void checkRecordSize(std::size_t worlds, int trials);

/// A new record of `manifest` (its shard fields set) in `dir`, which must not hold one.
/// Everything is checked before the folder is created and locked; nothing is written yet.
RecordSession createRecord(RunManifest manifest, std::vector<core::WorldSpec> worlds, const std::filesystem::path& dir);

/// The record in `dir`, to finish: locked (a write a kill interrupted completed first), its
/// manifest read, its worlds loaded (and checked against the digest), and, if incomplete, the
/// files its controller config names checked against their digests and its journal read and
/// checked row by row. With trajectories, a journaled episode whose trajectory file is missing
/// is left out of `previous`, to run again (the same seed gives the same row). A complete
/// record that cannot be locked (read-only) is opened without the lock: nothing is written.
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

  /// Appends a finished episode's row and flushes it, after writing its trajectory file
  /// (trajectories/world_W_trial_T.csv) if the record keeps trajectories; false if that
  /// failed (error() says why), after which nothing more can be kept.
  bool append(const EpisodeResult& result);
  /// Why the last append failed: the file and the system's reason.
  const std::string& error() const { return error_; }

  /// Closes the journal. If `finished` and the earlier rows hold every episode, writes the
  /// complete record (episodes.csv, summary.json, the manifest marked complete) and returns
  /// its episodes as written; else writes the manifest with what is done, for a later resume,
  /// and returns nothing. `wall_time_s` adds to the manifest's.
  std::optional<std::vector<EpisodeResult>> finish(std::vector<EpisodeResult> finished, double wall_time_s);

 private:
  RecordSession& session_;
  std::ofstream journal_;
  std::string error_;
};

/// The name of an episode's file in trajectories/.
std::string trajectoryFileName(int world_id, int trial);

/// The complete shard records of one run (`barn run --shard K/N`), read (readCompleteRecord)
/// and checked, as the files of the merged record in `out`: byte-identical to the record a
/// single run writes, the shards' trajectory files included. InputError if a shard is missing,
/// incomplete, twice, of another run, or its rows disagree with its manifest.
struct MergedRecord {
  RunManifest manifest;                 // the merged manifest (complete)
  std::vector<EpisodeResult> episodes;  // as written
  std::vector<core::FileContent> files;
};
MergedRecord mergedShardRecords(const std::vector<std::filesystem::path>& shards, const std::filesystem::path& out);

/// InputError if `dir` holds a run record (for writers of a new one other than `barn run`:
/// merge, import-out).
void checkNoRecordForOut(const std::filesystem::path& dir);

/// Merges the shards into `out` (which must not hold a record; checked again under its lock):
/// mergedShardRecords written as one set. Returns the merged record.
MergedRecord mergeShardRecords(const std::vector<std::filesystem::path>& shards, const std::filesystem::path& out);

/// Facts about where this process runs, for the manifest: the commit of the source tree
/// barnbench was built from (with "-dirty" if it had changes), recorded when it was built
/// ("unknown" outside a git checkout), the host name, and the current UTC time (ISO 8601).
std::string gitCommit();
std::string hostName();
std::string utcNow();

}  // namespace barn::bench
