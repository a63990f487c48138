// barn sweep: a controller over the Cartesian grid of config overrides, every cell a full run
// record, all episodes of all cells in one parallel pool; sweep.csv and its figures.

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <filesystem>

#include "barn/bench/report.hpp"
#include "barn/bench/record_session.hpp"
#include "barn/bench/results_io.hpp"
#include "barn/bench/sweep_grid.hpp"
#include "barn/controllers/registry.hpp"
#include "barn/core/config.hpp"
#include "barn/core/errors.hpp"
#include "barn/core/text_io.hpp"
#include "commands.hpp"
#include "config_units.hpp"
#include "repo_paths.hpp"
#include "run_session.hpp"
#include "sweep_plots.hpp"

namespace barn::cli {

namespace {

namespace fs = std::filesystem;

struct SweepOptions {
  std::string controller;
  std::string config;
  std::string sim_config;
  std::vector<std::string> params;
  std::string worlds = "test50";
  std::string world_dir;
  int trials = 1;
  std::string protocol;
  int jobs = 0;
  std::uint64_t seed = 0;
  std::string out;
  std::string resume;
  std::string shard;
  std::vector<std::string> merge;
  std::size_t stop_after = 0;
  std::string figures = "png";
};

// InputError naming the --param whose key is not in the controller's effective config.
void checkSweepKeys(const bench::SweepGrid& grid, const core::ConfigNode& base) {
  std::string type;
  base.child("type").read(type);
  const core::ConfigNode effective =
      core::ConfigNode::parseString(controllers::effectiveControllerConfig(base), "effective " + type + " config");
  for (const auto& p : grid.parameters) {
    const std::string path = p.key.rfind(type + ".", 0) == 0 ? p.key : type + "." + p.key;
    core::ConfigNode node = effective;
    for (std::size_t begin = 0; begin <= path.size() && !node.isNull();) {
      const std::size_t dot = std::min(path.find('.', begin), path.size());
      node = node.child(path.substr(begin, dot - begin));
      begin = dot + 1;
    }
    if (node.isNull())
      throw core::InputError("--param " + p.key + ": " + type + " has no setting " + path +
                             " (barn config RECORD or configs/controllers/ list them)");
  }
}

}  // namespace

void addSweepCommand(CLI::App& app, CommandContext& context) {
  auto options = std::make_shared<SweepOptions>();
  CLI::App* cmd = app.add_subcommand("sweep", "Run a controller over a grid of config values, all cells in one pool");
  cmd->add_option("--controller", options->controller, "Controller: a name in configs/controllers/ or a type");
  cmd->add_option("--config", options->config, "Controller config file (default configs/controllers/NAME.yaml)");
  cmd->add_option("--sim-config", options->sim_config, "Simulation config (default configs/sim/barn.yaml)");
  cmd->add_option("--param", options->params,
                  "KEY=V1,V2,... (repeatable): a controller config key, relative to its type block, and its values");
  cmd->add_option("--worlds", options->worlds, "all, test50, A:B[:STEP], 3,7,9 or a folder")->capture_default_str();
  cmd->add_option("--world-dir", options->world_dir, "Folder the ids of --worlds refer to (default worlds/)");
  cmd->add_option("--trials", options->trials, "Trials per world")->check(CLI::Range(1, 100000))->capture_default_str();
  cmd->add_option("--protocol", options->protocol, "barn2023 or barn2024");
  cmd->add_option("--jobs", options->jobs, "Threads (0 = all cores)")->check(CLI::Range(0, 4096));
  cmd->add_option("--seed", options->seed, "Run seed")->capture_default_str()->check(kNotNegative);
  cmd->add_option("--out", options->out, "Sweep folder (default results/sweep_<controller>)");
  cmd->add_option("--resume", options->resume, "Finish an interrupted sweep in this folder");
  cmd->add_option("--stop-after", options->stop_after, "Stop after this many episodes, as Ctrl-C would");
  cmd->add_option("--shard", options->shard, "Run shard K of N of every cell (combine with --merge)");
  cmd->add_option("--merge", options->merge, "Combine these shard sweep folders into --out");
  cmd->add_option("--figures", options->figures,
                  "Format of the figures: heat maps (two keys: score from 0 to the protocol's maximum, success and "
                  "collision rate from 0 to 1) or line plots with 95 % bootstrap intervals over worlds (one key)")
      ->check(CLI::IsMember({"png", "pdf", "svg"}))
      ->capture_default_str();
  cmd->callback([options, &context] {
    bench::SweepGrid grid;
    fs::path dir;
    std::vector<Session> sessions;
    int shard_index = 0, shard_count = 0;
    if (!options->shard.empty()) parseShard(options->shard, shard_index, shard_count);
    if (!options->merge.empty()) {
      // Every cell merged from its shards; then the table as for a single-machine sweep.
      if (options->out.empty()) throw core::InputError("sweep --merge: --out is required");
      dir = options->out;
      grid = bench::readSweepFile(options->merge.front());
      for (const auto& name : grid.cells) {
        std::vector<fs::path> parts;
        for (const auto& shard_dir : options->merge) parts.push_back(fs::path(shard_dir) / name);
        bench::mergeShardRecords(parts, dir / name);
        sessions.push_back(resumedSession(dir / name));
      }
      core::writeFilesAtomic(dir, {{bench::kSweepFile, bench::formatSweepFile(grid)}});
    } else if (options->resume.empty()) {
      if (options->controller.empty()) throw core::InputError("sweep: --controller is required (or --resume DIR)");
      if (options->params.empty()) throw core::InputError("sweep: give at least one --param KEY=V1,V2,...");
      std::vector<bench::SweepParameter> parameters;
      for (const auto& text : options->params) parameters.push_back(bench::parseSweepParameter(text));
      grid = bench::makeSweepGrid(options->controller, std::move(parameters));
      dir = options->out.empty() ? repoPath("results") / ("sweep_" + options->controller) : fs::path(options->out);
      if (!options->shard.empty() && options->out.empty())
        dir += "_shard" + std::to_string(shard_index) + "of" + std::to_string(shard_count);
      if (fs::exists(dir / bench::kSweepFile))
        throw core::InputError(dir.string() + ": already holds a sweep; finish it with --resume or choose another --out");
      // Validate every cell's config before anything runs; a key the controller does not have
      // is the --param's fault, not the config file's.
      const core::ConfigNode base = controllerConfigFor(options->controller, options->config);
      checkSweepKeys(grid, base);
      const bench::EpisodeConfig episode = episodeConfigFor(options->sim_config, options->protocol);
      const bench::LoadedWorlds loaded =
          bench::loadWorlds(options->worlds, options->world_dir.empty() ? repoPath("worlds") : fs::path(options->world_dir));
      for (std::size_t c = 0; c < grid.cells.size(); ++c)
        sessions.push_back(newSession(options->controller, bench::cellConfig(grid, base, c), episode, loaded, options->worlds,
                                      options->trials, options->seed, shard_index, shard_count, dir / grid.cells[c]));
      core::writeFilesAtomic(dir, {{bench::kSweepFile, bench::formatSweepFile(grid)}});
    } else {
      dir = options->resume;
      grid = bench::readSweepFile(dir);
      for (const auto& name : grid.cells) sessions.push_back(resumedSession(dir / name));
    }
    std::vector<Session*> pointers;
    for (auto& s : sessions) pointers.push_back(&s);
    SessionOptions session;
    session.jobs = options->jobs;
    session.stop_after = options->stop_after;
    const int status = executeSessions(pointers, session, false);
    if (status != 0 && !std::all_of(sessions.begin(), sessions.end(), [](const Session& s) {
          return std::filesystem::exists(s.record.dir / bench::kEpisodesFile);
        })) {
      std::printf("interrupted: finish with: barn sweep --resume %s\n", dir.c_str());
      context.exit_code = 1;
      return;
    }
    if (!sessions.empty() && sessions.front().record.manifest.shard_count > 0) {
      const bench::RunManifest& m = sessions.front().record.manifest;
      std::printf("shard %d/%d of the sweep done; combine the shards with: barn sweep --merge DIR... --out DIR\n",
                  m.shard_index, m.shard_count);
      return;
    }
    // sweep.csv and the figures. Units come from the controller's config file (a resumed or
    // merged sweep reads the default one, configs/controllers/NAME.yaml).
    const SweepTable table = readSweepTable(dir, controllerConfigFile(grid.controller, options->config));
    core::writeFileAtomic(dir / "sweep.csv", sweepCsv(table));
    std::printf("%s", sweepSummary(table).c_str());
    for (const auto& figure : writeSweepPlots(table, dir, "." + options->figures))
      std::printf("wrote %s\n", figure.c_str());
    std::printf("wrote %s\n", (dir / "sweep.csv").c_str());
    if (status != 0) context.exit_code = 1;
  });
}

}  // namespace barn::cli
