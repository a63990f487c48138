// The HTML report of a run record or sweep (report.hpp): its tables, figures and the page.

#include "barn/report/report.hpp"

#include <cerrno>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <string>
#include <utility>
#include <vector>

#include "barn/bench/report.hpp"
#include "barn/bench/results_io.hpp"
#include "barn/bench/run_record.hpp"
#include "barn/bench/sweep_grid.hpp"
#include "barn/core/errors.hpp"
#include "barn/core/protocol.hpp"
#include "barn/core/text_io.hpp"
#include "barn/report/sweep_plots.hpp"
#include "report_figures.hpp"

namespace barn::report {

namespace fs = std::filesystem;

namespace {

std::string fixed(double value, int digits) {
  if (!std::isfinite(value)) return "-";
  char text[32];
  std::snprintf(text, sizeof(text), "%.*f", digits, value);
  return text;
}

std::string protocolOf(const bench::RunManifest& m) { return std::string(core::toString(bench::recordProtocol(m, "manifest"))); }

HtmlTable summaryRows(const std::vector<std::pair<std::string, bench::RunSummary>>& rows, const std::string& id,
                       const std::string& first_column) {
  HtmlTable table;
  table.id = id;
  table.header = {first_column, "worlds", "episodes", "score", "success", "collision", "timeout", "error", "time [s]"};
  table.numeric = {false, true, true, true, true, true, true, true, true};
  for (const auto& [name, s] : rows)
    table.rows.push_back({name, std::to_string(s.worlds), std::to_string(s.episodes), fixed(s.score, 4),
                          fixed(s.success_rate, 3), fixed(s.collision_rate, 3), fixed(s.timeout_rate, 3),
                          fixed(s.error_rate, 3), fixed(s.avg_success_time, 1)});
  return table;
}

HtmlTable perWorldTable(const std::vector<bench::EpisodeResult>& results, const std::vector<core::WorldSpec>& worlds,
                        double max_score) {
  HtmlTable table;
  table.id = "per-world";
  table.header = {"world", "trials", "success", "collision", "timeout", "score", "95 % low", "95 % high", "time [s]",
                  "tortuosity"};
  table.numeric = std::vector<bool>(table.header.size(), true);
  for (const bench::WorldStats& w : bench::perWorldStats(results, max_score)) {
    double tortuosity = NAN;
    for (const auto& spec : worlds)
      if (spec.id == w.world_id) tortuosity = spec.metrics.tortuosity;
    const double n = w.trials;
    table.rows.push_back({std::to_string(w.world_id), std::to_string(w.trials), fixed(w.success_rate, 2),
                          fixed(w.collisions / n, 2), fixed(w.timeouts / n, 2), fixed(w.mean_score, 4),
                          fixed(w.score_ci_low, 4), fixed(w.score_ci_high, 4), fixed(w.mean_success_time, 1),
                          fixed(tortuosity, 3)});
  }
  return table;
}

HtmlTable difficultyTable(const std::vector<bench::BucketSummary>& buckets) {
  HtmlTable table;
  table.id = "breakdown";
  table.sortable = false;
  table.header = {"group", "bucket", "worlds", "score", "success", "collision", "timeout"};
  for (const auto& b : buckets)
    table.rows.push_back({b.group, b.bucket, std::to_string(b.summary.worlds), fixed(b.summary.score, 4),
                          fixed(b.summary.success_rate, 3), fixed(b.summary.collision_rate, 3),
                          fixed(b.summary.timeout_rate, 3)});
  return table;
}

}  // namespace

HtmlReport runReport(const fs::path& dir, const fs::path& figures, int max_failures) {
  const bench::CompleteRecord record = bench::readCompleteRecord(dir);
  const bench::RunManifest& m = record.manifest;
  const std::vector<core::WorldSpec> worlds = bench::loadManifestWorlds(m);
  const std::vector<bench::EpisodeResult>& results = record.episodes;
  const bench::RunSummary summary = bench::summarise(results);
  HtmlReport report;
  report.title = m.controller + " on " + bench::worldSetName(worlds) + " worlds";
  report.subtitle = "worlds " + m.worlds_spec + " x " + std::to_string(m.trials) + " trials, protocol " + protocolOf(m) +
                    ", run seed " + std::to_string(m.seed) + "; barnbench " + m.barnbench_version + ", commit " +
                    m.git_commit + ", " + m.host + ", started " + m.started;
  HtmlSection overview{"Summary", {"Rates and the score are means over worlds of the per-world mean over trials, as the "
                                   "official report_test.py computes them; the time is that of successful trials."},
                       {summaryRows({{m.controller, summary}}, "summary", "run")}, {}};
  overview.figures = scoreFigures(dir, figures);
  report.sections.push_back(overview);
  report.sections.push_back({"Per world", {"Click a column header to sort. The interval is Student's t over the trials."},
                             {perWorldTable(results, worlds, core::protocolPreset(bench::recordProtocol(m, "manifest")).maxScore())}, {}});
  report.sections.push_back({"By difficulty", {"Per generator setting and per quartile of each normalised metric."},
                             {difficultyTable(bench::difficultyBreakdown(results, worlds))}, {}});
  HtmlSection failures{"Failed episodes", {}, {}, {}};
  std::size_t failed = 0;
  for (const auto& r : results) failed += r.outcome != bench::Outcome::Success;
  if (failed == 0) {
    failures.paragraphs.push_back("Every episode succeeded.");
  } else if (!m.source.empty()) {
    failures.paragraphs.push_back(std::to_string(failed) + " episodes failed; this record was imported (" + m.source +
                                  "), so they cannot be re-simulated.");
  } else {
    FailureFigures drawn_figures = failureFigures(dir, figures, static_cast<std::size_t>(max_failures));
    failures.figures = std::move(drawn_figures.figures);
    const std::size_t drawn = drawn_figures.episodes;
    failures.paragraphs.push_back(
        std::to_string(failed) + " episodes failed" +
        (drawn == 0 ? "; none can be drawn: a Python class's episodes are drawn from their recorded trajectories "
                      "(barnbench.run(..., trajectories=True))"
         : failed > drawn ? "; " + std::to_string(drawn) + " of them are drawn" : "") +
        (drawn > 0 ? " (from recorded trajectories where the record has them, else re-simulated: the same seed gives the "
                     "same episode)." : "."));
  }
  report.sections.push_back(failures);
  return report;
}

HtmlReport sweepReport(const fs::path& dir, const fs::path& figures) {
  const SweepTable table = readSweepTable(dir);
  HtmlReport report;
  report.title = "Sweep of " + table.controller;
  std::string swept;
  for (const auto& key : table.keys) swept += (swept.empty() ? "" : " x ") + key;
  report.subtitle = std::to_string(table.cells.size()) + " cells over " + swept;
  if (!table.cells.empty())
    report.subtitle += "; " + std::to_string(table.cells.front().summary.worlds) + " worlds x " +
                       std::to_string(table.trials) + " trials, protocol " + std::string(core::toString(table.protocol));
  HtmlTable cells;
  cells.id = "cells";
  cells.header = table.keys;
  for (const char* column : {"score", "success", "collision", "timeout", "time [s]"}) cells.header.push_back(column);
  cells.numeric = std::vector<bool>(cells.header.size(), true);
  for (const SweepCell& cell : table.cells) {
    const bench::RunSummary& s = cell.summary;
    std::vector<std::string> row = cell.values;
    for (const std::string& v : {fixed(s.score, 4), fixed(s.success_rate, 3), fixed(s.collision_rate, 3),
                                 fixed(s.timeout_rate, 3), fixed(s.avg_success_time, 1)})
      row.push_back(v);
    cells.rows.push_back(row);
  }
  report.sections.push_back({"Cells", {"One run record per cell; click a column header to sort."}, {cells},
                             sweepFigures(table, figures)});
  return report;
}

void writeReport(const fs::path& input, const fs::path& output, const ReportOptions& options) {
  if (output.extension() != ".html") throw core::InputError(output.string() + ": expected a .html file for the report");
  const bool is_run = fs::exists(input / bench::kManifestFile);
  if (!is_run && !fs::exists(input / bench::kSweepFile))
    throw core::InputError(input.string() + ": neither a run record (manifest.yaml) nor a sweep (sweep.yaml)");
  if (fs::is_directory(output)) throw core::InputError(output.string() + ": is a folder, expected a .html file");
  if (options.max_failures < 0)
    throw core::InputError("max_failures: " + std::to_string(options.max_failures) + " (must be >= 0)");
  // Figures are drawn into a scratch folder of this call alone (two reports at once must not
  // draw into each other's), embedded, and removed.
  std::string scratch_name = (fs::temp_directory_path() / "barn_report.XXXXXX").string();
  if (::mkdtemp(scratch_name.data()) == nullptr)
    throw core::IoError(scratch_name + ": cannot create a scratch folder: " + std::strerror(errno));
  const fs::path scratch = scratch_name;
  std::error_code ec;
  std::string html;
  try {
    html = renderHtml(is_run ? runReport(input, scratch, options.max_failures) : sweepReport(input, scratch));
  } catch (...) {
    fs::remove_all(scratch, ec);
    throw;
  }
  fs::remove_all(scratch, ec);
  core::writeFileAtomic(output, html);
}

}  // namespace barn::report
