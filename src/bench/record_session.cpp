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

RecordLock::RecordLock(const fs::path& dir) {
  std::error_code ec;
  fs::create_directories(dir, ec);
  if (ec) throw core::IoError(dir.string() + ": cannot create folder: " + ec.message());
  const fs::path path = dir / ".barn.lock";
  fd_ = ::open(path.c_str(), O_RDWR | O_CREAT | O_CLOEXEC, 0644);
  if (fd_ < 0) throw core::IoError(path.string() + ": cannot open: " + std::strerror(errno));
  if (::flock(fd_, LOCK_EX | LOCK_NB) != 0) {
    char holder[32] = {};
    const ssize_t n = ::pread(fd_, holder, sizeof(holder) - 1, 0);
    ::close(fd_);
    fd_ = -1;
    throw core::InputError(dir.string() + ": another barn process is writing this record" +
                           (n > 0 ? " (pid " + std::string(holder, static_cast<std::size_t>(n)) + ")" : std::string()) +
                           "; wait for it or choose another --out");
  }
  const std::string pid = std::to_string(::getpid());
  if (::ftruncate(fd_, 0) == 0 && ::pwrite(fd_, pid.data(), pid.size(), 0) < 0) {
    // The pid is only for the message above; the lock holds without it.
  }
}

RecordLock& RecordLock::operator=(RecordLock&& other) noexcept {
  if (this != &other) {
    if (fd_ >= 0) ::close(fd_);
    fd_ = std::exchange(other.fd_, -1);
  }
  return *this;
}

RecordLock::~RecordLock() {
  if (fd_ >= 0) ::close(fd_);  // closing releases the flock
}

void checkNoRecord(const fs::path& dir) {
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

RecordSession createRecord(RunManifest manifest, std::vector<core::WorldSpec> worlds, const fs::path& dir) {
  checkNoRecord(dir);
  const std::size_t episodes = worlds.size() * static_cast<std::size_t>(std::max(manifest.trials, 0));
  if (episodes > kMaxEpisodesPerRecord)
    throw core::InputError("--trials: " + std::to_string(worlds.size()) + " worlds x " + std::to_string(manifest.trials) +
                           " trials = " + std::to_string(episodes) + " episodes, more than one record holds (" +
                           std::to_string(kMaxEpisodesPerRecord) + "); split the run with --shard K/N");
  RecordSession session;
  session.dir = dir;
  session.manifest = std::move(manifest);
  session.worlds = std::move(worlds);
  // Last, once everything is valid (so bad input leaves no folder behind): the lock, and the
  // check again under it, which a second process started at the same moment cannot pass.
  session.lock = RecordLock(dir);
  checkNoRecord(dir);
  return session;
}

RecordSession openRecord(const fs::path& dir) {
  RecordSession session;
  session.dir = dir;
  if (!fs::exists(dir / kManifestFile))
    throw core::InputError(dir.string() + ": no run record here (no " + std::string(kManifestFile) + ")");
  session.lock = RecordLock(dir);
  session.manifest = readManifest(dir / kManifestFile);
  const RunManifest& m = session.manifest;
  if (!m.source.empty())
    throw core::InputError(dir.string() + ": imported from " + m.source + " (barn import-out); there is nothing to run");
  session.worlds = loadManifestWorlds(m);
  if (!m.complete) {
    const fs::path journal = dir / kJournalFile;
    session.previous = readEpisodesCsv(journal, true);
    const std::size_t total = session.worlds.size() * static_cast<std::size_t>(m.trials);
    checkRows(m, session.previous, journal.string(),
              m.shard_count > 0 ? shardEpisodes(total, m.shard_index, m.shard_count) : std::vector<std::size_t>{}, false);
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
  core::writeFilesAtomic(session.dir, {{kManifestFile, formatManifest(m, session.dir)}, {kJournalFile, journal}});
  journal_.open(session.dir / kJournalFile, std::ios::app | std::ios::binary);
  if (!journal_) throw core::IoError((session.dir / kJournalFile).string() + ": cannot open: " + std::strerror(errno));
}

bool RecordJournal::append(const EpisodeResult& result) {
  journal_ << episodeCsvRow(result);
  journal_.flush();
  return static_cast<bool>(journal_);
}

std::optional<std::vector<EpisodeResult>> RecordJournal::finish(
    std::vector<EpisodeResult> finished, double wall_time_s,
    const std::optional<std::vector<core::FileContent>>& trajectories) {
  if (journal_.is_open()) journal_.close();
  RunManifest& m = session_.manifest;
  m.wall_time_s += wall_time_s;
  if (trajectories) core::writeFilesAtomic(session_.dir / "trajectories", *trajectories);
  finished.insert(finished.end(), session_.previous.begin(), session_.previous.end());
  if (finished.size() < m.episodes_total) {
    m.episodes_done = finished.size();
    core::writeFileAtomic(session_.dir / kManifestFile, formatManifest(m, session_.dir));
    return std::nullopt;
  }
  std::vector<EpisodeResult> written = writeCompleteRecord(session_.dir, m, std::move(finished), session_.worlds);
  m.complete = true;
  return written;
}

RunManifest mergeShardRecords(const std::vector<fs::path>& shards, const fs::path& out) {
  if (shards.empty()) throw core::InputError("merge: no shard records given");
  if (fs::exists(out / kManifestFile)) throw core::InputError(out.string() + ": already holds a run record");
  std::vector<RunManifest> manifests;
  for (const auto& dir : shards) manifests.push_back(readManifest(dir / kManifestFile));
  const RunManifest& first = manifests.front();
  std::set<int> seen;
  double wall = 0.0;
  std::vector<EpisodeResult> results;
  for (std::size_t i = 0; i < manifests.size(); ++i) {
    const RunManifest& m = manifests[i];
    const std::string dir = shards[i].string();
    if (m.shard_count == 0) throw core::InputError(dir + ": not a shard (run without --shard)");
    if (m.shard_count != first.shard_count)
      throw core::InputError(dir + ": shard of " + std::to_string(m.shard_count) + ", the first is of " +
                             std::to_string(first.shard_count));
    if (const std::string field = experimentDifference(first, m); !field.empty())
      throw core::InputError(dir + ": a different experiment from " + shards.front().string() + " (" + field + " differs)");
    if (!seen.insert(m.shard_index).second) throw core::InputError(dir + ": shard " + std::to_string(m.shard_index) + " given twice");
    if (!m.complete)
      throw core::InputError(dir + ": shard " + std::to_string(m.shard_index) + " is not complete (barn run --resume " + dir + ")");
    const auto rows = readEpisodesCsv(shards[i] / kEpisodesFile);
    results.insert(results.end(), rows.begin(), rows.end());
    wall += m.wall_time_s;
  }
  if (static_cast<int>(seen.size()) != first.shard_count) {
    std::string missing;
    for (int k = 1; k <= first.shard_count; ++k)
      if (!seen.count(k)) missing += (missing.empty() ? "" : ", ") + std::to_string(k);
    throw core::InputError("merge: shards " + missing + " of " + std::to_string(first.shard_count) + " are missing");
  }
  RunManifest merged = first;
  merged.shard_index = 0;
  merged.shard_count = 0;
  // Every episode once, each with its own seed: counts alone would take world 0 twice for a
  // missing world 1.
  checkRows(merged, results, "merge", {}, true);
  merged.episodes_total = first.world_ids.size() * static_cast<std::size_t>(first.trials);
  merged.wall_time_s = wall;
  writeCompleteRecord(out, merged, results, loadManifestWorlds(merged));
  merged.complete = true;
  merged.episodes_done = merged.episodes_total;
  return merged;
}

namespace {

std::string firstLineOf(const std::string& command) {
  std::string output;
  if (FILE* pipe = ::popen(command.c_str(), "r")) {
    std::array<char, 256> buffer{};
    if (std::fgets(buffer.data(), static_cast<int>(buffer.size()), pipe)) output = buffer.data();
    ::pclose(pipe);
  }
  while (!output.empty() && (output.back() == '\n' || output.back() == '\r')) output.pop_back();
  return output;
}

}  // namespace

std::string gitCommit() {
  const std::string dir = BARN_SOURCE_DIR;
  const std::string commit = firstLineOf("git -C '" + dir + "' rev-parse HEAD 2>/dev/null");
  if (commit.empty()) return "unknown";
  const std::string dirty = firstLineOf("git -C '" + dir + "' status --porcelain --untracked-files=no 2>/dev/null");
  return dirty.empty() ? commit : commit + "-dirty";
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
