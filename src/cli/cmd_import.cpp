// barn import-barn: the original BARN dataset as barnbench world files, with --verify.

#include <cstdio>
#include <string>

#include "barn/bench/record_writer.hpp"
#include "barn/core/world_file.hpp"
#include "commands.hpp"
#include "generator/dataset_import.hpp"
#include "barn/report/set_summary.hpp"

namespace barn::cli {

namespace {

struct ImportOptions {
  std::string dataset_dir;
  std::string out;
  bool verify = false;
};

void printVerifyReport(const generator::VerifyReport& report) {
  for (const auto& line : report.mismatches) std::printf("MISMATCH %s\n", line.c_str());
  std::printf("verify: %d worlds\n", report.worlds);
  std::printf("  A* paths identical      %d/%d\n", report.paths_identical, report.worlds);
  std::printf("  metrics equal (1e-9)    %d/%d\n", report.metrics_equal, report.worlds);
  std::printf("  cspaces identical       %d/%d\n", report.cspaces_identical, report.cspaces_present);
  if (report.norm_metrics_compared) {
    std::printf("  norm metrics equal      %d/%d\n", report.norm_metrics_equal, report.norm_metrics_present);
  } else {
    std::printf("  norm metrics            not compared: the stored z-scores are over all 300 worlds, "
                "this folder has %d\n", report.worlds);
  }
}

// How the worlds of a partial dataset compare in difficulty with the ones it lacks (from the
// stored z-scores, see absentWorldsMetrics): e.g. the held-out half of the official set.
void printAbsentWorlds(const generator::DatasetHalves& halves) {
  std::printf("difficulty metrics, mean (sd): the %d worlds here and the %d not here (from the stored z-scores over all %d)\n",
              halves.present.worlds, halves.absent.worlds, halves.present.worlds + halves.absent.worlds);
  std::printf("  %-26s %-16s %s\n", "metric", "here", "not here");
  for (std::size_t k = 0; k < 5; ++k) {
    char here[40], absent[40];
    std::snprintf(here, sizeof(here), "%.3f (%.3f)", halves.present.mean[k], halves.present.sd[k]);
    std::snprintf(absent, sizeof(absent), "%.3f (%.3f)", halves.absent.mean[k], halves.absent.sd[k]);
    std::printf("  %-26s %-16s %s\n", std::string(core::DifficultyMetrics::kNames[k]).c_str(), here, absent);
  }
}

}  // namespace

void addImportCommand(CLI::App& app, CommandContext& context) {
  auto options = std::make_shared<ImportOptions>();
  CLI::App* cmd = app.add_subcommand(
      "import-barn", "Convert the original BARN dataset (grid_files/, path_files/, metrics_files/ ...) to world files");
  cmd->add_option("dataset_dir", options->dataset_dir, "Folder of the original dataset")->required();
  cmd->add_option("--out", options->out, "Folder for the world files and index.csv")->required();
  cmd->add_flag("--verify", options->verify,
                "Recompute C-space, A* path and metrics from each grid and list every difference (exit 1 if any)");
  cmd->callback([options, &context] {
    // Everything is read and validated before anything is written.
    const auto dataset = generator::readDataset(options->dataset_dir);
    const auto worlds = generator::importDataset(dataset);
    if (options->verify) {
      const auto report = generator::verifyDataset(dataset);
      printVerifyReport(report);
      if (!report.ok()) context.exit_code = 1;
    }
    std::printf("%s", report::parameterSetTable(worlds).c_str());
    if (const auto halves = generator::absentWorldsMetrics(dataset)) printAbsentWorlds(*halves);
    checkOutFolder(options->out, "--out");
    const bench::RecordWriter writer(options->out);
    writer.write(core::worldSetFiles(worlds));
    std::printf("wrote %zu world files and index.csv to %s\n", worlds.size(), options->out.c_str());
  });
}

}  // namespace barn::cli
