// barn run: every (world, trial) episode of a controller in parallel, scored as BARN does,
// written as an experiment record (see bench/run_record.hpp). Interruptible and resumable;
// shardable across machines (barn merge puts the shards together).

#include <algorithm>
#include <cctype>
#include <cstdio>  // renameat2 (GNU)
#include <fcntl.h>
#include <filesystem>
#include <string>
#include <vector>

#include "barn/bench/controller_lookup.hpp"
#include "barn/bench/record_session.hpp"
#include "barn/controllers/registry.hpp"
#include "barn/core/config.hpp"
#include "barn/core/protocol.hpp"
#include "barn/core/errors.hpp"
#include "commands.hpp"
#include "repo_paths.hpp"
#include "run_session.hpp"

namespace barn::cli {

namespace {

namespace fs = std::filesystem;

struct RunOptions : ExperimentOptions {
  std::string out;
  std::string shard;
  std::string resume;
  bool keep_going = false;
  bool force = false;
  bool trajectories = false;
  bool check = false;
  std::size_t stop_after = 0;  // 0 = never
};

// UTC now as YYYYmmdd-HHMMSS, for a folder name.
std::string timestamp() {
  std::string iso = bench::utcNow();  // 2026-11-23T01:52:10Z
  std::string out;
  for (char ch : iso)
    if (std::isdigit(static_cast<unsigned char>(ch))) out += ch;
  return out.substr(0, 8) + "-" + out.substr(8, 6);
}

// --force: the new record (complete) takes the old one's place; an interrupted one stays
// beside it, to resume, and the old record is untouched.
void replaceRecord(Session& session, const fs::path& old_dir) {
  const fs::path& new_dir = session.record.dir;
  if (!session.record.manifest.complete) {
    std::printf("--force: %s is untouched; the new run is in %s (finish it with barn run --resume %s, then move it)\n",
                old_dir.c_str(), new_dir.c_str(), new_dir.c_str());
    return;
  }
  // One atomic exchange of the two folders (Linux renameat2), so OUT always holds a complete
  // record; where the file system cannot exchange, two renames.
  std::error_code ec;
  if (::renameat2(AT_FDCWD, new_dir.c_str(), AT_FDCWD, old_dir.c_str(), RENAME_EXCHANGE) == 0) {
    fs::remove_all(new_dir, ec);  // now the old record
  } else {
    const fs::path trash = old_dir.string() + ".old";
    fs::remove_all(trash, ec);
    fs::rename(old_dir, trash, ec);
    if (ec) throw core::IoError(old_dir.string() + ": cannot move aside: " + ec.message() + " (the new record is in " + new_dir.string() + ")");
    fs::rename(new_dir, old_dir, ec);
    if (ec) throw core::IoError(new_dir.string() + ": cannot move to " + old_dir.string() + ": " + ec.message() + " (the old record is in " + trash.string() + ")");
    fs::remove_all(trash, ec);
  }
  std::printf("replaced %s\n", old_dir.c_str());
}

}  // namespace

void checkOutFolder(const fs::path& dir, const std::string& option) {
  std::error_code ec;
  const fs::file_status status = fs::status(dir, ec);
  if (fs::exists(status) && !fs::is_directory(status))
    throw core::InputError(option + " " + dir.string() + ": is a file, expected a folder");
  if (!fs::exists(status) && fs::is_symlink(fs::symlink_status(dir, ec)))
    throw core::InputError(option + " " + dir.string() + ": is a symlink to a missing folder (" +
                           fs::read_symlink(dir, ec).string() + ")");
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

fs::path controllerConfigFile(const std::string& controller, const std::string& config_file) {
  return bench::controllerConfigFile(controller, config_file, repoPath("configs") / "controllers");
}

core::ConfigNode controllerConfigFor(const std::string& controller, const std::string& config_file) {
  return bench::controllerConfigNode(controller, config_file, repoPath("configs") / "controllers");
}

void addExperimentOptions(CLI::App* cmd, ExperimentOptions& options) {
  cmd->add_option("--controller", options.controller, "Controller: a name in configs/controllers/ or a type");
  cmd->add_option("--config", options.config, "Controller config file (default configs/controllers/NAME.yaml)");
  cmd->add_option("--sim-config", options.sim_config,
                  "Robot, LiDAR, physics and protocol config (default configs/sim/barn.yaml)");
  cmd->add_option("--worlds", options.worlds, "all, test50, A:B[:STEP], 3,7,9, or a folder of world files")
      ->capture_default_str();
  cmd->add_option("--world-dir", options.world_dir,
                  "Folder the ids of --worlds refer to (default worlds/; e.g. one written by barn import-barn)");
  cmd->add_option("--trials", options.trials, "Trials per world")->check(CLI::Range(1, 100000))->capture_default_str();
  cmd->add_option("--protocol", options.protocol, "barn2023 or barn2024 (overrides the sim config)");
  cmd->add_option("--jobs", options.jobs, "Threads (0 = all cores)")->check(CLI::Range(0, 4096))->capture_default_str();
  cmd->add_option("--seed", options.seed, "Run seed (LiDAR noise and controller randomness)")->capture_default_str()->check(kUnsigned);
}

bench::EpisodeConfig episodeConfigFor(const std::string& sim_config, const std::string& protocol) {
  if (!protocol.empty()) {
    const std::vector<std::string> known = core::protocolNames();
    if (std::find(known.begin(), known.end(), protocol) == known.end()) {
      std::string list;
      for (const auto& name : known) list += (list.empty() ? "" : ", ") + name;
      throw core::InputError("--protocol " + protocol + ": unknown (known: " + list + ")");
    }
  }
  const fs::path sim_file = sim_config.empty() ? repoPath("configs") / "sim" / "barn.yaml" : fs::path(sim_config);
  core::ConfigNode sim_node = core::ConfigNode::parseFile(sim_file);
  if (!protocol.empty()) sim_node.set("protocol", protocol);
  return bench::validatedEpisodeConfig(sim_node, sim_file.string());
}

void addRunCommand(CLI::App& app, CommandContext& context) {
  auto options = std::make_shared<RunOptions>();
  CLI::App* cmd = app.add_subcommand("run", "Run a controller on worlds x trials in parallel and score it as BARN does");
  addExperimentOptions(cmd, *options);
  cmd->add_option("--out", options->out, "Record folder (default results/<controller>)");
  cmd->add_option("--shard", options->shard, "Run shard K of N (every N-th episode from K); combine with barn merge");
  cmd->add_option("--resume", options->resume, "Finish the interrupted run in this record folder");
  cmd->add_flag("--keep-going", options->keep_going, "Skip world files that fail to load (reported) instead of stopping");
  cmd->add_option("--stop-after", options->stop_after,
                  "Stop after this many episodes, as Ctrl-C would (to try out --resume)")
      ->check(kUnsigned);
  cmd->add_flag("--trajectories", options->trajectories,
                "Also write trajectories/world_N_trial_T.csv (pose, command and state per control tick)");
  cmd->add_flag("--force", options->force,
                "Replace the complete record in --out, once the new run is complete (until then the old one stays)");
  cmd->add_flag("--check", options->check,
                "Read and check everything a run needs (configs, worlds, --out) as it would, then exit without "
                "running or writing anything (0: it would start)");
  cmd->callback([options, &context, cmd] {
    fs::path replaced;                  // with --force: the record the new one replaces
    bench::RecordWriter replaced_lock;  // ... held, locked, for the whole run and the exchange
    if (options->resume.empty() && options->controller.empty())
      throw core::InputError("run: --controller is required (or --resume DIR)");
    if (!options->resume.empty()) {
      for (const char* option : {"--controller", "--config", "--sim-config", "--worlds", "--world-dir", "--trials",
                                 "--protocol", "--seed", "--out", "--shard", "--keep-going", "--force", "--check"})
        if (cmd->count(option) > 0)
          throw core::InputError(std::string("run: ") + option +
                                 ": --resume takes its settings from the record; give only --jobs (and --stop-after) "
                                 "with it");
    }
    if (options->force && options->out.empty()) throw core::InputError("--force: replaces the record in --out; give --out");
    Session session;
    if (options->resume.empty()) {
      // Everything is read and validated before the first episode.
      const core::ConfigNode controller_node = controllerConfigFor(options->controller, options->config);
      const bench::EpisodeConfig episode = episodeConfigFor(options->sim_config, options->protocol);
      int shard_index = 0, shard_count = 0;
      if (!options->shard.empty()) parseShard(options->shard, shard_index, shard_count);
      const bench::LoadedWorlds loaded = bench::loadWorlds(
          options->worlds, options->world_dir.empty() ? repoPath("worlds") : fs::path(options->world_dir), options->keep_going);
      for (const auto& message : loaded.skipped) std::fprintf(stderr, "skipped (--keep-going): %s\n", message.c_str());
      fs::path dir = options->out.empty() ? repoPath("results") / options->controller : fs::path(options->out);
      if (!options->shard.empty() && options->out.empty())
        dir += "_shard" + std::to_string(shard_index) + "of" + std::to_string(shard_count);
      // The default folder is taken: a new one beside it, never someone's earlier results.
      if (options->out.empty() && fs::exists(dir / bench::kManifestFile)) dir += "_" + timestamp();
      checkOutFolder(dir, "--out");
      if (options->force && fs::exists(dir / bench::kManifestFile)) {
        // The old record stays locked until the new one has taken its place: a process still
        // writing it makes --force fail here, and none can start on it meanwhile.
        if (!options->check) replaced_lock = bench::RecordWriter(dir);
        const bench::RunManifest old = bench::readManifest(dir / bench::kManifestFile);
        if (!old.complete)
          throw core::InputError("--force: " + dir.string() + " holds an unfinished run (" +
                                 std::to_string(old.episodes_done) + " of " + std::to_string(old.episodes_total) +
                                 " episodes), which --force does not replace: finish it with barn run --resume " +
                                 dir.string() + ", or remove the folder yourself");
        replaced = dir;
        dir += ".new";
      }
      if (options->check) bench::checkNoRecord(dir);
      session = newSession(options->controller, controller_node, episode, loaded, options->worlds, options->trials,
                           options->seed, shard_index, shard_count, options->check ? fs::path() : dir);
      if (options->check) {
        std::printf("check: %s on %zu worlds x %d trials -> %s: ok (nothing run or written)\n",
                    options->controller.c_str(), loaded.worlds.size(), options->trials, dir.c_str());
        return;
      }
      session.record.manifest.trajectories = options->trajectories;
    } else {
      session = resumedSession(options->resume);
      // The record says whether it keeps trajectories; asking again is harmless, asking for
      // them midway is not possible (its earlier episodes have none).
      if (options->trajectories && !session.record.manifest.trajectories)
        throw core::InputError("--trajectories: " + options->resume +
                               " was started without trajectories, so its finished episodes have none; start the run "
                               "again with --trajectories, or resume it without");
    }
    SessionOptions session_options;
    session_options.jobs = options->jobs;
    session_options.stop_after = options->stop_after;
    context.exit_code = executeSessions({&session}, session_options, true);
    if (!replaced.empty()) replaceRecord(session, replaced);
  });
}

}  // namespace barn::cli
