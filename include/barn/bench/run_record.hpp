#pragma once
/// A run's experiment record: the folder `barn run` writes, `barn run --resume` finishes and
/// `barn merge` assembles from shards.
///
///   manifest.yaml          what was run (effective configs, worlds, seeds, shard) and where
///                          (commit, host, threads, wall time); enough to resume or reproduce
///   episodes.partial.csv   journal: rows appended as episodes finish (interrupted runs only)
///   episodes.csv           every row, sorted by (world, trial), once the run is complete
///   summary.json           report_test.py's summary and the difficulty breakdown
///
/// episodes.csv and summary.json depend only on what was run, never on threads, shards,
/// interruptions or time, so they are byte-identical across those.

#include <cstdint>
#include <filesystem>
#include <string>
#include <vector>

#include "barn/bench/episode.hpp"
#include "barn/bench/record_writer.hpp"
#include "barn/bench/world_selection.hpp"

namespace barn::bench {

inline constexpr const char* kManifestFile = "manifest.yaml";
inline constexpr const char* kJournalFile = "episodes.partial.csv";
inline constexpr const char* kEpisodesFile = "episodes.csv";
inline constexpr const char* kSummaryFile = "summary.json";

/// At most this many episodes in one record (its bookkeeping is set up before the first one
/// runs).
inline constexpr std::size_t kMaxEpisodesPerRecord = 1'000'000;

/// What the manifest does with a field besides writing and reading it (flags, or-ed).
namespace manifest_field {
inline constexpr unsigned kExperiment = 1u << 0;  // what was run: experimentDifference compares it
inline constexpr unsigned kConfigMap = 1u << 1;   // a config: YAML text here, a nested map in the file
inline constexpr unsigned kPath = 1u << 2;        // an absolute path, written relative to the record
inline constexpr unsigned kControllerPaths = 1u << 3;  // a controller config whose path fields (controllers::mapControllerPaths) are written relative to the record
inline constexpr unsigned kRunOnly = 1u << 4;     // left out of an imported record (nothing was run)
inline constexpr unsigned kImportOnly = 1u << 5;  // written for an imported record only
inline constexpr unsigned kOmitDefault = 1u << 6;  // left out at its default (empty, false): older manifests read back the same
}  // namespace manifest_field

/// A file the controller config names (a policy, a controller program's script), with a digest
/// of its bytes when the run started: resume, merge and regress refuse to go on with another
/// version of it.
struct ConfigFile {
  std::string path;    // absolute (written relative to the record)
  std::string digest;  // FNV-1a 64 of its bytes, hex
  template <class V> void visit(V& v) { v("path", path); v("digest", digest); }
  bool operator==(const ConfigFile&) const = default;
};

struct RunManifest {
  // What was run: two records with equal fields here hold parts of the same experiment.
  std::string controller;         // name given to --controller
  std::string controller_config;  // effective controller config (YAML text; a map in the file)
  std::vector<ConfigFile> config_files;  // the files controller_config names, with digests
  std::string episode_config;     // effective robot, LiDAR, physics and protocol config (YAML text; a map in the file)
  std::string worlds_spec;        // --worlds as given
  std::string worlds_folder;      // absolute folder of the world files (the file: relative to the record)
  std::vector<int> world_ids;     // in run order
  std::string worlds_digest;      // FNV-1a 64 of the world files' text, hex
  int trials = 1;
  std::uint64_t seed = 0;
  bool trajectories = false;  // trajectories/ holds one file per journaled episode (--trajectories)
  // Set for a record imported from another harness's results (barn import-out): nothing was
  // run, so it has no seed or controller config (neither is written) and cannot be resumed.
  std::string source;         // the imported file, as given
  std::string source_digest;  // FNV-1a 64 of its bytes, hex
  // Which part of it this record holds.
  int shard_index = 0;  // 1-based; 0 = the whole run
  int shard_count = 0;
  std::size_t episodes_total = 0;  // episodes of this record
  std::size_t episodes_done = 0;
  bool complete = false;
  // Where and how it ran (never compared).
  std::string barnbench_version;
  std::string git_commit;
  std::string host;
  int threads = 0;
  std::string started;       // UTC, ISO 8601
  double wall_time_s = 0.0;  // summed over resumed sessions
  double sim_time_s = 0.0;   // left out of the file when not finite (unknown)

  /// The manifest file's fields in file order, each with its manifest_field flags. The
  /// experiment fields are listed in the order experimentDifference reports them.
  template <class V>
  void visit(V& v) {
    using namespace manifest_field;
    v("controller", controller, kExperiment);
    v("controller_config", controller_config, kExperiment | kConfigMap | kControllerPaths | kRunOnly);
    v("config_files", config_files, kExperiment | kRunOnly | kOmitDefault);
    v("episode_config", episode_config, kExperiment | kConfigMap);
    v("worlds_spec", worlds_spec, 0u);
    v("worlds_folder", worlds_folder, kPath);
    v("world_ids", world_ids, kExperiment);
    v("worlds_digest", worlds_digest, kExperiment);
    v("trials", trials, kExperiment);
    v("seed", seed, kExperiment | kRunOnly);
    v("trajectories", trajectories, kRunOnly | kOmitDefault);
    v("source", source, kExperiment | kImportOnly);
    v("source_digest", source_digest, kExperiment | kImportOnly);
    v("shard_index", shard_index, 0u);
    v("shard_count", shard_count, 0u);
    v("episodes_total", episodes_total, 0u);
    v("episodes_done", episodes_done, 0u);
    v("complete", complete, 0u);
    v("barnbench_version", barnbench_version, 0u);
    v("git_commit", git_commit, 0u);
    v("host", host, 0u);
    v("threads", threads, 0u);
    v("started", started, 0u);
    v("wall_time_s", wall_time_s, 0u);
    v("sim_time_s", sim_time_s, 0u);
  }
};

/// The manifest of a new run: what is run (controller name and effective config text, the
/// episode config, the worlds loaded from `worlds_spec`, trials, seed); the rest left at its
/// defaults for the caller.
RunManifest newManifest(const std::string& controller, const std::string& controller_config, const EpisodeConfig& episode,
                        const LoadedWorlds& worlds, const std::string& worlds_spec, int trials, std::uint64_t seed);

/// The manifest's text for a record in `record_dir`. The two configs are nested maps. An
/// imported record (source set) has no seed or controller_config lines; a non-finite
/// sim_time_s (unknown) is left out. Missing fields read back as defaults. Absolute paths
/// (worlds_folder, config_files, the controller config's path fields as
/// controllers::mapControllerPaths knows them, such as a policy file) are written relative to
/// `record_dir` ("./x", "../x"), so a record holds no path of the machine that wrote it;
/// readManifest makes them absolute again.
std::string formatManifest(const RunManifest& manifest, const std::filesystem::path& record_dir);
/// Reads and checks a manifest; InputError naming the file and field on any problem. Paths
/// written relative to the record (see formatManifest) come back absolute. A config may be a
/// map or (records of earlier versions) YAML text in a string; either comes back as YAML text.
RunManifest readManifest(const std::filesystem::path& path);
/// readManifest of a manifest's text, as if it were the manifest of `record_dir` (`source`
/// names it in messages).
RunManifest parseManifest(const std::string& text, const std::filesystem::path& record_dir, const std::string& source);

/// The files a controller config (effective, paths absolute) names: every scalar value that is
/// an absolute path to a regular file, once each, in order, with its digest. InputError if one
/// cannot be read.
std::vector<ConfigFile> configFileDigests(const std::string& controller_config);
/// InputError naming the file if a file of `manifest.config_files` is missing or its bytes
/// changed since the run started (`what` says what refuses: "resume", "merge", "regress").
void checkConfigFiles(const RunManifest& manifest, const std::string& what);

/// The protocol the record's episodes ran under, read from its episode_config; InputError
/// naming `where` if that does not read.
core::ProtocolName recordProtocol(const RunManifest& manifest, const std::string& where);

/// Empty if `a` and `b` describe the same experiment (configs, worlds, trials, seed), else
/// the first field that differs.
std::string experimentDifference(const RunManifest& a, const RunManifest& b);

/// Digest of a world list (what `worlds_digest` records).
std::string worldsDigest(const std::vector<core::WorldSpec>& worlds);

/// Sorts results by (position of the world in `world_ids`, trial).
void sortResults(std::vector<EpisodeResult>& results, const std::vector<int>& world_ids);

/// The worlds a manifest names, read from its folder; InputError if one is missing or the
/// files changed since the run started (digest mismatch).
std::vector<core::WorldSpec> loadManifestWorlds(const RunManifest& manifest);

/// Checks episode rows against their record before they are trusted (a journal being resumed,
/// shards being merged): every row's world is one of the record's, its trial in range, its seed
/// the one (run seed, world, trial) gives (imported records have no seeds), no (world, trial)
/// twice, and every episode among `allowed` (indices world position x trials + trial; all of
/// the record's if empty) — and, with `complete`, every one of them present. InputError naming
/// `where` and the row otherwise.
void checkRows(const RunManifest& manifest, const std::vector<EpisodeResult>& rows, const std::string& where,
               const std::vector<std::size_t>& allowed, bool complete);

/// The files of a finished record in `dir`: episodes.csv (sorted), summary.json and the
/// manifest marked complete. `results` must hold every episode of the record; `episodes` are
/// they as written (sorted), so callers can go on without reading episodes.csv back.
struct CompleteRecordFiles {
  std::vector<core::FileContent> files;
  std::vector<EpisodeResult> episodes;
};
CompleteRecordFiles completeRecordFiles(const std::filesystem::path& dir, RunManifest manifest,
                                        std::vector<EpisodeResult> results, const std::vector<core::WorldSpec>& worlds);

/// Writes the finished record through `writer` (its folder, locked) as one set, the journal
/// removed with it; returns its episodes as written.
std::vector<EpisodeResult> writeCompleteRecord(const RecordWriter& writer, RunManifest manifest,
                                               std::vector<EpisodeResult> results,
                                               const std::vector<core::WorldSpec>& worlds);

/// A finished record read back.
struct CompleteRecord {
  RunManifest manifest;
  std::vector<EpisodeResult> episodes;  // as episodes.csv holds them
};

/// The one reader of a finished record, used by every command that reads one: InputError
/// (exit 2) naming the folder or file if it holds no record, is unfinished, a write into it
/// was interrupted, or its episodes.csv disagrees with its manifest — a row missing, extra,
/// twice or of another run ("episodes.csv: 3 rows, the manifest says 10 (world 3 trial 0
/// missing)"). The worlds are not loaded (loadManifestWorlds).
CompleteRecord readCompleteRecord(const std::filesystem::path& dir);
/// checkRows for a complete record's rows: every episode the manifest says it holds (its
/// shard's, or episodes_done for an imported one), each once. InputError naming `file`.
void checkCompleteRows(const RunManifest& manifest, const std::vector<EpisodeResult>& rows, const std::string& file);

}  // namespace barn::bench
