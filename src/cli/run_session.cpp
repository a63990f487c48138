// Executing run records: the shared core of barn run, regress and sweep.

#include "run_session.hpp"

#include <algorithm>
#include <atomic>
#include <chrono>
#include <cerrno>
#include <csignal>
#include <cstring>
#include <cstdio>
#include <exception>
#include <fstream>
#include <memory>
#include <optional>
#include <set>
#include <unistd.h>

#include "barn/bench/progress.hpp"
#include "barn/bench/record_session.hpp"
#include "barn/bench/report.hpp"
#include "barn/bench/results_io.hpp"
#include "barn/core/errors.hpp"
#include "barn/core/text_io.hpp"

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

}  // namespace

Session newSession(const std::string& controller_name, const core::ConfigNode& controller_config,
                   const bench::EpisodeConfig& episode, const bench::LoadedWorlds& loaded,
                   const std::string& worlds_spec, int trials, std::uint64_t seed, int shard_index, int shard_count,
                   const fs::path& dir) {
  if (!dir.empty()) bench::checkNoRecord(dir);  // before any work, for a quick answer
  Session session;
  controllers::PreparedController controller = controllers::prepareController(controller_config);
  session.make_controller = std::move(controller.factory);
  session.episode = episode;
  const std::unique_ptr<controllers::Controller> probe = session.make_controller();
  bench::checkControllerFits(*probe, episode);  // before any episode
  session.plant_warning = bench::plantMismatch(*probe, episode);
  bench::RunManifest manifest =
      bench::newManifest(controller_name, controller.effective_config, episode, loaded, worlds_spec, trials, seed);
  manifest.shard_index = shard_index;
  manifest.shard_count = shard_count;
  if (dir.empty()) {  // checked only
    bench::checkRecordSize(loaded.worlds.size(), trials);
    session.record.manifest = std::move(manifest);
    session.record.worlds = loaded.worlds;
    return session;
  }
  // Last, once everything is valid, so bad input leaves no folder behind.
  session.record = bench::createRecord(std::move(manifest), loaded.worlds, dir);
  return session;
}

Session resumedSession(const fs::path& dir) {
  Session session;
  session.record = bench::openRecord(dir);
  const bench::RunManifest& m = session.record.manifest;
  session.make_controller =
      controllers::makeControllerFactory(core::ConfigNode::parseString(m.controller_config, "manifest controller_config"));
  session.episode = bench::validatedEpisodeConfig(core::ConfigNode::parseString(m.episode_config, "manifest episode_config"),
                                                  (dir / bench::kManifestFile).string());
  try {
    session.plant_warning = bench::plantMismatch(*session.make_controller(), session.episode);
  } catch (const std::exception&) {
    // A controller that cannot be made (its policy file gone) fails every episode, as before.
  }
  return session;
}

void printRecordSummary(const fs::path& dir, const bench::RunManifest& m, const std::vector<core::WorldSpec>& worlds,
                        const std::vector<bench::EpisodeResult>& results, core::ProtocolName protocol,
                        bool every_bucket) {
  const bench::RunSummary summary = bench::summarise(results);
  std::printf("%s", bench::summaryTable(summary, m.controller + " on " + bench::worldSetName(worlds) + " worlds " +
                                                     m.worlds_spec + " x " + std::to_string(m.trials) + " trials (" +
                                                     std::string(core::toString(protocol)) + ")").c_str());
  // A bucket of a few worlds says little: a group is shown only when each of its buckets has
  // kMinWorldsPerBucket worlds (all of them with every_bucket; summary.json has them all).
  constexpr int kMinWorldsPerBucket = 5;
  const std::vector<bench::BucketSummary> all = bench::difficultyBreakdown(results, worlds);
  std::vector<bench::BucketSummary> shown;
  std::size_t left_out = 0;
  for (std::size_t begin = 0; begin < all.size();) {
    std::size_t end = begin;
    int fewest = all[begin].summary.worlds;
    while (end < all.size() && all[end].group == all[begin].group) fewest = std::min(fewest, all[end++].summary.worlds);
    if (every_bucket || fewest >= kMinWorldsPerBucket) shown.insert(shown.end(), all.begin() + static_cast<long>(begin), all.begin() + static_cast<long>(end));
    else ++left_out;
    begin = end;
  }
  if (!shown.empty()) std::printf("%s", bench::breakdownTable(shown).c_str());
  if (left_out > 0)
    std::printf("  (%zu difficulty groups with fewer than %d worlds per bucket not shown: barn show %s --breakdown)\n",
                left_out, kMinWorldsPerBucket, dir.c_str());
}

namespace {

/// The sessions with episodes left to run, in order; the complete ones are reported.
std::vector<Session*> sessionsToRun(const std::vector<Session*>& sessions, bool print_summaries) {
  std::vector<Session*> running;
  for (Session* session : sessions) {
    const bench::RecordSession& record = session->record;
    if (!record.manifest.complete) {
      running.push_back(session);
      continue;
    }
    std::printf("%s is already complete\n", record.dir.c_str());
    // Complete in an earlier session: its episodes are only on disk.
    if (print_summaries)
      printRecordSummary(record.dir, record.manifest, record.worlds, bench::readCompleteRecord(record.dir).episodes,
                         session->episode.protocol);
  }
  return running;
}

/// The experiment of a session's batch, all of it in one place: the record's worlds, trials
/// and seed, the episodes it still lacks, the session's controller and episode config.
bench::BatchSpec pendingBatch(const Session& session, bool record_trajectories) {
  const bench::RunManifest& m = session.record.manifest;
  bench::BatchSpec batch;
  batch.worlds = session.record.worlds;
  batch.trials = m.trials;
  batch.seed = m.seed;
  batch.episode = session.episode;
  batch.make_controller = session.make_controller;
  batch.record_trajectories = record_trajectories;
  batch.selected = bench::pendingEpisodes(session.record);
  return batch;
}

/// Every session's batch and open journal, in order.
struct PreparedBatches {
  std::vector<bench::BatchSpec> batches;
  std::vector<std::unique_ptr<bench::RecordJournal>> journals;
};

/// Makes each session's batch (the episodes still pending) and opens its journal; prints what
/// is about to run (`one_record`: the run is a single record's).
PreparedBatches prepareBatches(const std::vector<Session*>& running, bool one_record, int threads, std::size_t& total,
                               std::size_t& already) {
  PreparedBatches prepared;
  total = already = 0;
  for (Session* session : running) {
    const bench::BatchSpec& batch =
        prepared.batches.emplace_back(pendingBatch(*session, session->record.manifest.trajectories));
    prepared.journals.push_back(std::make_unique<bench::RecordJournal>(session->record, batch.selected->size(), threads));
    total += session->record.manifest.episodes_total;
    already += session->record.previous.size();
  }
  if (one_record) {
    const bench::RecordSession& s = running.front()->record;
    const bench::RunManifest& m = s.manifest;
    std::printf("running %s: %zu worlds x %d trials = %zu episodes%s on %d threads -> %s\n", m.controller.c_str(),
                s.worlds.size(), m.trials, m.episodes_total,
                m.shard_count ? (" (shard " + std::to_string(m.shard_index) + "/" + std::to_string(m.shard_count) + ")").c_str() : "",
                threads, s.dir.c_str());
  } else {
    std::printf("running %zu records, %zu episodes in one pool on %d threads\n", running.size(), total, threads);
  }
  if (already > 0) std::printf("resuming: %zu episodes already finished\n", already);
  std::fflush(stdout);
  return prepared;
}

/// What one pool of batches produced, per batch.
struct PoolOutput {
  std::vector<std::vector<bench::EpisodeResult>> results;
  double wall = 0.0;  // [s]
};

/// Runs every batch in one pool, journaling each episode as it ends; Ctrl-C, SIGTERM,
/// --stop-after or a failed journal write stop it between episodes.
PoolOutput runPool(PreparedBatches& prepared, const SessionOptions& options,
                   std::size_t total, std::size_t already) {
  std::vector<const bench::BatchSpec*> specs;
  for (const bench::BatchSpec& batch : prepared.batches) specs.push_back(&batch);
  std::vector<std::unique_ptr<bench::RecordJournal>>& journals = prepared.journals;
  g_interrupted.store(false);
  std::signal(SIGINT, onInterrupt);
  std::signal(SIGTERM, onInterrupt);  // Slurm's time limit and preemption
  const bench::BatchExecution execution{options.jobs, &g_interrupted};
  bench::ProgressReporter progress(total, already, ::isatty(STDOUT_FILENO));
  PoolOutput out;
  const auto t0 = std::chrono::steady_clock::now();
  std::size_t finished_here = 0;
  std::string journal_error;  // the first failed journal write: the run stops there
  out.results = bench::runBatches(specs, execution, [&](std::size_t batch, const bench::EpisodeResult& r, std::size_t, std::size_t) {
    if (journal_error.empty() && !journals[batch]->append(r)) {
      journal_error = journals[batch]->error();
      g_interrupted.store(true);  // nothing more can be kept: start no new episode
    }
    progress.update(r.outcome == bench::Outcome::Success, r.sim_time);
    if (options.stop_after > 0 && ++finished_here >= options.stop_after) g_interrupted.store(true);
  });
  progress.finish();
  std::signal(SIGINT, SIG_DFL);
  std::signal(SIGTERM, SIG_DFL);
  if (!journal_error.empty()) throw core::IoError(journal_error + " (the episodes journaled before it are kept; --resume when the disk has room)");
  out.wall = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
  return out;
}

}  // namespace

int executeSessions(const std::vector<Session*>& sessions, const SessionOptions& options, bool print_summaries) {
  const int threads = options.jobs > 0 ? options.jobs : static_cast<int>(std::max(1L, ::sysconf(_SC_NPROCESSORS_ONLN)));
  const std::vector<Session*> running = sessionsToRun(sessions, print_summaries);
  if (running.empty()) return 0;
  std::set<std::string> warned;  // a sweep's cells mostly share one policy: each warning once
  for (const Session* session : running)
    if (!session->plant_warning.empty() && warned.insert(session->plant_warning).second)
      std::fprintf(stderr, "warning: %s: %s\n", session->record.manifest.controller.c_str(), session->plant_warning.c_str());
  std::size_t total = 0, already = 0;
  PreparedBatches prepared = prepareBatches(running, sessions.size() == 1, threads, total, already);
  PoolOutput pool = runPool(prepared, options, total, already);

  // Each record is written whole (or, interrupted, left to --resume).
  int status = 0;
  double sim_time_here = 0.0;
  bool interrupted = false;
  for (std::size_t batch = 0; batch < running.size(); ++batch) {
    bench::RecordSession& record = running[batch]->record;
    bool episode_error = false;
    for (const auto& r : pool.results[batch]) {
      sim_time_here += r.sim_time;
      episode_error = episode_error || r.outcome == bench::Outcome::Error;
    }
    for (const auto& r : record.previous) episode_error = episode_error || r.outcome == bench::Outcome::Error;
    const std::optional<std::vector<bench::EpisodeResult>> complete =
        prepared.journals[batch]->finish(std::move(pool.results[batch]), pool.wall / static_cast<double>(running.size()));
    if (!complete) {
      interrupted = true;
      continue;
    }
    if (print_summaries) printRecordSummary(record.dir, record.manifest, record.worlds, *complete, running[batch]->episode.protocol);
    if (episode_error) status = 1;
  }
  std::printf("  performance: wall %.2f s, simulated %.1f s, %.0f simulated s per wall s (%.0f per core, %d threads)\n",
              pool.wall, sim_time_here, sim_time_here / pool.wall, sim_time_here / pool.wall / threads, threads);
  if (interrupted) {
    for (Session* s : sessions)
      if (!s->record.manifest.complete && fs::exists(s->record.dir / bench::kJournalFile))
        std::printf("interrupted: finish with: barn run --resume %s\n", s->record.dir.c_str());
    return 1;
  }
  if (sessions.size() == 1) std::printf("wrote %s\n", sessions.front()->record.dir.c_str());
  return status;
}

int runRecordFolder(const fs::path& dir, const SessionOptions& options) {
  Session session = resumedSession(dir);
  return executeSessions({&session}, options, true);
}

}  // namespace barn::cli
