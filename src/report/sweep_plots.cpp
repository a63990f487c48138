#include "barn/report/sweep_plots.hpp"

#include <algorithm>
#include <charconv>
#include <cstdint>
#include <cmath>
#include <cstdio>

#include "barn/bench/results_io.hpp"
#include "barn/bench/run_record.hpp"
#include "barn/bench/sweep_grid.hpp"
#include "barn/controllers/registry.hpp"
#include "barn/core/config.hpp"
#include "barn/core/errors.hpp"
#include "barn/core/protocol.hpp"
#include "barn/core/text_io.hpp"
#include "barn/viz/line_plot.hpp"
#include "barn/viz/plots.hpp"

namespace barn::report {

namespace {

std::size_t bestCell(const SweepTable& table) {
  std::size_t best = 0;
  for (std::size_t i = 1; i < table.cells.size(); ++i)
    if (table.cells[i].summary.score > table.cells[best].summary.score) best = i;
  return best;
}

constexpr int kBootstrapResamples = 10000;   // as barn compare's default
constexpr std::uint64_t kBootstrapSeed = 0;  // fixed, so the same sweep draws the same figure

/// What a figure shows: a run summary's field and its per-world counterpart.
struct Metric {
  const char* name;   // in the file name: heatmap_<name>, line_<name>
  const char* title;  // e.g. "BARN score"
  double bench::RunSummary::*field;
  double (*per_world)(const bench::WorldStats&);
  bool higher_is_better;
  bool is_score;  // scaled 0 ... the protocol's maximum score; a rate otherwise, 0 ... 1
};

double worldScore(const bench::WorldStats& w) { return w.mean_score; }
double worldSuccess(const bench::WorldStats& w) { return w.success_rate; }
double worldCollision(const bench::WorldStats& w) {
  return w.trials > 0 ? static_cast<double>(w.collisions) / w.trials : std::nan("");
}

std::string scoreText(double score) {
  char text[32];
  std::snprintf(text, sizeof text, "%g", score);
  return text;
}

/// "max_speed [m/s]", or the key alone when its unit is unknown.
std::string axisLabel(const SweepTable& table, std::size_t key) {
  const std::string unit = key < table.units.size() ? table.units[key] : "";
  return unit.empty() ? table.keys[key] : table.keys[key] + " [" + unit + "]";
}

/// The distinct values of key `key`, in grid order.
std::vector<std::string> keyValues(const SweepTable& table, std::size_t key) {
  std::vector<std::string> values;
  for (const auto& c : table.cells)
    if (std::find(values.begin(), values.end(), c.values[key]) == values.end()) values.push_back(c.values[key]);
  return values;
}

// Rows: the first key's values; columns: the second key's (the odometer's fast key).
viz::HeatMap heatMap(const SweepTable& table, const Metric& metric) {
  viz::HeatMap map;
  map.y_label = axisLabel(table, 0);
  map.x_label = axisLabel(table, 1);
  map.y_ticks = keyValues(table, 0);
  map.x_ticks = keyValues(table, 1);
  map.values.assign(map.y_ticks.size(), std::vector<double>(map.x_ticks.size(), std::nan("")));
  for (const auto& c : table.cells) {
    const auto r = static_cast<std::size_t>(std::find(map.y_ticks.begin(), map.y_ticks.end(), c.values[0]) - map.y_ticks.begin());
    const auto k = static_cast<std::size_t>(std::find(map.x_ticks.begin(), map.x_ticks.end(), c.values[1]) - map.x_ticks.begin());
    map.values[r][k] = c.summary.*metric.field;
  }
  map.higher_is_better = metric.higher_is_better;
  return map;
}

/// A whole-text finite number, or NaN.
double numberOrNan(const std::string& text) {
  double value = 0.0;
  const auto [end, ec] = std::from_chars(text.data(), text.data() + text.size(), value);
  return ec == std::errc() && end == text.data() + text.size() && std::isfinite(value) ? value : std::nan("");
}

// One point per cell: the mean over worlds of the per-world values (report_test.py's
// aggregation) with a percentile bootstrap interval that resamples worlds, the unit the
// benchmark samples. Numeric values sit at their value on the x axis; any other text makes the
// axis a list of categories.
viz::LinePlot linePlot(const SweepTable& table, const Metric& metric) {
  viz::LinePlot plot;
  plot.width = 720;
  plot.height = 480;
  plot.x_label = axisLabel(table, 0);
  plot.y_label = std::string(metric.title) + ", mean over worlds";
  bool numeric = true;
  for (const auto& c : table.cells) numeric = numeric && std::isfinite(numberOrNan(c.values[0]));
  viz::LineSeries series;
  series.label = "mean over " + std::to_string(table.cells.front().summary.worlds) +
                 " worlds; bars: 95 % bootstrap interval, worlds resampled";
  series.markers = true;
  for (std::size_t i = 0; i < table.cells.size(); ++i) {
    const SweepCell& c = table.cells[i];
    const double x = numeric ? numberOrNan(c.values[0]) : static_cast<double>(i);
    std::vector<double> values;
    for (const auto& w : c.worlds) values.push_back(metric.per_world(w));
    plot.x_ticks.push_back({x, c.values[0]});
    series.x.push_back(x);
    if (values.empty()) {
      series.y.push_back(std::nan(""));
      series.low.push_back(std::nan(""));
      series.high.push_back(std::nan(""));
      continue;
    }
    const bench::BootstrapInterval interval = bench::bootstrapMean(values, kBootstrapResamples, kBootstrapSeed);
    series.y.push_back(interval.estimate);
    series.low.push_back(interval.low);
    series.high.push_back(interval.high);
  }
  plot.series = {series};
  return plot;
}

}  // namespace

std::string sweptKeyUnit(const std::string& controller_config, const std::string& key) {
  const core::ConfigNode config = core::ConfigNode::parseString(controller_config, "controller_config");
  std::string type;
  if (!config.isMap() || !config.child("type").read(type)) return {};
  return controllers::controllerKeyUnit(type, key);
}

SweepTable readSweepTable(const std::filesystem::path& dir) {
  const bench::SweepGrid grid = bench::readSweepFile(dir);
  SweepTable table;
  table.controller = grid.controller;
  for (const auto& p : grid.parameters) table.keys.push_back(p.key);
  for (std::size_t c = 0; c < grid.cells.size(); ++c) {
    const std::filesystem::path cell_dir = dir / grid.cells[c];
    if (!bench::readManifest(cell_dir / bench::kManifestFile).complete)
      throw core::InputError(cell_dir.string() + ": not complete; finish the sweep with barn sweep --resume " + dir.string());
    const bench::CompleteRecord record = bench::readCompleteRecord(cell_dir);
    const bench::RunManifest& m = record.manifest;
    if (c == 0) {
      table.protocol = bench::recordProtocol(m, "manifest");
      table.trials = m.trials;
      for (const auto& p : grid.parameters) table.units.push_back(sweptKeyUnit(m.controller_config, p.key));
    }
    SweepCell cell;
    cell.name = grid.cells[c];
    cell.values = bench::cellValues(grid, c);
    const std::vector<bench::EpisodeResult>& episodes = record.episodes;
    cell.summary = bench::summarise(episodes);
    cell.worlds = bench::perWorldStats(episodes, core::protocolPreset(table.protocol).maxScore());
    table.cells.push_back(cell);
  }
  return table;
}

std::string sweepCsv(const SweepTable& table) {
  std::string text = "cell";
  for (const auto& k : table.keys) text += "," + k;
  text += ",score,success_rate,collision_rate,timeout_rate,error_rate,avg_success_time_s,worlds,episodes\n";
  for (const auto& c : table.cells) {
    text += c.name;
    for (const auto& v : c.values) text += "," + v;
    const auto& s = c.summary;
    text += "," + core::formatDouble(s.score) + "," + core::formatDouble(s.success_rate) + "," +
            core::formatDouble(s.collision_rate) + "," + core::formatDouble(s.timeout_rate) + "," +
            core::formatDouble(s.error_rate) + "," + (std::isfinite(s.avg_success_time) ? core::formatDouble(s.avg_success_time) : "") +
            "," + std::to_string(s.worlds) + "," + std::to_string(s.episodes) + "\n";
  }
  return text;
}

std::string sweepSummary(const SweepTable& table) {
  std::string text = "sweep of " + table.controller + " (" + std::to_string(table.cells.size()) + " cells)\n ";
  for (const auto& k : table.keys) {
    char col[64];
    std::snprintf(col, sizeof(col), " %18s", k.c_str());
    text += col;
  }
  text += "    score  success  collision  timeout  avg time\n";
  const std::size_t best = bestCell(table);
  for (std::size_t i = 0; i < table.cells.size(); ++i) {
    const auto& c = table.cells[i];
    text += i == best ? "*" : " ";
    for (const auto& v : c.values) {
      char col[64];
      std::snprintf(col, sizeof(col), " %18s", v.c_str());
      text += col;
    }
    char line[160];
    std::snprintf(line, sizeof(line), "   %.4f    %.3f      %.3f    %.3f   %6.2f\n", c.summary.score, c.summary.success_rate,
                  c.summary.collision_rate, c.summary.timeout_rate, c.summary.avg_success_time);
    text += line;
  }
  text += "(* best score)\n";
  return text;
}

std::vector<std::filesystem::path> writeSweepPlots(const SweepTable& table, const std::filesystem::path& dir,
                                                   const std::string& extension) {
  std::vector<std::filesystem::path> written;
  if (table.cells.empty() || table.keys.empty() || table.keys.size() > 2) return written;
  const double max_score = core::protocolPreset(table.protocol).maxScore();
  const int worlds = table.cells.front().summary.worlds;
  const std::string scope = std::to_string(worlds) + (worlds == 1 ? " world x " : " worlds x ") +
                            std::to_string(table.trials) + (table.trials == 1 ? " trial, " : " trials, ") +
                            std::string(core::toString(table.protocol));
  const Metric metrics[] = {{"score", "BARN score", &bench::RunSummary::score, &worldScore, true, true},
                            {"success", "success rate", &bench::RunSummary::success_rate, &worldSuccess, true, false},
                            {"collision", "collision rate", &bench::RunSummary::collision_rate, &worldCollision, false, false}};
  for (const Metric& metric : metrics) {
    const double scale_max = metric.is_score ? max_score : 1.0;
    const std::filesystem::path file =
        dir / ((table.keys.size() == 2 ? "heatmap_" : "line_") + std::string(metric.name) + extension);
    if (table.keys.size() == 2) {
      viz::HeatMap map = heatMap(table, metric);
      map.title = table.controller + ": " + metric.title + " (" + scope + ")";
      map.scale_min = 0.0;
      map.scale_max = scale_max;
      map.scale_label = metric.is_score ? "score (" + std::string(core::toString(table.protocol)) + " maximum " + scoreText(max_score) + ")"
                                        : std::string(metric.title) + " (fraction of episodes)";
      viz::renderHeatMap(map, file);
    } else {
      viz::LinePlot plot = linePlot(table, metric);
      plot.title = table.controller + ": " + metric.title + " (" + scope + ")";
      plot.y_min = 0.0;
      plot.y_max = scale_max;
      viz::renderLinePlot(plot, file);
    }
    written.push_back(file);
  }
  return written;
}

}  // namespace barn::report
