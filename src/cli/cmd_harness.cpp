// barn import-out / export-out: the official BARN harness's results file (run.py --out, one
// line "world_idx success collided timeout time nav_metric" per episode) to and from a run
// record, so Gazebo runs go through the same summaries, plots and comparisons.

#include <algorithm>
#include <cstdio>
#include <filesystem>

#include "barn/bench/record_session.hpp"
#include "barn/bench/harness_out.hpp"
#include "barn/bench/report.hpp"
#include "barn/bench/results_io.hpp"
#include "barn/bench/run_record.hpp"
#include "barn/bench/world_selection.hpp"
#include "barn/core/config.hpp"
#include "barn/core/errors.hpp"
#include "barn/core/text_io.hpp"
#include "commands.hpp"

namespace barn::cli {

namespace {

namespace fs = std::filesystem;

struct ImportOutOptions {
  std::string file;
  std::string world_dir;
  std::string out;
  std::string protocol = "barn2023";
  std::string label;
};

struct ExportOutOptions {
  std::string record;
  std::string out;
};

std::string hex64(std::uint64_t value) {
  char text[32];
  std::snprintf(text, sizeof text, "%016llx", static_cast<unsigned long long>(value));
  return text;
}

void importOut(const ImportOutOptions& o) {
  checkOutFolder(o.out, "--out");
  bench::checkNoRecordForOut(o.out);
  const core::Protocol protocol = core::protocolPreset(o.protocol);
  // Everything is read and checked before anything is written.
  const std::string text = core::readTextFile(o.file);
  const auto lines = bench::parseHarnessOut(text, o.file);
  const bench::LoadedWorlds loaded = bench::loadWorlds(o.world_dir, o.world_dir, /*keep_going=*/true);
  const bench::HarnessImport imported = bench::importHarnessLines(lines, loaded.worlds, protocol, o.file);
  std::vector<core::WorldSpec> worlds;
  for (const auto& w : loaded.worlds)
    if (std::binary_search(imported.world_ids.begin(), imported.world_ids.end(), w.id)) worlds.push_back(w);

  if (imported.unflagged > 0)
    std::fprintf(stderr, "warning: %s: %d lines have no flag set (run.py never writes that); read as timeouts\n",
                 o.file.c_str(), imported.unflagged);
  if (imported.min_trials != imported.max_trials)
    std::fprintf(stderr, "warning: %s: worlds have %d to %d trials; the record's trials field says %d\n",
                 o.file.c_str(), imported.min_trials, imported.max_trials, imported.max_trials);
  const bench::NavMetricCheck& check = imported.check;
  if (check.score_mismatches > 0) {
    std::fprintf(stderr,
                 "warning: %s: nav_metric differs from the recomputed %s score (k = %g) by more than 1e-3 on %d of %d "
                 "lines (largest %.4f, line %d); is the file of the other protocol (--protocol)?\n",
                 o.file.c_str(), std::string(core::toString(protocol.name)).c_str(), protocol.clip_low,
                 check.score_mismatches, check.lines, check.max_score_difference, check.worst_line);
    if (check.ratio_matches > 0)
      std::fprintf(stderr,
                   "         %d of them hold success * AT / OT instead (within 0.1 %%): this harness version wrote the "
                   "time ratio, not the score\n",
                   check.ratio_matches);
  }

  bench::RunManifest m;
  m.controller = o.label.empty() ? "gazebo:" + fs::path(o.file).stem().string() : o.label;
  m.episode_config = "protocol: " + std::string(core::toString(protocol.name)) + "\n";
  for (int id : imported.world_ids) m.worlds_spec += (m.worlds_spec.empty() ? "" : ",") + std::to_string(id);
  m.worlds_folder = loaded.folder.string();
  m.world_ids = imported.world_ids;
  m.worlds_digest = bench::worldsDigest(worlds);
  m.trials = imported.max_trials;
  m.source = fs::absolute(o.file).lexically_normal().string();
  m.source_digest = hex64(core::fnv1a64(text));
  m.episodes_total = imported.results.size();
  m.barnbench_version = BARN_VERSION;
  m.git_commit = bench::gitCommit();
  const bench::RecordWriter writer(o.out);
  bench::checkNoRecordForOut(o.out);  // again under the lock: a second import into --out cannot pass it
  const std::vector<bench::EpisodeResult> written = bench::writeCompleteRecord(writer, m, imported.results, worlds);
  std::printf("imported %zu episodes on %zu worlds from %s (scored with %s)\n", imported.results.size(),
              imported.world_ids.size(), o.file.c_str(), std::string(core::toString(protocol.name)).c_str());
  printRecordSummary(o.out, m, worlds, written, protocol.name);
  std::printf("wrote %s\n", o.out.c_str());
}

void exportOut(const ExportOutOptions& o) {
  const bench::CompleteRecord record = bench::readCompleteRecord(o.record);
  const bench::RunManifest& m = record.manifest;
  const std::vector<bench::EpisodeResult>& results = record.episodes;
  if (fs::is_directory(o.out)) throw core::InputError("--out " + o.out + ": is a folder, expected a file");
  int errors = 0;
  for (const auto& r : results) errors += r.outcome == bench::Outcome::Error;
  if (errors > 0)
    std::fprintf(stderr, "warning: %d error episodes have no counterpart in run.py's file; written with no flag set\n",
                 errors);
  core::writeFileAtomic(o.out, bench::harnessOut(results));
  const std::string protocol(core::toString(bench::recordProtocol(m, o.record + " manifest")));
  std::printf("wrote %zu lines to %s (nav_metric = the record's %s score)\n", results.size(), o.out.c_str(),
              protocol.c_str());
}

}  // namespace

void addHarnessOutCommands(CLI::App& app, CommandContext& /*context*/) {
  auto in = std::make_shared<ImportOutOptions>();
  CLI::App* import = app.add_subcommand(
      "import-out", "Read an official BARN harness results file (run.py --out) into a run record");
  import->add_option("file", in->file, "Results file: 'world_idx success collided timeout time nav_metric' per line")
      ->required();
  import->add_option("--world-dir", in->world_dir, "Folder of the world files the run used (e.g. from barn import-barn)")
      ->required();
  import->add_option("--out", in->out, "Folder for the record")->required();
  import->add_option("--protocol", in->protocol, "Score with barn2023 (k = 4) or barn2024 (k = 2)")->capture_default_str();
  import->add_option("--controller-label", in->label, "Controller name in the record (default gazebo:<file stem>)");
  import->callback([in] { importOut(*in); });

  auto out = std::make_shared<ExportOutOptions>();
  CLI::App* exporter = app.add_subcommand("export-out", "Write a run record as an official BARN harness results file");
  exporter->add_option("record", out->record, "Run record folder")->required();
  exporter->add_option("--out", out->out, "Results file to write")->required();
  exporter->callback([out] { exportOut(*out); });
}

}  // namespace barn::cli
