// barn plot: pictures of one run record — per-world scores ordered by difficulty, and the
// trajectories of chosen worlds (re-simulated from the record: the same seed drives the same
// episode bit for bit), coloured by controller state or by trial.

#include <algorithm>
#include <cstdio>
#include <map>

#include "barn/bench/compare.hpp"
#include "barn/bench/episode.hpp"
#include "barn/bench/report.hpp"
#include "barn/bench/results_io.hpp"
#include "barn/bench/run_record.hpp"
#include "barn/controllers/registry.hpp"
#include "barn/core/config.hpp"
#include "barn/core/errors.hpp"
#include "barn/viz/image_format.hpp"
#include "barn/viz/plots.hpp"
#include "commands.hpp"
#include "run_session.hpp"

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
};

// A difficulty index per world: the sum of the normalised metrics signed so that larger means
// harder (less clearance, visibility and width; more dispersion and tortuosity).
double difficultyIndex(const core::WorldSpec& w) {
  const auto& z = w.norm_metrics;
  return -z.closest_wall - z.avg_visibility + z.dispersion - z.characteristic_dimension + z.tortuosity;
}

double orderKey(const core::WorldSpec& w, const std::string& by) {
  if (by == "difficulty") return difficultyIndex(w);
  if (by == "id") return w.id;
  const auto values = w.norm_metrics.toArray();
  for (std::size_t k = 0; k < values.size(); ++k)
    if (by == core::DifficultyMetrics::kNames[k]) {
      // Larger is harder for dispersion and tortuosity, easier for the others.
      const bool harder_when_larger = k == 2 || k == 4;
      return harder_when_larger ? values[k] : -values[k];
    }
  throw core::InputError("--by '" + by + "': expected difficulty, id or a metric name");
}

// "300 worlds of worlds/ (barnbench-generated)": how many of the record's worlds are shown,
// which folder they are in and where they came from (bench::worldSetName), so a figure of the
// official BARN worlds is not mistaken for one of barnbench's own.
std::string worldSetText(const bench::RunManifest& manifest, const std::vector<core::WorldSpec>& worlds,
                         std::size_t shown) {
  const std::string folder = fs::path(manifest.worlds_folder).lexically_normal().filename().string();
  return std::to_string(shown) + (shown == 1 ? " world of " : " worlds of ") + (folder.empty() ? "?" : folder) +
         "/ (" + bench::worldSetName(worlds) + ")";
}

// traj.pdf -> traj_world_<id>.pdf beside it: one figure per world of a several-world request.
fs::path perWorldFile(const fs::path& output, int world_id) {
  fs::path file = output;
  file.replace_filename(output.stem().string() + "_world_" + std::to_string(world_id) + output.extension().string());
  return file;
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
    const bench::RunManifest manifest = bench::readManifest(fs::path(options->record) / bench::kManifestFile);
    const auto worlds = bench::loadManifestWorlds(manifest);
    const auto results = bench::readEpisodesCsv(fs::path(options->record) / bench::kEpisodesFile);
    std::map<int, bench::WorldStats> stats;
    for (const bench::WorldStats& w : bench::perWorldStats(results)) stats[w.world_id] = w;
    std::map<int, std::pair<double, double>> range;  // world -> (worst, best) trial score
    for (const auto& r : results) {
      const auto [it, fresh] = range.try_emplace(r.world_id, r.score, r.score);
      if (!fresh) it->second = {std::min(it->second.first, r.score), std::max(it->second.second, r.score)};
    }
    std::vector<const core::WorldSpec*> order;
    for (const auto& w : worlds)
      if (stats.count(w.id)) order.push_back(&w);
    std::stable_sort(order.begin(), order.end(),
                     [&](const auto* a, const auto* b) { return orderKey(*a, options->by) < orderKey(*b, options->by); });
    const std::string protocol =
        core::readConfig<bench::EpisodeConfig>(core::ConfigNode::parseString(manifest.episode_config, "manifest")).protocol;
    const core::Protocol preset = core::protocolPreset(protocol);

    viz::WorldBars bars;
    bars.title = manifest.controller + ": mean score per world";
    char max_score[32];
    std::snprintf(max_score, sizeof max_score, "%g", preset.maxScore());
    bars.subtitle = worldSetText(manifest, worlds, order.size()) + " x " + std::to_string(manifest.trials) +
                    (manifest.trials == 1 ? " trial, " : " trials, ") + protocol + " (max score " + max_score + ")";
    if (!manifest.source.empty())
      bars.subtitle += "; results imported from " + fs::path(manifest.source).filename().string();
    bars.y_label = "mean score";
    bars.x_label = "worlds, easiest to hardest (by " + options->by + ")";
    // Whiskers only when there is a spread to show: one trial is its own minimum and maximum.
    const bool whiskers = manifest.trials > 1;
    if (whiskers) bars.whisker_label = "min to max of its " + std::to_string(manifest.trials) + " trials";
    for (const auto* w : order) {
      const bench::WorldStats& s = stats[w->id];
      bars.labels.push_back(std::to_string(w->id));
      bars.values.push_back(s.mean_score);
      bars.outcomes.push_back({s.successes, s.collisions, s.timeouts, s.errors});
      if (whiskers) {
        bars.low.push_back(range[w->id].first);
        bars.high.push_back(range[w->id].second);
      }
    }
    bars.y_max = preset.maxScore();
    bars.reference_lines = {preset.maxScore(), preset.minSuccessScore()};
    viz::renderWorldBars(bars, options->output);
    std::printf("wrote %s\n", options->output.c_str());
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
    const bench::RunManifest manifest = bench::readManifest(fs::path(options->record) / bench::kManifestFile);
    if (!manifest.source.empty())
      throw core::InputError(options->record + ": imported from " + manifest.source +
                             " (barn import-out); its episodes cannot be re-simulated");
    const auto worlds = bench::loadManifestWorlds(manifest);
    const auto make = controllers::makeControllerFactory(core::ConfigNode::parseString(manifest.controller_config, "manifest"));
    const bench::EpisodeConfig episode =
        bench::validatedEpisodeConfig(core::ConfigNode::parseString(manifest.episode_config, "manifest"), options->record);
    const core::Protocol protocol = core::protocolPreset(episode.protocol);
    std::vector<int> trials = options->trials;
    if (trials.empty())
      for (int t = 0; t < manifest.trials; ++t) trials.push_back(t);
    for (int t : trials)
      if (t < 0 || t >= manifest.trials) throw core::InputError("--trial " + std::to_string(t) + ": the record has trials 0.." + std::to_string(manifest.trials - 1));
    for (int id : options->worlds) {
      const auto it = std::find_if(worlds.begin(), worlds.end(), [id](const auto& w) { return w.id == id; });
      if (it == worlds.end()) throw core::InputError("--world " + std::to_string(id) + ": not a world of the record");
      const sim::ObstacleField field = sim::ObstacleField::fromWorld(*it);
      std::vector<viz::TrajectoryOverlay> overlays;
      for (int t : trials) {
        auto controller = make();
        const bench::EpisodeResult r = bench::runEpisode(*it, field, *controller, episode,
                                                         bench::episodeSeed(manifest.seed, id, t), true);
        viz::TrajectoryOverlay overlay;
        overlay.label = "trial " + std::to_string(t) + "  " + std::string(bench::toString(r.outcome));
        char detail[64];
        std::snprintf(detail, sizeof detail, "%.1f s  score %.3f", r.actual_time, r.score);
        overlay.detail = detail;
        for (const auto& s : r.trajectory) overlay.points.push_back({s.pose.x, s.pose.y, s.state});
        if (r.collision) {
          // The samples are control ticks; the contact comes after the last, so the line is
          // carried on to the pose of contact, where the outline is drawn.
          const std::string state = r.trajectory.empty() ? std::string() : r.trajectory.back().state;
          overlay.points.push_back({r.collision->pose.x, r.collision->pose.y, state});
          overlay.collided = true;
          overlay.collision_x = r.collision->point.x();
          overlay.collision_y = r.collision->point.y();
          overlay.collision_pose = r.collision->pose;
        }
        overlays.push_back(std::move(overlay));
      }
      const fs::path file = options->worlds.size() == 1 ? fs::path(options->output) : perWorldFile(options->output, id);
      viz::TrajectoryStyle style;
      style.colouring = options->colour == "trial" ? viz::TrajectoryColouring::ByTrial : viz::TrajectoryColouring::ByState;
      style.robot_outline = episode.robot.collisionRects();
      viz::renderTrajectories(*it, protocol, overlays, file, style);
      std::printf("wrote %s\n", file.c_str());
    }
  });
}

}  // namespace barn::cli
