// barn show: a finished record read back: its summary, the difficulty breakdown and one line
// per world (outcomes, mean score with its 95 % interval over trials, mean successful time).

#include <cmath>
#include <cstdio>
#include <filesystem>

#include "barn/bench/report.hpp"
#include "barn/bench/results_io.hpp"
#include "barn/bench/run_record.hpp"
#include "barn/core/errors.hpp"
#include "commands.hpp"

namespace barn::cli {

namespace {

namespace fs = std::filesystem;

struct ShowOptions {
  std::string record;
  bool breakdown = false;
};

std::string worldTable(const std::vector<bench::EpisodeResult>& results, double max_score) {
  std::string table = "  world  trials  success  collision  timeout   score  95 % interval      time [s]\n";
  for (const bench::WorldStats& w : bench::perWorldStats(results, max_score)) {
    char interval[48] = "            -";
    if (std::isfinite(w.score_ci_low))
      std::snprintf(interval, sizeof(interval), "[%+.4f, %+.4f]", w.score_ci_low, w.score_ci_high);
    char time[16] = "     -";
    if (std::isfinite(w.mean_success_time)) std::snprintf(time, sizeof(time), "%6.1f", w.mean_success_time);
    const double n = w.trials;
    char line[160];
    std::snprintf(line, sizeof(line), "  %5d  %6d  %7.2f  %9.2f  %7.2f  %.4f  %-18s %s\n", w.world_id, w.trials,
                  w.success_rate, w.collisions / n, w.timeouts / n, w.mean_score, interval, time);
    table += line;
  }
  return table;
}

}  // namespace

void addShowCommand(CLI::App& app, CommandContext& /*context*/) {
  auto options = std::make_shared<ShowOptions>();
  CLI::App* cmd = app.add_subcommand("show", "Summary, difficulty breakdown and per-world table of a finished record");
  cmd->add_option("record", options->record, "Run record folder")->required();
  cmd->add_flag("--breakdown", options->breakdown, "Show every difficulty group, however few worlds its buckets hold");
  cmd->callback([options] {
    const fs::path dir = options->record;
    const bench::CompleteRecord record = bench::readCompleteRecord(dir);
    const bench::RunManifest& m = record.manifest;
    const std::vector<core::WorldSpec> worlds = bench::loadManifestWorlds(m);
    const std::vector<bench::EpisodeResult>& results = record.episodes;
    printRecordSummary(dir, m, worlds, results, bench::recordProtocol(m, "manifest"), options->breakdown);
    std::printf("%s", worldTable(results, core::protocolPreset(bench::recordProtocol(m, "manifest")).maxScore()).c_str());
  });
}

}  // namespace barn::cli
