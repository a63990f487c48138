// barn world info|render: look at one world file.

#include <cstdio>

#include <nlohmann/json.hpp>

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

// Members in the order written (nlohmann writes a non-finite double as null).
using Json = nlohmann::ordered_json;

Json cellJson(core::Cell cell) { return Json::array({cell.row, cell.col}); }

Json metricsJson(const core::DifficultyMetrics& metrics) {
  Json json = Json::object();
  const auto values = metrics.toArray();
  for (std::size_t k = 0; k < values.size(); ++k) json[std::string(core::DifficultyMetrics::kNames[k])] = values[k];
  return json;
}

std::string worldJson(const core::WorldSpec& w, const core::Protocol& protocol) {
  Json path = Json::array();
  for (const auto& cell : w.path) path.push_back(cellJson(cell));
  const Json json{{"id", w.id},
                  {"source", std::string(core::toString(w.source))},
                  {"seed", w.seed ? Json(*w.seed) : Json(nullptr)},
                  {"fill_pct", w.fill_pct},
                  {"smooth_iter", w.smooth_iter},
                  {"grid", w.grid.toRowStrings()},
                  {"start_cell", cellJson(w.start_cell)},
                  {"goal_cell", cellJson(w.goal_cell)},
                  {"path", std::move(path)},
                  {"protocol", std::string(core::toString(protocol.name))},
                  {"path_length_m", core::referencePathLength(w.path, protocol)},
                  {"optimal_time_s", core::optimalTime(w.path, protocol)},
                  {"metrics", metricsJson(w.metrics)},
                  {"norm_metrics", metricsJson(w.norm_metrics)}};
  return json.dump();
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
