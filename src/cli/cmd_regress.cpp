// barn regress: rerun the committed reference runs and fail on a score or success drop.

#include <chrono>
#include <cmath>
#include <cstdio>
#include <filesystem>

#include "barn/bench/report.hpp"
#include "barn/bench/record_writer.hpp"
#include "barn/bench/results_io.hpp"
#include "barn/bench/run_record.hpp"
#include "barn/core/config.hpp"
#include "barn/core/errors.hpp"
#include "barn/core/text_io.hpp"
#include "commands.hpp"
#include "repo_paths.hpp"

namespace barn::cli {

namespace {

// Marks a folder barn regress made for a rerun (and may therefore replace).
constexpr const char* kRerunMarker = ".barn_regress_rerun";

namespace fs = std::filesystem;

struct RegressOptions {
  std::string baseline;
  std::vector<std::string> controllers;
  double tolerance = 0.005;
  double success_tolerance = 0.0;
  std::vector<std::string> overrides;
  bool update = false;
  int jobs = 0;
  std::string work;
};

struct Row {
  std::string name;
  bench::RunSummary before, after;
  bool identical = false;
  bool failed = false;
};

// The reference records: one folder per controller run, each with a complete manifest.
std::vector<fs::path> referenceRecords(const fs::path& baseline, const std::vector<std::string>& only) {
  std::error_code ec;
  if (!fs::is_directory(baseline, ec)) throw core::InputError(baseline.string() + ": no such baseline folder");
  std::vector<fs::path> records;
  for (const auto& entry : fs::directory_iterator(baseline, ec))
    if (entry.is_directory() && fs::exists(entry.path() / bench::kManifestFile)) records.push_back(entry.path());
  std::sort(records.begin(), records.end());
  if (!only.empty()) {
    std::vector<fs::path> selected;
    for (const auto& name : only) {
      const fs::path record = baseline / name;
      if (!fs::exists(record / bench::kManifestFile))
        throw core::InputError(baseline.string() + ": no reference run '" + name + "'");
      selected.push_back(record);
    }
    records = selected;
  }
  if (records.empty()) throw core::InputError(baseline.string() + ": holds no reference runs (folders with manifest.yaml)");
  return records;
}

}  // namespace

void addRegressCommand(CLI::App& app, CommandContext& context) {
  auto options = std::make_shared<RegressOptions>();
  CLI::App* cmd = app.add_subcommand(
      "regress", "Rerun the reference runs in the baseline and fail if a score or success rate dropped");
  cmd->add_option("--baseline", options->baseline, "Baseline folder (one record per controller)")
      ->default_str("results/baseline");
  cmd->add_option("--controllers", options->controllers, "Only these reference runs (folder names)")->delimiter(',');
  cmd->add_option("--tolerance", options->tolerance, "Allowed drop of the score")->capture_default_str()
      ->check(kFiniteNumber)
      ->check(CLI::Range(0.0, 1.0));
  cmd->add_option("--success-tolerance", options->success_tolerance, "Allowed drop of the success rate")
      ->capture_default_str()
      ->check(kFiniteNumber)
      ->check(CLI::Range(0.0, 1.0));
  cmd->add_option("--set", options->overrides,
                  "Override a controller config key for the rerun, KEY=VALUE (e.g. inventec.safety.front_pad_y=0)");
  cmd->add_flag("--update", options->update, "Rewrite the baseline with the reruns (after an intended change)");
  cmd->add_option("--jobs", options->jobs, "Threads (0 = all cores)")->check(CLI::Range(0, 4096));
  cmd->add_option("--work", options->work, "Folder for the reruns (default results/regress)");
  cmd->callback([options, &context] {
    const fs::path baseline = options->baseline.empty() ? repoPath("results") / "baseline" : fs::path(options->baseline);
    const fs::path work = options->work.empty() ? repoPath("results") / "regress" : fs::path(options->work);
    std::vector<Row> rows;
    for (const fs::path& record : referenceRecords(baseline, options->controllers)) {
      // The reference run, read whole (a reference whose rows disagree with its manifest
      // would make the check pass against a wrong score); locked while it may be rewritten.
      bench::RecordWriter baseline_lock;
      if (options->update) baseline_lock = bench::RecordWriter(record);
      const bench::CompleteRecord reference = bench::readCompleteRecord(record);
      const bench::RunManifest& manifest = reference.manifest;
      // The rerun: the same experiment, from scratch, in a fresh record.
      bench::RunManifest rerun = manifest;
      core::ConfigNode node = core::ConfigNode::parseString(rerun.controller_config, record.string() + " controller_config");
      // A committed baseline names files of the checkout it was made in: point a policy file
      // that is not there at this checkout's configs/policies/, and the repository's worlds at
      // this checkout's worlds/ (the digests still guard their content).
      std::string type;
      node.child("type").read(type);
      std::string policy;
      if (node.child(type).child("policy").read(policy) && !fs::exists(policy))
        node.set(type + ".policy", (repoPath("configs") / "policies" / fs::path(policy).filename()).string());
      for (const auto& item : options->overrides) {
        const auto eq = item.find('=');
        if (eq == std::string::npos || eq == 0) throw core::InputError("--set '" + item + "': expected KEY=VALUE");
        node.set(item.substr(0, eq), item.substr(eq + 1));
      }
      rerun.controller_config = node.toYaml();
      // The files the rerun's config names must be the ones the reference ran with (a policy
      // retrained since, or another one of the same name, would compare two controllers).
      rerun.config_files = bench::configFileDigests(rerun.controller_config);
      if (!manifest.config_files.empty() && options->overrides.empty()) {
        for (std::size_t i = 0; i < manifest.config_files.size(); ++i) {
          const bench::ConfigFile& was = manifest.config_files[i];
          if (i >= rerun.config_files.size() || rerun.config_files[i].digest != was.digest)
            throw core::InputError(record.string() + ": " +
                                   (i < rerun.config_files.size() ? rerun.config_files[i].path : was.path) +
                                   " is not the file the reference run used (its digest was " + was.digest +
                                   "); restore it, or rerun the reference with barn regress --update");
        }
      }
      if (fs::path(rerun.worlds_folder).filename() == "worlds") rerun.worlds_folder = fs::absolute(repoPath("worlds")).string();
      rerun.complete = false;
      rerun.episodes_done = 0;
      rerun.wall_time_s = 0.0;
      rerun.started.clear();
      // The rerun's folder is replaced only if an earlier regress made it (its marker file):
      // a command never deletes what it did not create (--work pointing at the baseline, or at
      // results/, must not wipe them).
      const fs::path dir = work / record.filename();
      if (fs::exists(dir)) {
        if (!fs::exists(dir / kRerunMarker))
          throw core::InputError(dir.string() + ": exists and was not made by barn regress; choose another --work");
        fs::remove_all(dir);
      }
      {
        const bench::RecordWriter writer(dir);  // released before the run takes the folder
        writer.write({{bench::kManifestFile, bench::formatManifest(rerun, dir)},
                      {kRerunMarker, "a rerun made by barn regress; barn regress replaces this folder\n"}});
      }
      std::printf("== %s: rerunning %s\n", record.filename().c_str(), manifest.worlds_spec.c_str());
      std::fflush(stdout);
      SessionOptions session;
      session.jobs = options->jobs;
      runRecordFolder(dir, session);

      const bench::CompleteRecord after = bench::readCompleteRecord(dir);
      Row row;
      row.name = record.filename().string();
      row.before = bench::summarise(reference.episodes);
      row.after = bench::summarise(after.episodes);
      row.identical = core::readTextFile(record / bench::kEpisodesFile) == core::readTextFile(dir / bench::kEpisodesFile);
      row.failed = row.after.score < row.before.score - options->tolerance - 1e-12 ||
                   row.after.success_rate < row.before.success_rate - options->success_tolerance - 1e-12;
      rows.push_back(row);
      if (options->update) {
        // One set, renamed into place: a kill or a full disk leaves the old reference whole.
        // The manifest's paths are written relative to the baseline's folder, not the rerun's.
        baseline_lock.write({{bench::kManifestFile, bench::formatManifest(after.manifest, record)},
                             {bench::kEpisodesFile, core::readTextFile(dir / bench::kEpisodesFile)},
                             {bench::kSummaryFile, core::readTextFile(dir / bench::kSummaryFile)}});
      }
    }
    std::printf("\nregression check against %s (tolerance: score %.4f, success %.4f)\n", baseline.c_str(),
                options->tolerance, options->success_tolerance);
    std::printf("  %-18s %9s %9s %9s  %8s %8s  %-9s %s\n", "run", "score", "now", "delta", "success", "now", "episodes",
                "status");
    bool any_failed = false;
    for (const Row& r : rows) {
      std::printf("  %-18s %9.4f %9.4f %+9.4f  %8.3f %8.3f  %-9s %s\n", r.name.c_str(), r.before.score, r.after.score,
                  r.after.score - r.before.score, r.before.success_rate, r.after.success_rate,
                  r.identical ? "identical" : "differ", r.failed ? "FAIL" : "ok");
      any_failed = any_failed || r.failed;
    }
    if (options->update) std::printf("baseline updated: %s\n", baseline.c_str());
    if (any_failed && !options->update) {
      std::printf("REGRESSION: a score or success rate dropped beyond the tolerance\n");
      context.exit_code = 1;
    }
  });
}

}  // namespace barn::cli
