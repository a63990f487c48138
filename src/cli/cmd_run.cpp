// barn run: every (world, trial) episode of a controller in parallel, scored as BARN does.

#include <chrono>
#include <cstdio>
#include <filesystem>
#include <unistd.h>

#include "barn/bench/batch.hpp"
#include "barn/bench/report.hpp"
#include "barn/bench/world_selection.hpp"
#include "barn/core/config.hpp"
#include "barn/core/text_io.hpp"
#include "commands.hpp"
#include "repo_paths.hpp"

namespace barn::cli {

namespace {

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
  bool trajectories = false;
};

// The controller config: --config FILE, else configs/controllers/NAME.yaml, else the type NAME
// with its defaults.
core::ConfigNode controllerConfig(const RunOptions& options) {
  if (!options.config.empty()) return core::ConfigNode::parseFile(options.config);
  const auto file = repoPath("configs") / "controllers" / (options.controller + ".yaml");
  if (std::filesystem::exists(file)) return core::ConfigNode::parseFile(file);
  return core::ConfigNode::parseString("type: " + options.controller, "--controller " + options.controller);
}

bench::EpisodeConfig episodeConfig(const RunOptions& options) {
  const std::filesystem::path file =
      options.sim_config.empty() ? repoPath("configs") / "sim" / "barn.yaml" : std::filesystem::path(options.sim_config);
  bench::EpisodeConfig config = core::readConfig<bench::EpisodeConfig>(core::ConfigNode::parseFile(file));
  if (!options.protocol.empty()) config.protocol = options.protocol;
  core::Errors errors(file.string());
  bench::validate(config, errors);
  errors.throwIfAny();
  return config;
}

}  // namespace

void addRunCommand(CLI::App& app, CommandContext& context) {
  auto options = std::make_shared<RunOptions>();
  CLI::App* cmd = app.add_subcommand("run", "Run a controller on worlds x trials in parallel and score it as BARN does");
  cmd->add_option("--controller", options->controller, "Controller: a name in configs/controllers/ or a type")->required();
  cmd->add_option("--config", options->config, "Controller config file (default configs/controllers/NAME.yaml)");
  cmd->add_option("--sim-config", options->sim_config, "Robot, LiDAR, physics and protocol config (default configs/sim/barn.yaml)");
  cmd->add_option("--worlds", options->worlds, "all, test50, A:B[:STEP], 3,7,9, or a folder of world files")
      ->capture_default_str();
  cmd->add_option("--trials", options->trials, "Trials per world")->check(CLI::Range(1, 100000))->capture_default_str();
  cmd->add_option("--protocol", options->protocol, "barn2023 (default in configs/sim/barn.yaml) or barn2024");
  cmd->add_option("--jobs", options->jobs, "Threads (0 = all cores)")->check(CLI::Range(0, 4096))->capture_default_str();
  cmd->add_option("--seed", options->seed, "Run seed (LiDAR noise and controller randomness)")->capture_default_str();
  cmd->add_option("--out", options->out, "Folder for episodes.csv (default results/<controller>)");
  cmd->add_flag("--trajectories", options->trajectories,
                "Also write trajectories/world_N_trial_T.csv (pose, command and state per control tick)");
  cmd->callback([options, &context] {
    // Everything is read and validated before the first episode.
    const core::ConfigNode controller_config = controllerConfig(*options);
    bench::BatchSpec spec;
    spec.make_controller = controllers::makeControllerFactory(controller_config);
    spec.episode = episodeConfig(*options);
    spec.worlds = bench::loadWorlds(options->worlds, repoPath("worlds"));
    spec.trials = options->trials;
    spec.jobs = options->jobs;
    spec.seed = options->seed;
    spec.record_trajectories = options->trajectories;
    const std::filesystem::path out = options->out.empty() ? repoPath("results") / options->controller : std::filesystem::path(options->out);

    const bool terminal = ::isatty(STDOUT_FILENO);
    const auto t0 = std::chrono::steady_clock::now();
    std::size_t successes = 0;
    const auto progress = [&](const bench::EpisodeResult& r, std::size_t done, std::size_t total) {
      successes += r.outcome == bench::Outcome::Success;
      const bool last = done == total;
      const std::size_t every = terminal ? 1 : std::max<std::size_t>(1, total / 10);
      if (!last && done % every != 0) return;
      const double elapsed = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
      const double eta = elapsed / static_cast<double>(done) * static_cast<double>(total - done);
      std::printf("%s[%zu/%zu] success %.1f%%  elapsed %.1f s  eta %.1f s%s", terminal ? "\r" : "", done, total,
                  100.0 * static_cast<double>(successes) / static_cast<double>(done), elapsed, eta,
                  terminal && !last ? "" : "\n");
      std::fflush(stdout);
    };
    const std::vector<bench::EpisodeResult> results = bench::runBatch(spec, progress);
    const double wall = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();

    core::writeFilesAtomic(out, {{"episodes.csv", bench::episodesCsv(results)}});
    if (options->trajectories) {
      std::vector<core::FileContent> files;
      for (const auto& r : results)
        files.push_back({"world_" + std::to_string(r.world_id) + "_trial_" + std::to_string(r.trial) + ".csv",
                         bench::trajectoryCsv(r)});
      core::writeFilesAtomic(out / "trajectories", files);
    }
    const bench::RunSummary summary = bench::summarise(results);
    std::printf("%s", bench::summaryTable(summary, options->controller + " on " + options->worlds + " (" +
                                                       spec.episode.protocol + ")").c_str());
    std::printf("  wall time %.2f s, simulated %.1f s, %.0f simulated s per wall s\n", wall, summary.sim_time,
                summary.sim_time / wall);
    std::printf("wrote %s\n", (out / "episodes.csv").c_str());
    if (summary.error_rate > 0.0) context.exit_code = 1;
  });
}

}  // namespace barn::cli
