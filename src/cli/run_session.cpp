// Executing run records: the shared core of barn run, regress and sweep.

#include "run_session.hpp"

#include <algorithm>
#include <atomic>
#include <chrono>
#include <cerrno>
#include <csignal>
#include <cstring>
#include <cstdio>
#include <fstream>
#include <map>
#include <fcntl.h>
#include <sys/file.h>
#include <unistd.h>

#include "barn/bench/report.hpp"
#include "barn/bench/results_io.hpp"
#include "barn/core/errors.hpp"
#include "barn/core/text_io.hpp"
#include "progress.hpp"
#include "run_environment.hpp"

namespace barn::cli {

namespace fs = std::filesystem;

namespace {

// Set by SIGINT: the batch starts no new episode, running ones finish and are kept. A signal
// handler can only reach a global; this is the one mutable global of barnbench.
std::atomic<bool> g_interrupted{false};

extern "C" void onInterrupt(int signal) {
  g_interrupted.store(true);
  std::signal(signal, SIG_DFL);  // a second Ctrl-C kills at once
}

// Episode indices of the record still to run.
std::vector<std::size_t> pendingEpisodes(const Session& session) {
  const std::size_t total = session.worlds.size() * static_cast<std::size_t>(session.manifest.trials);
  std::vector<std::size_t> mine;
  if (session.manifest.shard_count > 0) {
    mine = bench::shardEpisodes(total, session.manifest.shard_index, session.manifest.shard_count);
  } else {
    for (std::size_t i = 0; i < total; ++i) mine.push_back(i);
  }
  std::vector<char> finished(total, 0);
  std::map<int, std::size_t> position;
  for (std::size_t i = 0; i < session.worlds.size(); ++i) position.emplace(session.worlds[i].id, i);
  for (const auto& r : session.previous) {
    if (!position.count(r.world_id) || r.trial < 0 || r.trial >= session.manifest.trials) continue;
    finished[position.at(r.world_id) * static_cast<std::size_t>(session.manifest.trials) + static_cast<std::size_t>(r.trial)] = 1;
  }
  std::vector<std::size_t> pending;
  for (std::size_t i : mine)
    if (!finished[i]) pending.push_back(i);
  return pending;
}

}  // namespace

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

Session newSession(const std::string& controller_name, const core::ConfigNode& controller_config,
                   const bench::EpisodeConfig& episode, const bench::LoadedWorlds& loaded,
                   const std::string& worlds_spec, int trials, std::uint64_t seed, int shard_index, int shard_count,
                   const fs::path& dir) {
  Session session;
  session.dir = dir;
  const auto refuseAnExistingRun = [&] {
    if (fs::exists(session.dir / bench::kManifestFile))
      throw core::InputError(session.dir.string() + ": already holds a run; finish it with --resume " +
                             session.dir.string() + " or choose another --out");
  };
  refuseAnExistingRun();  // before any work, for a quick answer
  // A bound on one record's bookkeeping (a few hundred bytes per episode, set up before the
  // first one runs): beyond it, shards (--shard K/N) split the run across processes.
  constexpr std::size_t kMaxEpisodesPerRecord = 1'000'000;
  const std::size_t episodes = loaded.worlds.size() * static_cast<std::size_t>(std::max(trials, 0));
  if (episodes > kMaxEpisodesPerRecord)
    throw core::InputError("--trials: " + std::to_string(loaded.worlds.size()) + " worlds x " + std::to_string(trials) +
                           " trials = " + std::to_string(episodes) + " episodes, more than one record holds (" +
                           std::to_string(kMaxEpisodesPerRecord) + "); split the run with --shard K/N");
  session.spec.make_controller = controllers::makeControllerFactory(controller_config);
  session.spec.episode = episode;
  session.manifest = bench::newManifest(controller_name, controllers::effectiveControllerConfig(controller_config), episode,
                                       loaded, worlds_spec, trials, seed);
  bench::RunManifest& m = session.manifest;
  m.shard_index = shard_index;
  m.shard_count = shard_count;
  session.worlds = loaded.worlds;
  // Last, once everything is valid (so bad input leaves no folder behind): the lock, and the
  // check again under it, which a second process started at the same moment cannot pass.
  session.lock = RecordLock(dir);
  refuseAnExistingRun();
  return session;
}

Session resumedSession(const fs::path& dir) {
  Session session;
  session.dir = dir;
  if (!fs::exists(dir / bench::kManifestFile))
    throw core::InputError(dir.string() + ": no run record here (no " + std::string(bench::kManifestFile) + ")");
  session.lock = RecordLock(dir);
  session.manifest = bench::readManifest(session.dir / bench::kManifestFile);
  const bench::RunManifest& m = session.manifest;
  if (!m.source.empty())
    throw core::InputError(dir.string() + ": imported from " + m.source + " (barn import-out); there is nothing to run");
  session.spec.make_controller =
      controllers::makeControllerFactory(core::ConfigNode::parseString(m.controller_config, "manifest controller_config"));
  session.spec.episode = bench::validatedEpisodeConfig(core::ConfigNode::parseString(m.episode_config, "manifest episode_config"),
                                                (session.dir / bench::kManifestFile).string());
  session.worlds = bench::loadManifestWorlds(m);
  if (!m.complete) {
    const fs::path journal = session.dir / bench::kJournalFile;
    session.previous = bench::readEpisodesCsv(journal, true);
    const std::size_t total = session.worlds.size() * static_cast<std::size_t>(m.trials);
    bench::checkRows(m, session.previous, journal.string(),
                     m.shard_count > 0 ? bench::shardEpisodes(total, m.shard_index, m.shard_count) : std::vector<std::size_t>{},
                     false);
  }
  return session;
}

void printRecordSummary(const fs::path& dir, const bench::RunManifest& m, const std::vector<core::WorldSpec>& worlds) {
  const std::vector<bench::EpisodeResult> results = bench::readEpisodesCsv(dir / bench::kEpisodesFile);
  const bench::RunSummary summary = bench::summarise(results);
  const std::string protocol =
      core::readConfig<bench::EpisodeConfig>(core::ConfigNode::parseString(m.episode_config, "manifest")).protocol;
  std::printf("%s", bench::summaryTable(summary, m.controller + " on " + m.worlds_spec + " x " + std::to_string(m.trials) +
                                                     " trials (" + protocol + ")").c_str());
  std::printf("%s", bench::breakdownTable(bench::difficultyBreakdown(results, worlds)).c_str());
}


int executeSessions(const std::vector<Session*>& sessions, const SessionOptions& options, bool print_summaries) {
  const int threads = options.jobs > 0 ? options.jobs : static_cast<int>(std::max(1L, ::sysconf(_SC_NPROCESSORS_ONLN)));
  std::vector<Session*> pending_sessions;
  std::vector<std::ofstream> journals(sessions.size());
  std::size_t total = 0, already = 0;
  for (std::size_t b = 0; b < sessions.size(); ++b) {
    Session& session = *sessions[b];
    bench::RunManifest& m = session.manifest;
    if (m.complete) continue;
    session.spec.worlds = session.worlds;
    session.spec.trials = m.trials;
    session.spec.seed = m.seed;
    session.spec.jobs = options.jobs;
    session.spec.record_trajectories = options.trajectories;
    session.spec.selected = pendingEpisodes(session);
    m.barnbench_version = BARN_VERSION;
    m.git_commit = gitCommit();
    m.host = hostName();
    m.threads = threads;
    if (m.started.empty()) m.started = utcNow();
    m.episodes_total = session.previous.size() + session.spec.selected->size();
    m.episodes_done = session.previous.size();
    total += m.episodes_total;
    already += session.previous.size();
    // The journal is rewritten from the rows that survived (an interrupted write may have left
    // half a line), then appended to as episodes finish.
    std::string journal = bench::episodesCsvHeader();
    for (const auto& r : session.previous) journal += bench::episodeCsvRow(r);
    core::writeFilesAtomic(session.dir, {{bench::kManifestFile, bench::formatManifest(m)}, {bench::kJournalFile, journal}});
    journals[b].open(session.dir / bench::kJournalFile, std::ios::app | std::ios::binary);
  }
  std::vector<const bench::BatchSpec*> specs;
  std::vector<std::size_t> batch_session;
  for (std::size_t b = 0; b < sessions.size(); ++b) {
    if (sessions[b]->manifest.complete) {
      std::printf("%s is already complete\n", sessions[b]->dir.c_str());
      if (print_summaries) printRecordSummary(sessions[b]->dir, sessions[b]->manifest, sessions[b]->worlds);
      continue;
    }
    specs.push_back(&sessions[b]->spec);
    batch_session.push_back(b);
  }
  if (specs.empty()) return 0;

  if (sessions.size() == 1) {
    const Session& s = *sessions.front();
    const bench::RunManifest& m = s.manifest;
    std::printf("running %s: %zu worlds x %d trials = %zu episodes%s on %d threads -> %s\n", m.controller.c_str(),
                s.worlds.size(), m.trials, m.episodes_total,
                m.shard_count ? (" (shard " + std::to_string(m.shard_index) + "/" + std::to_string(m.shard_count) + ")").c_str() : "",
                threads, s.dir.c_str());
  } else {
    std::printf("running %zu records, %zu episodes in one pool on %d threads\n", specs.size(), total, threads);
  }
  if (already > 0) std::printf("resuming: %zu episodes already finished\n", already);
  std::fflush(stdout);

  g_interrupted.store(false);
  std::signal(SIGINT, onInterrupt);
  std::signal(SIGTERM, onInterrupt);  // Slurm's time limit and preemption
  const_cast<bench::BatchSpec*>(specs.front())->stop = &g_interrupted;
  ProgressReporter progress(total, already, ::isatty(STDOUT_FILENO));
  std::vector<std::vector<core::FileContent>> trajectories(sessions.size());
  const auto t0 = std::chrono::steady_clock::now();
  std::size_t finished_here = 0;
  std::string journal_error;  // the first failed journal write: the run stops there
  std::vector<std::vector<bench::EpisodeResult>> results =
      bench::runBatches(specs, [&](std::size_t batch, const bench::EpisodeResult& r, std::size_t, std::size_t) {
        const std::size_t b = batch_session[batch];
        journals[b] << bench::episodeCsvRow(r);
        journals[b].flush();
        if (!journals[b] && journal_error.empty()) {
          journal_error = (sessions[b]->dir / bench::kJournalFile).string() + ": write failed: " + std::strerror(errno);
          g_interrupted.store(true);  // nothing more can be kept: start no new episode
        }
        if (options.trajectories)
          trajectories[b].push_back({"world_" + std::to_string(r.world_id) + "_trial_" + std::to_string(r.trial) + ".csv",
                                     bench::trajectoryCsv(r)});
        progress.update(r.outcome == bench::Outcome::Success, r.sim_time);
        if (options.stop_after > 0 && ++finished_here >= options.stop_after) g_interrupted.store(true);
      });
  progress.finish();
  std::signal(SIGINT, SIG_DFL);
  std::signal(SIGTERM, SIG_DFL);
  for (auto& j : journals) if (j.is_open()) j.close();
  if (!journal_error.empty()) throw core::IoError(journal_error + " (the episodes journaled before it are kept; --resume when the disk has room)");
  const double wall = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();

  int status = 0;
  double sim_time_here = 0.0;
  bool interrupted = false;
  for (std::size_t batch = 0; batch < specs.size(); ++batch) {
    Session& session = *sessions[batch_session[batch]];
    bench::RunManifest& m = session.manifest;
    std::vector<bench::EpisodeResult>& mine = results[batch];
    for (const auto& r : mine) sim_time_here += r.sim_time;
    m.wall_time_s += wall / static_cast<double>(specs.size());
    if (options.trajectories) core::writeFilesAtomic(session.dir / "trajectories", trajectories[batch_session[batch]]);
    mine.insert(mine.end(), session.previous.begin(), session.previous.end());
    if (mine.size() < m.episodes_total) {
      m.episodes_done = mine.size();
      core::writeFileAtomic(session.dir / bench::kManifestFile, bench::formatManifest(m));
      interrupted = true;
      continue;
    }
    bench::writeCompleteRecord(session.dir, m, mine, session.worlds);
    if (print_summaries) printRecordSummary(session.dir, m, session.worlds);
    for (const auto& r : mine)
      if (r.outcome == bench::Outcome::Error) status = 1;
  }
  std::printf("  performance: wall %.2f s, simulated %.1f s, %.0f simulated s per wall s (%.0f per core, %d threads)\n",
              wall, sim_time_here, sim_time_here / wall, sim_time_here / wall / threads, threads);
  if (interrupted) {
    for (Session* s : sessions)
      if (!s->manifest.complete && fs::exists(s->dir / bench::kJournalFile))
        std::printf("interrupted: finish with: barn run --resume %s\n", s->dir.c_str());
    return 1;
  }
  if (sessions.size() == 1) std::printf("wrote %s\n", sessions.front()->dir.c_str());
  return status;
}

int runRecordFolder(const fs::path& dir, const SessionOptions& options) {
  Session session = resumedSession(dir);
  return executeSessions({&session}, options, true);
}

}  // namespace barn::cli
