// barn world info|render: look at one world file.

#include <cstdio>

#include "barn/core/json_writer.hpp"
#include "barn/core/protocol.hpp"
#include "barn/core/world_file.hpp"
#include "barn/viz/world_render.hpp"
#include "commands.hpp"

namespace barn::cli {

namespace {

struct WorldOptions {
  std::string file;
  bool json = false;
  std::string output;
  std::string protocol = "barn2023";
  double pixels_per_metre = viz::RenderOptions{}.pixels_per_metre;
};

void writeCell(core::JsonWriter& json, core::Cell cell) { json.beginArray().value(cell.row).value(cell.col).endArray(); }

void writeMetrics(core::JsonWriter& json, const core::DifficultyMetrics& metrics) {
  json.beginObject();
  const auto values = metrics.toArray();
  for (std::size_t k = 0; k < values.size(); ++k) json.key(core::DifficultyMetrics::kNames[k]).value(values[k]);
  json.endObject();
}

std::string worldJson(const core::WorldSpec& w, const core::Protocol& protocol) {
  core::JsonWriter json;
  json.beginObject();
  json.key("id").value(w.id);
  json.key("source").value(core::toString(w.source));
  json.key("seed");
  if (w.seed) json.value(*w.seed); else json.null();
  json.key("fill_pct").value(w.fill_pct);
  json.key("smooth_iter").value(w.smooth_iter);
  json.key("grid").beginArray();
  for (const auto& row : w.grid.toRowStrings()) json.value(row);
  json.endArray();
  json.key("start_cell");
  writeCell(json, w.start_cell);
  json.key("goal_cell");
  writeCell(json, w.goal_cell);
  json.key("path").beginArray();
  for (const auto& cell : w.path) writeCell(json, cell);
  json.endArray();
  json.key("protocol").value(std::string(core::toString(protocol.name)));
  json.key("path_length_m").value(core::referencePathLength(w.path, protocol));
  json.key("optimal_time_s").value(core::optimalTime(w.path, protocol));
  json.key("metrics");
  writeMetrics(json, w.metrics);
  json.key("norm_metrics");
  writeMetrics(json, w.norm_metrics);
  json.endObject();
  return json.str();
}

void printWorldText(const core::WorldSpec& w, const core::Protocol& protocol) {
  std::printf("world %d (%s", w.id, std::string(core::toString(w.source)).c_str());
  if (w.seed) std::printf(", seed %llu", static_cast<unsigned long long>(*w.seed));
  std::printf(")\n  generator      fill %.2f, smoothing %d\n", w.fill_pct, w.smooth_iter);
  std::printf("  start -> goal  (%d, %d) -> (%d, %d), %zu path cells\n", w.start_cell.row, w.start_cell.col,
              w.goal_cell.row, w.goal_cell.col, w.path.size());
  std::printf("  %s  reference path %.4f m, optimal time %.4f s\n", std::string(core::toString(protocol.name)).c_str(),
              core::referencePathLength(w.path, protocol), core::optimalTime(w.path, protocol));
  const auto raw = w.metrics.toArray();
  const auto norm = w.norm_metrics.toArray();
  for (std::size_t k = 0; k < raw.size(); ++k)
    std::printf("  %-25s %8.4f  (z %+.3f)\n", std::string(core::DifficultyMetrics::kNames[k]).c_str(), raw[k], norm[k]);
  for (const auto& row : w.grid.toRowStrings()) {
    std::string line;
    for (char ch : row) line += ch == '1' ? '#' : '.';
    std::printf("  %s\n", line.c_str());
  }
}

}  // namespace

void addWorldCommand(CLI::App& app, CommandContext& /*context*/) {
  auto options = std::make_shared<WorldOptions>();
  CLI::App* world = app.add_subcommand("world", "Inspect a world file");
  world->require_subcommand(1);

  CLI::App* info = world->add_subcommand("info", "Print a world's cells, path, optimal time and metrics");
  info->add_option("file", options->file, "World file (.yaml)")->required();
  info->add_flag("--json", options->json, "Print one JSON object");
  info->add_option("--protocol", options->protocol, "Protocol for path length and OT (barn2023, barn2024)")
      ->capture_default_str();
  info->callback([options] {
    const core::Protocol protocol = core::protocolPreset(options->protocol);
    const core::WorldSpec w = core::readWorldFile(options->file);
    if (options->json) std::printf("%s\n", worldJson(w, protocol).c_str());
    else printWorldText(w, protocol);
  });

  CLI::App* render =
      world->add_subcommand("render", "Draw a world (grid, cylinders, start, goal, A* path) as PNG, PDF or SVG");
  render->add_option("file", options->file, "World file (.yaml)")->required();
  render->add_option("-o,--output", options->output, "Image to write; .png, .pdf or .svg (the extension chooses)")
      ->required();
  render->add_option("--protocol", options->protocol, "Protocol for start and goal (barn2023, barn2024)")
      ->capture_default_str();
  render->add_option("--scale", options->pixels_per_metre, "Pixels (PNG) or points (PDF, SVG) per metre")
      ->check(CLI::Range(10.0, 1000.0))
      ->capture_default_str();
  render->callback([options] {
    const core::Protocol protocol = core::protocolPreset(options->protocol);
    const core::WorldSpec w = core::readWorldFile(options->file);
    viz::RenderOptions render_options;
    render_options.pixels_per_metre = options->pixels_per_metre;
    viz::renderWorld(w, protocol, options->output, render_options);
    std::printf("wrote %s\n", options->output.c_str());
  });
}

}  // namespace barn::cli
