// barn sweep: a controller over the Cartesian grid of config overrides, every cell a full run
// record, all episodes of all cells in one parallel pool; sweep.csv and heat maps.

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <filesystem>
#include <sstream>

#include "barn/bench/report.hpp"
#include "barn/bench/results_io.hpp"
#include "barn/core/config.hpp"
#include "barn/core/errors.hpp"
#include "barn/core/text_io.hpp"
#include "commands.hpp"
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
};

// One swept parameter: a key of the controller config (relative to its type block) and values.
struct Parameter {
  std::string key;
  std::vector<std::string> values;
};

Parameter parseParameter(const std::string& text) {
  const auto eq = text.find('=');
  if (eq == std::string::npos || eq == 0 || eq + 1 == text.size())
    throw core::InputError("--param '" + text + "': expected KEY=V1,V2,...");
  Parameter p;
  p.key = text.substr(0, eq);
  std::stringstream values(text.substr(eq + 1));
  for (std::string v; std::getline(values, v, ',');) {
    if (v.empty()) throw core::InputError("--param '" + text + "': empty value");
    p.values.push_back(v);
  }
  return p;
}

std::string cellName(std::size_t index, const std::vector<Parameter>& params, const std::vector<std::size_t>& at) {
  std::string name = "cell_" + std::to_string(index);
  for (std::size_t k = 0; k < params.size(); ++k) name += "_" + params[k].key + "=" + params[k].values[at[k]];
  for (char& ch : name)
    if (ch == '/' || ch == ' ') ch = '_';
  return name;
}

// sweep.yaml: the grid, so --resume can find the cells again.
std::string formatSweepFile(const std::string& controller, const std::vector<Parameter>& params,
                            const std::vector<std::string>& cells) {
  std::string text = "# barnbench sweep: one run record per cell in the folders below\ncontroller: \"" + controller + "\"\nparameters:\n";
  for (const auto& p : params) {
    text += "  - key: \"" + p.key + "\"\n    values: [";
    for (std::size_t i = 0; i < p.values.size(); ++i) text += (i ? ", \"" : "\"") + p.values[i] + "\"";
    text += "]\n";
  }
  text += "cells:\n";
  for (const auto& c : cells) text += "  - \"" + c + "\"\n";
  return text;
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
  cmd->callback([options, &context] {
    std::vector<Parameter> params;
    std::vector<std::string> cell_names;
    fs::path dir;
    std::vector<Session> sessions;
    std::string controller = options->controller;
    int shard_index = 0, shard_count = 0;
    if (!options->shard.empty()) parseShard(options->shard, shard_index, shard_count);
    if (!options->merge.empty()) {
      // Every cell merged from its shards; then the table as for a single-machine sweep.
      if (options->out.empty()) throw core::InputError("sweep --merge: --out is required");
      dir = options->out;
      const core::ConfigNode sweep = core::ConfigNode::parseFile(fs::path(options->merge.front()) / "sweep.yaml");
      sweep.child("controller").read(controller);
      for (std::size_t i = 0;; ++i) {
        const core::ConfigNode item = sweep.child("parameters").element(i);
        if (item.isNull()) break;
        Parameter p;
        item.child("key").read(p.key);
        item.child("values").read(p.values);
        params.push_back(p);
      }
      for (std::size_t i = 0;; ++i) {
        std::string name;
        if (!sweep.child("cells").element(i).read(name)) break;
        cell_names.push_back(name);
        std::vector<std::string> parts;
        for (const auto& shard_dir : options->merge) parts.push_back((fs::path(shard_dir) / name).string());
        mergeRecords(parts, dir / name, false);
        sessions.push_back(resumedSession(dir / name));
      }
      core::writeFilesAtomic(dir, {{"sweep.yaml", formatSweepFile(controller, params, cell_names)}});
    } else if (options->resume.empty()) {
      if (options->controller.empty()) throw core::InputError("sweep: --controller is required (or --resume DIR)");
      if (options->params.empty()) throw core::InputError("sweep: give at least one --param KEY=V1,V2,...");
      for (const auto& text : options->params) {
        params.push_back(parseParameter(text));
        for (std::size_t k = 0; k + 1 < params.size(); ++k)
          if (params[k].key == params.back().key)
            throw core::InputError("--param " + params.back().key + ": given twice (list every value in one --param)");
      }
      dir = options->out.empty() ? repoPath("results") / ("sweep_" + options->controller) : fs::path(options->out);
      if (!options->shard.empty() && options->out.empty())
        dir += "_shard" + std::to_string(shard_index) + "of" + std::to_string(shard_count);
      if (fs::exists(dir / "sweep.yaml"))
        throw core::InputError(dir.string() + ": already holds a sweep; finish it with --resume or choose another --out");
      // Validate every cell's config before anything runs.
      const core::ConfigNode base = controllerConfigFor(options->controller, options->config);
      std::string type;
      base.child("type").read(type);
      const bench::EpisodeConfig episode = episodeConfigFor(options->sim_config, options->protocol);
      const bench::LoadedWorlds loaded =
          bench::loadWorlds(options->worlds, options->world_dir.empty() ? repoPath("worlds") : fs::path(options->world_dir));
      std::size_t cells = 1;
      for (const auto& p : params) cells *= p.values.size();
      if (cells > 10000) throw core::InputError("sweep: " + std::to_string(cells) + " cells is too many (at most 10000)");
      std::vector<std::size_t> at(params.size(), 0);
      for (std::size_t c = 0; c < cells; ++c) {
        core::ConfigNode node = core::ConfigNode::parseString(base.toYaml(), base.source().empty() ? "sweep" : base.source());
        for (std::size_t k = 0; k < params.size(); ++k) {
          const std::string& key = params[k].key;
          node.set(key.rfind(type + ".", 0) == 0 ? key : type + "." + key, params[k].values[at[k]]);
        }
        cell_names.push_back(cellName(c, params, at));
        sessions.push_back(newSession(options->controller, node, episode, loaded, options->worlds, options->trials,
                                      options->seed, shard_index, shard_count, dir / cell_names.back()));
        for (std::size_t k = params.size(); k-- > 0;) {  // odometer, last parameter fastest
          if (++at[k] < params[k].values.size()) break;
          at[k] = 0;
        }
      }
      core::writeFilesAtomic(dir, {{"sweep.yaml", formatSweepFile(options->controller, params, cell_names)}});
    } else {
      dir = options->resume;
      const core::ConfigNode sweep = core::ConfigNode::parseFile(dir / "sweep.yaml");
      sweep.child("controller").read(controller);
      const core::ConfigNode list = sweep.child("parameters");
      for (std::size_t i = 0;; ++i) {
        const core::ConfigNode item = list.element(i);
        if (item.isNull()) break;
        Parameter p;
        item.child("key").read(p.key);
        item.child("values").read(p.values);
        params.push_back(p);
      }
      const core::ConfigNode cells = sweep.child("cells");
      for (std::size_t i = 0;; ++i) {
        std::string name;
        if (!cells.element(i).read(name)) break;
        cell_names.push_back(name);
        sessions.push_back(resumedSession(dir / name));
      }
    }
    std::vector<Session*> pointers;
    for (auto& s : sessions) pointers.push_back(&s);
    SessionOptions session;
    session.jobs = options->jobs;
    session.stop_after = options->stop_after;
    const int status = executeSessions(pointers, session, false);
    if (status != 0 && !std::all_of(sessions.begin(), sessions.end(), [](const Session& s) {
          return std::filesystem::exists(s.dir / bench::kEpisodesFile);
        })) {
      std::printf("interrupted: finish with: barn sweep --resume %s\n", dir.c_str());
      context.exit_code = 1;
      return;
    }
    if (!sessions.empty() && sessions.front().manifest.shard_count > 0) {
      std::printf("shard %d/%d of the sweep done; combine the shards with: barn sweep --merge DIR... --out DIR\n",
                  sessions.front().manifest.shard_index, sessions.front().manifest.shard_count);
      return;
    }
    // sweep.csv and the heat maps.
    SweepTable table;
    table.controller = controller;
    for (const auto& p : params) table.keys.push_back(p.key);
    for (std::size_t c = 0; c < sessions.size(); ++c) {
      SweepCell cell;
      cell.name = cell_names[c];
      std::size_t rest = c;
      cell.values.resize(params.size());
      for (std::size_t k = params.size(); k-- > 0;) {
        cell.values[k] = params[k].values[rest % params[k].values.size()];
        rest /= params[k].values.size();
      }
      cell.summary = bench::summarise(bench::readEpisodesCsv(sessions[c].dir / bench::kEpisodesFile));
      table.cells.push_back(cell);
    }
    core::writeFileAtomic(dir / "sweep.csv", sweepCsv(table));
    std::printf("%s", sweepSummary(table).c_str());
    for (const auto& png : writeSweepPlots(table, dir)) std::printf("wrote %s\n", png.c_str());
    std::printf("wrote %s\n", (dir / "sweep.csv").c_str());
    if (status != 0) context.exit_code = 1;
  });
}

}  // namespace barn::cli
