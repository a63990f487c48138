// barn plot: pictures of one run record — per-world scores ordered by difficulty, and the
// trajectories of chosen worlds (re-simulated from the record: the same seed drives the same
// episode bit for bit), coloured by controller state or by trial; and the stack parameters a
// controller set during an episode (from its trajectory file).

#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <filesystem>
#include <map>
#include <sstream>
#include <string>
#include <vector>

#include "barn/core/errors.hpp"
#include "barn/core/text_io.hpp"
#include "barn/viz/line_plot.hpp"

#include "barn/viz/image_format.hpp"
#include "commands.hpp"
#include "barn/report/params_plot.hpp"
#include "barn/report/record_figures.hpp"

namespace barn::cli {

namespace {

namespace fs = std::filesystem;

struct PlotOptions {
  std::string record;
  std::string output;
  std::string by = "difficulty";
  std::vector<int> worlds;
  std::vector<int> trials;
  std::string colour = "state";
  std::string trajectory_file;
  std::vector<std::string> keys;
  std::string title;
};

// traj.pdf -> traj_world_<id>.pdf beside it: one figure per world of a several-world request.
fs::path perWorldFile(const fs::path& output, int world_id) {
  fs::path file = output;
  file.replace_filename(output.stem().string() + "_world_" + std::to_string(world_id) + output.extension().string());
  return file;
}

// A CSV file with a header row: its columns by name (values as numbers; "nan" or an empty
// cell is NaN, which breaks a line).
std::map<std::string, std::vector<double>> readCsvColumns(const std::string& path, std::vector<std::string>& names) {
  std::istringstream in(core::readTextFile(path));
  std::string line;
  const auto split = [](const std::string& text) {
    std::vector<std::string> cells;
    std::string cell;
    std::istringstream row(text);
    while (std::getline(row, cell, ',')) cells.push_back(cell);
    if (!text.empty() && text.back() == ',') cells.emplace_back();
    return cells;
  };
  if (!std::getline(in, line) || line.empty()) throw core::InputError(path + ": empty (expected a header row of column names)");
  if (line.back() == '\r') line.pop_back();
  names = split(line);
  std::map<std::string, std::vector<double>> columns;
  for (const std::string& name : names) columns[name];
  int number = 1;
  while (std::getline(in, line)) {
    ++number;
    if (!line.empty() && line.back() == '\r') line.pop_back();
    if (line.empty()) continue;
    const std::vector<std::string> cells = split(line);
    if (cells.size() != names.size())
      throw core::InputError(path + ":" + std::to_string(number) + ": " + std::to_string(cells.size()) + " cells, the header has " +
                             std::to_string(names.size()));
    for (std::size_t k = 0; k < cells.size(); ++k) {
      char* end = nullptr;
      const double value = cells[k].empty() ? std::nan("") : std::strtod(cells[k].c_str(), &end);
      if (!cells[k].empty() && end != cells[k].c_str() + cells[k].size())
        throw core::InputError(path + ":" + std::to_string(number) + ": column " + names[k] + ": '" + cells[k] +
                               "' is not a number");
      columns[names[k]].push_back(value);
    }
  }
  return columns;
}

struct CurveOptions {
  std::string csv;
  std::string output;
  std::string x = "steps";
  std::vector<std::string> y;
  std::string title;
  std::string y_label;
  double y_min = std::nan("");
  double y_max = std::nan("");
};

void renderCurve(const CurveOptions& o) {
  std::vector<std::string> names;
  const auto columns = readCsvColumns(o.csv, names);
  const auto column = [&](const std::string& name) -> const std::vector<double>& {
    const auto it = columns.find(name);
    if (it == columns.end()) {
      std::string known;
      for (const std::string& n : names) known += (known.empty() ? "" : ", ") + n;
      throw core::InputError(o.csv + ": no column '" + name + "' (columns: " + known + ")");
    }
    return it->second;
  };
  viz::LinePlot plot;
  plot.title = o.title.empty() ? std::filesystem::path(o.csv).filename().string() : o.title;
  plot.x_label = o.x;
  plot.y_label = o.y_label;
  plot.y_min = o.y_min;
  plot.y_max = o.y_max;
  for (const std::string& name : o.y) plot.series.push_back({name, column(o.x), column(name), {}, {}, false});
  viz::renderLinePlot(plot, o.output);
}

}  // namespace

void addPlotCommand(CLI::App& app, CommandContext& /*context*/) {
  auto options = std::make_shared<PlotOptions>();
  CLI::App* plot = app.add_subcommand("plot", "Plots of a run record");
  plot->require_subcommand(1);

  CLI::App* scores = plot->add_subcommand(
      "scores",
      "Per-world score bars, easiest to hardest: the bar is the world's mean score over its trials, the whisker the "
      "min to max of its trials' scores, the strip under it the trials' outcomes (success, collision, timeout, "
      "error); the title names the world set and the protocol");
  scores->add_option("record", options->record, "Run record folder")->required();
  scores->add_option("-o,--output", options->output, "Image to write; .png, .pdf or .svg (the extension chooses)")
      ->required();
  scores->add_option("--by", options->by, "Order: difficulty (signed sum of the z-scored metrics), id, or a metric")
      ->capture_default_str();
  scores->callback([options] {
    viz::imageFormatFor(options->output);  // a bad extension is refused before any reading
    report::renderScoreBars(options->record, options->by, options->output);
    std::printf("wrote %s\n", options->output.c_str());
  });

  auto curve_options = std::make_shared<CurveOptions>();
  CLI::App* curve = plot->add_subcommand(
      "curve", "Columns of a CSV file (a header row of names, then numbers) against one of them, e.g. a learning "
               "curve written by tools/train_e2e.py");
  curve->add_option("csv", curve_options->csv, "CSV file")->required();
  curve->add_option("-o,--output", curve_options->output, "Image to write; .png, .pdf or .svg (the extension chooses)")
      ->required();
  curve->add_option("--x", curve_options->x, "Column on the x axis")->capture_default_str();
  curve->add_option("--y", curve_options->y, "Column(s) to draw, one line each")->required()->delimiter(',');
  curve->add_option("--title", curve_options->title, "Title (default: the file's name)");
  curve->add_option("--y-label", curve_options->y_label, "Label of the y axis");
  curve->add_option("--y-min", curve_options->y_min, "Bottom of the y axis (default: automatic)");
  curve->add_option("--y-max", curve_options->y_max, "Top of the y axis (default: automatic)");
  curve->callback([curve_options] {
    viz::imageFormatFor(curve_options->output);
    renderCurve(*curve_options);
    std::printf("wrote %s\n", curve_options->output.c_str());
  });

  CLI::App* trajectory = plot->add_subcommand(
      "trajectory",
      "Re-simulate and draw episodes of chosen worlds: each trial's path coloured by controller state or by trial, "
      "its outcome, time (AT) and score in the legend, the robot's collision outline at the pose of any contact");
  trajectory->add_option("record", options->record, "Run record folder")->required();
  trajectory->add_option("--world", options->worlds, "World id(s)")->required()->delimiter(',');
  trajectory->add_option("--trial", options->trials, "Trial(s) (default: every trial of the record)")->delimiter(',');
  trajectory
      ->add_option("-o,--output", options->output,
                   "Image to write; .png, .pdf or .svg (the extension chooses). With several worlds, one file per "
                   "world: traj.pdf -> traj_world_3.pdf, ...")
      ->required();
  trajectory
      ->add_option("--colour", options->colour,
                   "state: segments in the controller state's colour, trials told apart by dashes; trial: one colour "
                   "per trial")
      ->check(CLI::IsMember({"state", "trial"}))
      ->capture_default_str();
  trajectory->callback([options] {
    viz::imageFormatFor(options->output);  // a bad extension is refused before any simulation
    const report::RecordReplay replay(options->record);
    std::vector<int> trials = options->trials;
    if (trials.empty())
      for (int t = 0; t < replay.manifest().trials; ++t) trials.push_back(t);
    const viz::TrajectoryColouring colouring =
        options->colour == "trial" ? viz::TrajectoryColouring::ByTrial : viz::TrajectoryColouring::ByState;
    for (int id : options->worlds) {
      const fs::path file = options->worlds.size() == 1 ? fs::path(options->output) : perWorldFile(options->output, id);
      replay.renderWorld(id, trials, colouring, file);
      std::printf("wrote %s\n", file.c_str());
    }
  });

  CLI::App* params = plot->add_subcommand(
      "params",
      "The stack parameters a controller set during one episode (the params column of a trajectory file written by "
      "`barn run --trajectories`): one panel per parameter, its value against time as a step line");
  params->add_option("trajectory", options->trajectory_file, "Trajectory file, e.g. RECORD/trajectories/world_0_trial_0.csv")
      ->required();
  params->add_option("--keys", options->keys, "Parameters to draw, in this order (default: every one the file holds)")
      ->delimiter(',');
  params->add_option("--title", options->title, "Title above the first panel");
  params->add_option("-o,--output", options->output, "Image to write; .png, .pdf or .svg (the extension chooses)")
      ->required();
  params->callback([options] {
    viz::imageFormatFor(options->output);
    report::renderParameterPlot(options->trajectory_file, options->keys, options->title, options->output);
    std::printf("wrote %s\n", options->output.c_str());
  });
}

}  // namespace barn::cli
