// barn sweep: a controller over the Cartesian grid of config overrides, every cell a full run
// record, all episodes of all cells in one parallel pool; sweep.csv and its figures.

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <filesystem>
#include <map>

#include "barn/bench/report.hpp"
#include "barn/bench/record_session.hpp"
#include "barn/bench/results_io.hpp"
#include "barn/bench/sweep_grid.hpp"
#include "barn/controllers/registry.hpp"
#include "barn/core/config.hpp"
#include "barn/core/errors.hpp"
#include "barn/core/text_io.hpp"
#include "commands.hpp"
#include "repo_paths.hpp"
#include "run_session.hpp"
#include "barn/report/sweep_plots.hpp"

namespace barn::cli {

namespace {

namespace fs = std::filesystem;

struct SweepOptions : ExperimentOptions {
  std::vector<std::string> params;
  std::string out;
  std::string resume;
  std::string shard;
  std::vector<std::string> merge;
  bool check = false;
  std::size_t stop_after = 0;
  std::string figures = "png";
};

// InputError naming the --param whose key is not in the controller's effective config, or
// that sets the same setting as another under another name ("speed", "pure_pursuit.speed").
void checkSweepKeys(const bench::SweepGrid& grid, const core::ConfigNode& base) {
  std::string type;
  base.child("type").read(type);
  const core::ConfigNode effective =
      core::ConfigNode::parseString(controllers::effectiveControllerConfig(base), "effective " + type + " config");
  std::map<std::string, std::string> given;  // setting -> the --param key that named it
  for (const auto& p : grid.parameters) {
    const std::string path = p.key.rfind(type + ".", 0) == 0 ? p.key : type + "." + p.key;
    if (const auto [at, fresh] = given.emplace(path, p.key); !fresh)
      throw core::InputError("--param " + p.key + ": the same setting (" + path + ") as --param " + at->second +
                             "; list every value in one --param");
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

namespace {

/// A sweep about to run: its grid, folder (locked) and one session per cell.
struct SweepSessions {
  bench::SweepGrid grid;
  fs::path dir;
  bench::RecordWriter writer;  // the sweep folder's lock: one process writes a sweep at a time
  std::vector<Session> sessions;
};

void checkNoSweep(const fs::path& dir) {
  std::error_code ec;
  if (fs::exists(dir / bench::kSweepFile, ec) || fs::exists(dir / core::kCommitNote, ec))
    throw core::InputError(dir.string() + ": already holds a sweep; finish it with --resume or choose another --out");
}

/// sweep --merge: every cell merged from its shards, all of them and sweep.yaml written as one
/// set, then run (a no-op) as a complete sweep.
SweepSessions mergedSweep(const SweepOptions& options) {
  if (options.out.empty()) throw core::InputError("sweep --merge: --out is required");
  SweepSessions sweep;
  sweep.dir = options.out;
  checkOutFolder(sweep.dir, "--out");
  checkNoSweep(sweep.dir);
  sweep.grid = bench::readSweepFile(options.merge.front());
  for (std::size_t k = 1; k < options.merge.size(); ++k)
    if (bench::readSweepFile(options.merge[k]).cells != sweep.grid.cells)
      throw core::InputError(options.merge[k] + ": a shard of another sweep than " + options.merge.front() +
                             " (other cells)");
  std::vector<core::FileContent> files = {{bench::kSweepFile, bench::formatSweepFile(sweep.grid)}};
  for (const auto& name : sweep.grid.cells) {
    std::vector<fs::path> parts;
    for (const auto& shard_dir : options.merge) parts.push_back(fs::path(shard_dir) / name);
    for (core::FileContent& file : bench::mergedShardRecords(parts, sweep.dir / name).files)
      files.push_back({name + "/" + file.name, std::move(file.content)});
  }
  sweep.writer = bench::RecordWriter(sweep.dir);
  checkNoSweep(sweep.dir);  // again under the lock
  sweep.writer.write(files);
  for (const auto& name : sweep.grid.cells) sweep.sessions.push_back(resumedSession(sweep.dir / name));
  return sweep;
}

/// A new sweep (or one shard of it): every cell's config validated before anything runs.
SweepSessions newSweep(const SweepOptions& options, int shard_index, int shard_count) {
  if (options.controller.empty()) throw core::InputError("sweep: --controller is required (or --resume DIR)");
  if (options.params.empty()) throw core::InputError("sweep: give at least one --param KEY=V1,V2,...");
  std::vector<bench::SweepParameter> parameters;
  for (const auto& text : options.params) parameters.push_back(bench::parseSweepParameter(text));
  SweepSessions sweep;
  sweep.grid = bench::makeSweepGrid(options.controller, std::move(parameters));
  sweep.dir = options.out.empty() ? repoPath("results") / ("sweep_" + options.controller) : fs::path(options.out);
  if (!options.shard.empty() && options.out.empty())
    sweep.dir += "_shard" + std::to_string(shard_index) + "of" + std::to_string(shard_count);
  checkOutFolder(sweep.dir, "--out");
  checkNoSweep(sweep.dir);
  // A key the controller does not have is the --param's fault, not the config file's.
  const core::ConfigNode base = controllerConfigFor(options.controller, options.config);
  checkSweepKeys(sweep.grid, base);
  const bench::EpisodeConfig episode = episodeConfigFor(options.sim_config, options.protocol);
  const bench::LoadedWorlds loaded =
      bench::loadWorlds(options.worlds, options.world_dir.empty() ? repoPath("worlds") : fs::path(options.world_dir));
  // Every cell checked before any folder is made (a bad value in the last cell leaves nothing
  // behind), its problems blamed on the --param values that made it.
  for (std::size_t c = 0; c < sweep.grid.cells.size(); ++c) {
    try {
      sweep.sessions.push_back(newSession(options.controller, bench::cellConfig(sweep.grid, base, c), episode, loaded,
                                          options.worlds, options.trials, options.seed, shard_index, shard_count, {}));
    } catch (const core::InputError& e) {
      throw core::InputError("--param values of " + sweep.grid.cells[c] + ": " + e.what());
    }
  }
  if (options.check) return sweep;
  // Then the sweep: every cell's record created, and sweep.yaml with the cells' first manifests
  // written as one set, so a kill leaves a sweep that --resume finishes or none at all.
  sweep.writer = bench::RecordWriter(sweep.dir);
  checkNoSweep(sweep.dir);
  std::vector<core::FileContent> files = {{bench::kSweepFile, bench::formatSweepFile(sweep.grid)}};
  for (std::size_t c = 0; c < sweep.grid.cells.size(); ++c) {
    const fs::path cell = sweep.dir / sweep.grid.cells[c];
    bench::RecordSession& record = sweep.sessions[c].record;
    record = bench::createRecord(std::move(record.manifest), std::move(record.worlds), cell);
    files.push_back({sweep.grid.cells[c] + "/" + bench::kManifestFile, bench::formatManifest(record.manifest, cell)});
  }
  sweep.writer.write(files);
  return sweep;
}

/// sweep --resume DIR: every cell from its record.
SweepSessions resumedSweep(const fs::path& dir) {
  SweepSessions sweep;
  sweep.dir = dir;
  std::error_code ec;
  if (!fs::exists(dir / bench::kSweepFile, ec) && !fs::exists(dir / core::kCommitNote, ec))
    throw core::InputError(dir.string() + ": no sweep here (no " + bench::kSweepFile + ")");
  sweep.writer = bench::RecordWriter(dir);  // completes a write a kill interrupted
  sweep.grid = bench::readSweepFile(dir);
  for (const auto& name : sweep.grid.cells) sweep.sessions.push_back(resumedSession(dir / name));
  return sweep;
}

/// sweep.csv and the figures (axis units from the controller config's schema).
void writeSweepResults(const SweepSessions& sweep, const std::string& figures) {
  const report::SweepTable table = report::readSweepTable(sweep.dir);
  core::writeFileAtomic(sweep.dir / "sweep.csv", report::sweepCsv(table));
  std::printf("%s", report::sweepSummary(table).c_str());
  for (const auto& figure : report::writeSweepPlots(table, sweep.dir, "." + figures)) std::printf("wrote %s\n", figure.c_str());
  std::printf("wrote %s\n", (sweep.dir / "sweep.csv").c_str());
}

}  // namespace

void addSweepCommand(CLI::App& app, CommandContext& context) {
  auto options = std::make_shared<SweepOptions>();
  CLI::App* cmd = app.add_subcommand("sweep", "Run a controller over a grid of config values, all cells in one pool");
  options->worlds = "test50";  // a sweep runs every cell: a smaller default set than barn run's
  addExperimentOptions(cmd, *options);
  cmd->add_option("--param", options->params,
                  "KEY=V1,V2,... (repeatable): a controller config key, relative to its type block, and its values");
  cmd->add_option("--out", options->out, "Sweep folder (default results/sweep_<controller>)");
  cmd->add_option("--resume", options->resume, "Finish an interrupted sweep in this folder");
  cmd->add_option("--stop-after", options->stop_after, "Stop after this many episodes, as Ctrl-C would")->check(kUnsigned);
  cmd->add_option("--shard", options->shard, "Run shard K of N of every cell (combine with --merge)");
  cmd->add_option("--merge", options->merge, "Combine these shard sweep folders into --out");
  cmd->add_option("--figures", options->figures,
                  "Format of the figures: heat maps (two keys: score from 0 to the protocol's maximum, success and "
                  "collision rate from 0 to 1) or line plots with 95 % bootstrap intervals over worlds (one key)")
      ->check(CLI::IsMember({"png", "pdf", "svg"}))
      ->capture_default_str();
  cmd->add_flag("--check", options->check,
                "Read and check everything the sweep needs (configs of every cell, worlds, --out), then exit without "
                "running or writing anything");
  cmd->callback([options, &context, cmd] {
    if (!options->resume.empty() || !options->merge.empty()) {
      for (const char* option : {"--controller", "--config", "--sim-config", "--param", "--worlds", "--world-dir",
                                 "--trials", "--protocol", "--seed", "--shard", "--check"})
        if (cmd->count(option) > 0)
          throw core::InputError(std::string("sweep: ") + option + ": " +
                                 (options->merge.empty() ? "--resume" : "--merge") +
                                 " takes the settings from the sweep; give only --jobs, --stop-after and --figures");
      if (!options->resume.empty() && cmd->count("--out") > 0)
        throw core::InputError("sweep: --out: --resume finishes the sweep in its own folder");
    }
    int shard_index = 0, shard_count = 0;
    if (!options->shard.empty()) parseShard(options->shard, shard_index, shard_count);
    SweepSessions sweep = !options->merge.empty()  ? mergedSweep(*options)
                          : options->resume.empty() ? newSweep(*options, shard_index, shard_count)
                                                    : resumedSweep(options->resume);
    if (options->check) {
      std::printf("check: %zu cells -> %s: ok (nothing run or written)\n", sweep.grid.cells.size(), sweep.dir.c_str());
      return;
    }
    std::vector<Session*> pointers;
    for (auto& s : sweep.sessions) pointers.push_back(&s);
    SessionOptions session;
    session.jobs = options->jobs;
    session.stop_after = options->stop_after;
    const int status = executeSessions(pointers, session, false);
    if (status != 0 && !std::all_of(sweep.sessions.begin(), sweep.sessions.end(), [](const Session& s) {
          return std::filesystem::exists(s.record.dir / bench::kEpisodesFile);
        })) {
      std::printf("interrupted: finish with: barn sweep --resume %s\n", sweep.dir.c_str());
      context.exit_code = 1;
      return;
    }
    if (!sweep.sessions.empty() && sweep.sessions.front().record.manifest.shard_count > 0) {
      const bench::RunManifest& m = sweep.sessions.front().record.manifest;
      std::printf("shard %d/%d of the sweep done; combine the shards with: barn sweep --merge DIR... --out DIR\n",
                  m.shard_index, m.shard_count);
      return;
    }
    writeSweepResults(sweep, options->figures);
    if (status != 0) context.exit_code = 1;
  });
}

}  // namespace barn::cli
