#include "barn/bench/record_session.hpp"

#include <algorithm>
#include <array>
#include <cerrno>
#include <cstdio>
#include <cstring>
#include <ctime>
#include <map>
#include <set>
#include <fcntl.h>
#include <sys/file.h>
#include <unistd.h>

#include "barn/bench/batch.hpp"
#include "barn/bench/results_io.hpp"
#include "barn/core/errors.hpp"

namespace barn::bench {

namespace fs = std::filesystem;

void checkNoRecord(const fs::path& dir) {
  std::error_code ec;
  if (fs::exists(dir / core::kCommitNote, ec))
    throw core::InputError(dir.string() + ": a write into this record was interrupted; barn run --resume " + dir.string() +
                           " completes it (or choose another --out)");
  if (!fs::exists(dir / kManifestFile)) return;
  bool complete = false;
  try {
    complete = readManifest(dir / kManifestFile).complete;
  } catch (const core::InputError&) {
    // A broken manifest is still a record not to overwrite; say so as for an unfinished one.
  }
  if (complete)
    throw core::InputError(dir.string() + ": already holds a complete run; choose another --out (barn run --force "
                           "replaces it once the new run is complete)");
  throw core::InputError(dir.string() + ": already holds an unfinished run; finish it with --resume " + dir.string() +
                         " or choose another --out");
}

void checkRecordSize(std::size_t worlds, int trials) {
  const std::size_t episodes = worlds * static_cast<std::size_t>(std::max(trials, 0));
  if (episodes > kMaxEpisodesPerRecord)
    throw core::InputError("--trials: " + std::to_string(worlds) + " worlds x " + std::to_string(trials) + " trials = " +
                           std::to_string(episodes) + " episodes, more than one run holds (" +
                           std::to_string(kMaxEpisodesPerRecord) + ", shards included); run fewer worlds or trials");
}

RecordSession createRecord(RunManifest manifest, std::vector<core::WorldSpec> worlds, const fs::path& dir) {
  checkNoRecord(dir);
  checkRecordSize(worlds.size(), manifest.trials);
  RecordSession session;
  session.dir = dir;
  session.manifest = std::move(manifest);
  session.worlds = std::move(worlds);
  // Last, once everything is valid (so bad input leaves no folder behind): the lock, and the
  // check again under it, which a second process started at the same moment cannot pass.
  session.writer = RecordWriter(dir);
  checkNoRecord(dir);
  return session;
}

std::string trajectoryFileName(int world_id, int trial) {
  return "world_" + std::to_string(world_id) + "_trial_" + std::to_string(trial) + ".csv";
}

RecordSession openRecord(const fs::path& dir) {
  RecordSession session;
  session.dir = dir;
  std::error_code ec;
  // A write killed before the manifest landed leaves its commit note: the writer completes it.
  if (!fs::exists(dir / kManifestFile, ec) && !fs::exists(dir / core::kCommitNote, ec))
    throw core::InputError(dir.string() + ": no run record here (no " + std::string(kManifestFile) + ")");
  try {
    session.writer = RecordWriter(dir);
  } catch (const core::IoError&) {
    // A complete record can be "resumed" (there is nothing to run) without being writable.
    core::checkNoInterruptedWrite(dir);
    if (!fs::exists(dir / kManifestFile, ec) || !readManifest(dir / kManifestFile).complete) throw;
  }
  if (!fs::exists(dir / kManifestFile, ec))
    throw core::InputError(dir.string() + ": no run record here (no " + std::string(kManifestFile) + ")");
  session.manifest = readManifest(dir / kManifestFile);
  const RunManifest& m = session.manifest;
  if (!m.source.empty())
    throw core::InputError(dir.string() + ": imported from " + m.source + " (barn import-out); there is nothing to run");
  session.worlds = loadManifestWorlds(m);
  if (!m.complete) {
    checkConfigFiles(m, "resuming");
    const fs::path journal = dir / kJournalFile;
    std::vector<EpisodeResult> previous = readEpisodesCsv(journal, true);
    const std::size_t total = session.worlds.size() * static_cast<std::size_t>(m.trials);
    checkRows(m, previous, journal.string(),
              m.shard_count > 0 ? shardEpisodes(total, m.shard_index, m.shard_count) : std::vector<std::size_t>{}, false);
    for (EpisodeResult& r : previous) {
      // An episode journaled without its trajectory file (a record of an older barn, or a file
      // lost) runs again: the same seed gives the same row and the file.
      if (m.trajectories && !fs::exists(dir / "trajectories" / trajectoryFileName(r.world_id, r.trial), ec)) continue;
      session.previous.push_back(std::move(r));
    }
  }
  return session;
}

std::vector<std::size_t> pendingEpisodes(const RecordSession& session) {
  const RunManifest& m = session.manifest;
  const std::size_t total = session.worlds.size() * static_cast<std::size_t>(m.trials);
  std::vector<std::size_t> mine;
  if (m.shard_count > 0) {
    mine = shardEpisodes(total, m.shard_index, m.shard_count);
  } else {
    for (std::size_t i = 0; i < total; ++i) mine.push_back(i);
  }
  std::vector<char> finished(total, 0);
  std::map<int, std::size_t> position;
  for (std::size_t i = 0; i < session.worlds.size(); ++i) position.emplace(session.worlds[i].id, i);
  for (const auto& r : session.previous) {
    if (!position.count(r.world_id) || r.trial < 0 || r.trial >= m.trials) continue;
    finished[position.at(r.world_id) * static_cast<std::size_t>(m.trials) + static_cast<std::size_t>(r.trial)] = 1;
  }
  std::vector<std::size_t> pending;
  for (std::size_t i : mine)
    if (!finished[i]) pending.push_back(i);
  return pending;
}

RecordJournal::RecordJournal(RecordSession& session, std::size_t pending, int threads) : session_(session) {
  RunManifest& m = session.manifest;
  m.barnbench_version = BARN_VERSION;
  m.git_commit = gitCommit();
  m.host = hostName();
  m.threads = threads;
  if (m.started.empty()) m.started = utcNow();
  m.episodes_total = session.previous.size() + pending;
  m.episodes_done = session.previous.size();
  std::string journal = episodesCsvHeader();
  for (const auto& r : session.previous) journal += episodeCsvRow(r);
  session.writer.write({{kManifestFile, formatManifest(m, session.dir)}, {kJournalFile, journal}});
  if (m.trajectories) {
    std::error_code ec;
    fs::create_directories(session.dir / "trajectories", ec);
    if (ec) throw core::IoError((session.dir / "trajectories").string() + ": cannot create folder: " + ec.message());
  }
  journal_.open(session.dir / kJournalFile, std::ios::app | std::ios::binary);
  if (!journal_) throw core::IoError((session.dir / kJournalFile).string() + ": cannot open: " + std::strerror(errno));
}

bool RecordJournal::append(const EpisodeResult& result) {
  if (session_.manifest.trajectories) {
    // The file first: a journaled row always has its trajectory (a kill between the two
    // leaves a file whose episode runs again and rewrites it, byte for byte).
    try {
      core::writeFileAtomic(session_.dir / "trajectories" / trajectoryFileName(result.world_id, result.trial),
                            trajectoryCsv(result));
    } catch (const core::IoError& e) {
      error_ = e.what();
      return false;
    }
  }
  journal_ << episodeCsvRow(result);
  journal_.flush();
  if (!journal_) {
    error_ = (session_.dir / kJournalFile).string() + ": write failed: " + std::strerror(errno);
    return false;
  }
  return true;
}

std::optional<std::vector<EpisodeResult>> RecordJournal::finish(std::vector<EpisodeResult> finished, double wall_time_s) {
  if (journal_.is_open()) journal_.close();
  RunManifest& m = session_.manifest;
  m.wall_time_s += wall_time_s;
  finished.insert(finished.end(), session_.previous.begin(), session_.previous.end());
  if (finished.size() < m.episodes_total) {
    m.episodes_done = finished.size();
    session_.writer.write({{kManifestFile, formatManifest(m, session_.dir)}});
    return std::nullopt;
  }
  std::vector<EpisodeResult> written = writeCompleteRecord(session_.writer, m, std::move(finished), session_.worlds);
  m.complete = true;
  m.episodes_done = m.episodes_total;
  return written;
}

void checkNoRecordForOut(const fs::path& dir) {
  std::error_code ec;
  if (fs::exists(dir / kManifestFile, ec) || fs::exists(dir / core::kCommitNote, ec))
    throw core::InputError(dir.string() + ": already holds a run record; choose another --out");
}

MergedRecord mergedShardRecords(const std::vector<fs::path>& shards, const fs::path& out) {
  if (shards.empty()) throw core::InputError("merge: no shard records given");
  std::vector<CompleteRecord> records;
  for (const auto& dir : shards) {
    std::error_code ec;
    if (!fs::exists(dir / kManifestFile, ec))
      throw core::InputError(dir.string() + ": no run record here (no " + std::string(kManifestFile) + ")");
    const RunManifest m = readManifest(dir / kManifestFile);
    if (m.shard_count == 0) throw core::InputError(dir.string() + ": not a shard (run without --shard)");
    if (!m.complete)
      throw core::InputError(dir.string() + ": shard " + std::to_string(m.shard_index) + " is not complete (barn run --resume " +
                             dir.string() + ")");
    records.push_back(readCompleteRecord(dir));
  }
  const RunManifest& first = records.front().manifest;
  std::set<int> seen;
  double wall = 0.0;
  bool trajectories = true;
  std::vector<EpisodeResult> results;
  for (std::size_t i = 0; i < records.size(); ++i) {
    const RunManifest& m = records[i].manifest;
    const std::string dir = shards[i].string();
    if (m.shard_count != first.shard_count)
      throw core::InputError(dir + ": shard of " + std::to_string(m.shard_count) + ", the first is of " +
                             std::to_string(first.shard_count));
    if (const std::string field = experimentDifference(first, m); !field.empty())
      throw core::InputError(dir + ": a different experiment from " + shards.front().string() + " (" + field + " differs)");
    if (!seen.insert(m.shard_index).second) throw core::InputError(dir + ": shard " + std::to_string(m.shard_index) + " given twice");
    results.insert(results.end(), records[i].episodes.begin(), records[i].episodes.end());
    wall += m.wall_time_s;
    trajectories = trajectories && m.trajectories;
  }
  if (static_cast<int>(seen.size()) != first.shard_count) {
    std::string missing;
    for (int k = 1; k <= first.shard_count; ++k)
      if (!seen.count(k)) missing += (missing.empty() ? "" : ", ") + std::to_string(k);
    throw core::InputError("merge: shards " + missing + " of " + std::to_string(first.shard_count) + " are missing");
  }
  MergedRecord merged;
  merged.manifest = first;
  RunManifest& m = merged.manifest;
  m.shard_index = 0;
  m.shard_count = 0;
  m.trajectories = trajectories;
  // Every episode once, each with its own seed: counts alone would take world 0 twice for a
  // missing world 1.
  checkRows(m, results, "merge", {}, true);
  m.episodes_total = first.world_ids.size() * static_cast<std::size_t>(first.trials);
  m.wall_time_s = wall;
  CompleteRecordFiles files = completeRecordFiles(out, m, std::move(results), loadManifestWorlds(m));
  merged.files = std::move(files.files);
  merged.episodes = std::move(files.episodes);
  if (trajectories) {
    for (std::size_t i = 0; i < records.size(); ++i)
      for (const EpisodeResult& r : records[i].episodes) {
        const std::string name = trajectoryFileName(r.world_id, r.trial);
        merged.files.push_back({"trajectories/" + name, core::readTextFile(shards[i] / "trajectories" / name)});
      }
  }
  m.complete = true;
  m.episodes_done = m.episodes_total;
  return merged;
}

MergedRecord mergeShardRecords(const std::vector<fs::path>& shards, const fs::path& out) {
  checkNoRecordForOut(out);
  MergedRecord merged = mergedShardRecords(shards, out);
  const RecordWriter writer(out);
  checkNoRecordForOut(out);  // again under the lock: a second merge into `out` cannot pass it
  writer.write(merged.files);
  return merged;
}

std::string hostName() {
  char name[256] = {};
  if (::gethostname(name, sizeof(name) - 1) != 0) return "unknown";
  return name;
}

std::string utcNow() {
  const std::time_t now = std::time(nullptr);
  std::tm utc{};
  ::gmtime_r(&now, &utc);
  char text[32];
  std::strftime(text, sizeof(text), "%Y-%m-%dT%H:%M:%SZ", &utc);
  return text;
}

}  // namespace barn::bench
