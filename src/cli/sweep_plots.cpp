#include "sweep_plots.hpp"

#include <algorithm>
#include <cmath>
#include <cstdio>

#include "barn/core/text_io.hpp"
#include "barn/viz/plots.hpp"

namespace barn::cli {

namespace {

std::size_t bestCell(const SweepTable& table) {
  std::size_t best = 0;
  for (std::size_t i = 1; i < table.cells.size(); ++i)
    if (table.cells[i].summary.score > table.cells[best].summary.score) best = i;
  return best;
}

}  // namespace

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

std::vector<std::filesystem::path> writeSweepPlots(const SweepTable& table, const std::filesystem::path& dir) {
  std::vector<std::filesystem::path> written;
  if (table.keys.size() != 2 || table.cells.empty()) return written;  // heat maps need exactly two keys
  // Rows: the first key's values; columns: the second key's (the odometer's fast key).
  std::vector<std::string> rows, cols;
  for (const auto& c : table.cells) {
    if (std::find(rows.begin(), rows.end(), c.values[0]) == rows.end()) rows.push_back(c.values[0]);
    if (std::find(cols.begin(), cols.end(), c.values[1]) == cols.end()) cols.push_back(c.values[1]);
  }
  struct Metric {
    const char* file;
    const char* title;
    double bench::RunSummary::*field;
    bool higher_is_better;
  };
  const Metric metrics[] = {{"heatmap_score.png", "BARN score", &bench::RunSummary::score, true},
                            {"heatmap_success.png", "success rate", &bench::RunSummary::success_rate, true},
                            {"heatmap_collision.png", "collision rate", &bench::RunSummary::collision_rate, false}};
  for (const auto& metric : metrics) {
    viz::HeatMap map;
    map.title = table.controller + ": " + metric.title;
    map.y_label = table.keys[0];
    map.x_label = table.keys[1];
    map.y_ticks = rows;
    map.x_ticks = cols;
    map.values.assign(rows.size(), std::vector<double>(cols.size(), std::nan("")));
    for (const auto& c : table.cells) {
      const auto r = static_cast<std::size_t>(std::find(rows.begin(), rows.end(), c.values[0]) - rows.begin());
      const auto k = static_cast<std::size_t>(std::find(cols.begin(), cols.end(), c.values[1]) - cols.begin());
      map.values[r][k] = c.summary.*metric.field;
    }
    map.higher_is_better = metric.higher_is_better;
    viz::renderHeatMap(map, dir / metric.file);
    written.push_back(dir / metric.file);
  }
  return written;
}

}  // namespace barn::cli
