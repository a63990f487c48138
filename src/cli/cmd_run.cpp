// barn run: every (world, trial) episode of a controller in parallel, scored as BARN does,
// written as an experiment record (see bench/run_record.hpp). Interruptible and resumable;
// shardable across machines (barn merge puts the shards together).

#include <atomic>
#include <chrono>
#include <csignal>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <unistd.h>

#include "barn/bench/batch.hpp"
#include "barn/bench/report.hpp"
#include "barn/bench/results_io.hpp"
#include "barn/bench/run_record.hpp"
#include "barn/bench/world_selection.hpp"
#include "barn/core/config.hpp"
#include "barn/core/errors.hpp"
#include "barn/core/text_io.hpp"
#include "commands.hpp"
#include "progress.hpp"
#include "repo_paths.hpp"
#include "run_environment.hpp"

namespace barn::cli {

namespace {

namespace fs = std::filesystem;

// Set by SIGINT: the batch starts no new episode, running ones finish and are kept. A signal
// handler can only reach a global; this is the one mutable global of barnbench.
std::atomic<bool> g_interrupted{false};

extern "C" void onInterrupt(int signal) {
  g_interrupted.store(true);
  std::signal(signal, SIG_DFL);  // a second Ctrl-C kills at once
}

struct RunOptions {
  std::string controller;
  std::string config;
  std::string sim_config;
  std::string worlds = "all";
  int trials = 1;
  std::string protocol;
  int jobs = 0;
  std::uint64_t seed = 0;
  std::string out;
  std::string shard;
  std::string resume;
  bool keep_going = false;
  bool trajectories = false;
  std::size_t stop_after = 0;  // 0 = never
};

// The controller config: --config FILE, else configs/controllers/NAME.yaml, else the type NAME
// with its defaults.
core::ConfigNode controllerConfig(const RunOptions& options) {
  if (!options.config.empty()) return core::ConfigNode::parseFile(options.config);
  const auto file = repoPath("configs") / "controllers" / (options.controller + ".yaml");
  if (fs::exists(file)) return core::ConfigNode::parseFile(file);
  return core::ConfigNode::parseString("type: " + options.controller, "--controller " + options.controller);
}

bench::EpisodeConfig validatedEpisodeConfig(const core::ConfigNode& node, const std::string& where) {
  bench::EpisodeConfig config = core::readConfig<bench::EpisodeConfig>(node);
  core::Errors errors(where);
  bench::validate(config, errors);
  errors.throwIfAny();
  return config;
}

void parseShard(const std::string& text, int& index, int& count) {
  const auto slash = text.find('/');
  const auto fail = [&] {
    throw core::InputError("--shard '" + text + "': expected K/N with 1 <= K <= N (e.g. 2/8)");
  };
  if (slash == std::string::npos) fail();
  try {
    std::size_t used_k = 0, used_n = 0;
    index = std::stoi(text.substr(0, slash), &used_k);
    count = std::stoi(text.substr(slash + 1), &used_n);
    if (used_k != slash || used_n != text.size() - slash - 1) fail();
  } catch (const std::logic_error&) {
    fail();
  }
  if (count < 1 || index < 1 || index > count) fail();
}

// Everything a session needs to run (part of) a record.
struct Session {
  fs::path dir;
  bench::RunManifest manifest;
  std::vector<core::WorldSpec> worlds;
  bench::BatchSpec spec;
  std::vector<bench::EpisodeResult> previous;  // finished in earlier sessions (resume)
};

Session freshSession(const RunOptions& options) {
  Session session;
  // Everything is read and validated before the first episode.
  const core::ConfigNode controller_node = controllerConfig(options);
  session.spec.make_controller = controllers::makeControllerFactory(controller_node);
  const fs::path sim_file = options.sim_config.empty() ? repoPath("configs") / "sim" / "barn.yaml" : fs::path(options.sim_config);
  core::ConfigNode sim_node = core::ConfigNode::parseFile(sim_file);
  if (!options.protocol.empty()) sim_node.set("protocol", options.protocol);
  session.spec.episode = validatedEpisodeConfig(sim_node, sim_file.string());
  int shard_index = 0, shard_count = 0;
  if (!options.shard.empty()) parseShard(options.shard, shard_index, shard_count);
  bench::LoadedWorlds loaded = bench::loadWorlds(options.worlds, repoPath("worlds"), options.keep_going);
  for (const auto& message : loaded.skipped) std::fprintf(stderr, "skipped (--keep-going): %s\n", message.c_str());

  session.dir = options.out.empty() ? repoPath("results") / options.controller : fs::path(options.out);
  if (!options.shard.empty() && options.out.empty())
    session.dir += "_shard" + std::to_string(shard_index) + "of" + std::to_string(shard_count);
  if (fs::exists(session.dir / bench::kManifestFile))
    throw core::InputError(session.dir.string() + ": already holds a run; finish it with --resume " +
                           session.dir.string() + " or choose another --out");

  bench::RunManifest& m = session.manifest;
  m.controller = options.controller;
  m.controller_config = controllers::effectiveControllerConfig(controller_node);
  m.episode_config = core::writeConfig(session.spec.episode);
  m.worlds_spec = options.worlds;
  m.worlds_folder = loaded.folder.string();
  for (const auto& w : loaded.worlds) m.world_ids.push_back(w.id);
  m.worlds_digest = bench::worldsDigest(loaded.worlds);
  m.trials = options.trials;
  m.seed = options.seed;
  m.shard_index = shard_index;
  m.shard_count = shard_count;
  session.worlds = std::move(loaded.worlds);
  return session;
}

Session resumedSession(const RunOptions& options) {
  Session session;
  session.dir = options.resume;
  session.manifest = bench::readManifest(session.dir / bench::kManifestFile);
  const bench::RunManifest& m = session.manifest;
  session.spec.make_controller =
      controllers::makeControllerFactory(core::ConfigNode::parseString(m.controller_config, "manifest controller_config"));
  session.spec.episode = validatedEpisodeConfig(core::ConfigNode::parseString(m.episode_config, "manifest episode_config"),
                                                (session.dir / bench::kManifestFile).string());
  session.worlds = bench::loadManifestWorlds(m);
  if (!m.complete) {
    session.previous = bench::readEpisodesCsv(session.dir / bench::kJournalFile, true);
  }
  return session;
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

void printRecordSummary(const fs::path& dir, const bench::RunManifest& m, const std::vector<core::WorldSpec>& worlds) {
  const std::vector<bench::EpisodeResult> results = bench::readEpisodesCsv(dir / bench::kEpisodesFile);
  const bench::RunSummary summary = bench::summarise(results);
  const std::string protocol =
      core::readConfig<bench::EpisodeConfig>(core::ConfigNode::parseString(m.episode_config, "manifest")).protocol;
  std::printf("%s", bench::summaryTable(summary, m.controller + " on " + m.worlds_spec + " x " + std::to_string(m.trials) +
                                                     " trials (" + protocol + ")").c_str());
  std::printf("%s", bench::breakdownTable(bench::difficultyBreakdown(results, worlds)).c_str());
}


// Runs what is left of the session's record and completes it; 0 complete, 1 interrupted or
// an episode ended in error.
int executeSession(Session& session, const SessionOptions& options) {
  bench::RunManifest& m = session.manifest;
  if (m.complete) {
    std::printf("%s is already complete\n", session.dir.c_str());
    printRecordSummary(session.dir, m, session.worlds);
    return 0;
  }
  session.spec.worlds = session.worlds;
  session.spec.trials = m.trials;
  session.spec.seed = m.seed;
  session.spec.jobs = options.jobs;
  session.spec.record_trajectories = options.trajectories;
  session.spec.selected = pendingEpisodes(session);
  const std::size_t total_of_record = session.previous.size() + session.spec.selected->size();
  const int threads = options.jobs > 0 ? options.jobs : static_cast<int>(std::max(1L, ::sysconf(_SC_NPROCESSORS_ONLN)));

  m.barnbench_version = BARN_VERSION;
  m.git_commit = gitCommit();
  m.host = hostName();
  m.threads = threads;
  if (m.started.empty()) m.started = utcNow();
  m.episodes_total = total_of_record;
  m.episodes_done = session.previous.size();
  // The journal is rewritten from the rows that survived (an interrupted write may have left
  // half a line), then appended to as episodes finish.
  std::string journal = bench::episodesCsvHeader();
  for (const auto& r : session.previous) journal += bench::episodeCsvRow(r);
  core::writeFilesAtomic(session.dir, {{bench::kManifestFile, bench::formatManifest(m)}, {bench::kJournalFile, journal}});
  std::ofstream journal_out(session.dir / bench::kJournalFile, std::ios::app | std::ios::binary);

  std::printf("running %s: %zu worlds x %d trials = %zu episodes%s on %d threads -> %s\n", m.controller.c_str(),
              session.worlds.size(), m.trials, total_of_record,
              m.shard_count ? (" (shard " + std::to_string(m.shard_index) + "/" + std::to_string(m.shard_count) + ")").c_str() : "",
              threads, session.dir.c_str());
  if (!session.previous.empty()) std::printf("resuming: %zu episodes already finished\n", session.previous.size());
  std::fflush(stdout);

  g_interrupted.store(false);
  std::signal(SIGINT, onInterrupt);
  std::signal(SIGTERM, onInterrupt);  // Slurm's time limit and preemption
  ProgressReporter progress(total_of_record, session.previous.size(), ::isatty(STDOUT_FILENO));
  std::vector<core::FileContent> trajectories;
  const auto t0 = std::chrono::steady_clock::now();
  session.spec.stop = &g_interrupted;
  std::size_t finished_here = 0;
  std::vector<bench::EpisodeResult> results =
      bench::runBatch(session.spec, [&](const bench::EpisodeResult& r, std::size_t, std::size_t) {
        journal_out << bench::episodeCsvRow(r);
        journal_out.flush();
        if (options.trajectories)
          trajectories.push_back({"world_" + std::to_string(r.world_id) + "_trial_" + std::to_string(r.trial) + ".csv",
                                  bench::trajectoryCsv(r)});
        progress.update(r.outcome == bench::Outcome::Success, r.sim_time);
        if (options.stop_after > 0 && ++finished_here >= options.stop_after) g_interrupted.store(true);
      });
  progress.finish();
  std::signal(SIGINT, SIG_DFL);
  std::signal(SIGTERM, SIG_DFL);
  journal_out.close();
  const double wall = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
  m.wall_time_s += wall;
  double sim_time_here = 0.0;
  for (const auto& r : results) sim_time_here += r.sim_time;
  if (options.trajectories) core::writeFilesAtomic(session.dir / "trajectories", trajectories);

  results.insert(results.end(), session.previous.begin(), session.previous.end());
  if (results.size() < total_of_record) {
    m.episodes_done = results.size();
    core::writeFileAtomic(session.dir / bench::kManifestFile, bench::formatManifest(m));
    std::printf("interrupted: %zu of %zu episodes finished and kept; finish with: barn run --resume %s\n",
                results.size(), total_of_record, session.dir.c_str());
    return 1;
  }
  bench::writeCompleteRecord(session.dir, m, results, session.worlds);
  printRecordSummary(session.dir, m, session.worlds);
  std::printf("  performance: wall %.2f s, simulated %.1f s, %.0f simulated s per wall s (%.0f per core, %d threads)\n",
              wall, sim_time_here, sim_time_here / wall, sim_time_here / wall / threads, threads);
  std::printf("wrote %s\n", session.dir.c_str());
  for (const auto& r : results)
    if (r.outcome == bench::Outcome::Error) return 1;
  return 0;
}

int runRecordFolder(const fs::path& dir, const SessionOptions& options) {
  RunOptions resume;
  resume.resume = dir.string();
  Session session = resumedSession(resume);
  return executeSession(session, options);
}

void addRunCommand(CLI::App& app, CommandContext& context) {
  auto options = std::make_shared<RunOptions>();
  CLI::App* cmd = app.add_subcommand("run", "Run a controller on worlds x trials in parallel and score it as BARN does");
  cmd->add_option("--controller", options->controller, "Controller: a name in configs/controllers/ or a type");
  cmd->add_option("--config", options->config, "Controller config file (default configs/controllers/NAME.yaml)");
  cmd->add_option("--sim-config", options->sim_config,
                  "Robot, LiDAR, physics and protocol config (default configs/sim/barn.yaml)");
  cmd->add_option("--worlds", options->worlds, "all, test50, A:B[:STEP], 3,7,9, or a folder of world files")
      ->capture_default_str();
  cmd->add_option("--trials", options->trials, "Trials per world")->check(CLI::Range(1, 100000))->capture_default_str();
  cmd->add_option("--protocol", options->protocol, "barn2023 or barn2024 (overrides the sim config)");
  cmd->add_option("--jobs", options->jobs, "Threads (0 = all cores)")->check(CLI::Range(0, 4096))->capture_default_str();
  cmd->add_option("--seed", options->seed, "Run seed (LiDAR noise and controller randomness)")->capture_default_str();
  cmd->add_option("--out", options->out, "Record folder (default results/<controller>)");
  cmd->add_option("--shard", options->shard, "Run shard K of N (every N-th episode from K); combine with barn merge");
  cmd->add_option("--resume", options->resume, "Finish the interrupted run in this record folder");
  cmd->add_flag("--keep-going", options->keep_going, "Skip world files that fail to load (reported) instead of stopping");
  cmd->add_option("--stop-after", options->stop_after,
                  "Stop after this many episodes, as Ctrl-C would (to try out --resume)");
  cmd->add_flag("--trajectories", options->trajectories,
                "Also write trajectories/world_N_trial_T.csv (pose, command and state per control tick)");
  cmd->callback([options, &context] {
    if (options->resume.empty() && options->controller.empty())
      throw core::InputError("run: --controller is required (or --resume DIR)");
    if (!options->resume.empty() && (!options->controller.empty() || !options->config.empty() ||
                                     !options->shard.empty() || !options->out.empty()))
      throw core::InputError("run: --resume takes its settings from the record; give only --jobs (and --stop-after) with it");
    Session session = options->resume.empty() ? freshSession(*options) : resumedSession(*options);
    SessionOptions session_options;
    session_options.jobs = options->jobs;
    session_options.trajectories = options->trajectories;
    session_options.stop_after = options->stop_after;
    context.exit_code = executeSession(session, session_options);
  });
}

}  // namespace barn::cli
