#include "barn/report/record_figures.hpp"

#include <algorithm>
#include <cstdio>
#include <map>

#include "barn/bench/batch.hpp"
#include "barn/bench/report.hpp"
#include "barn/bench/record_session.hpp"
#include "barn/bench/results_io.hpp"
#include "barn/core/config.hpp"
#include "barn/core/errors.hpp"
#include "barn/core/protocol.hpp"
#include "barn/sim/obstacle_field.hpp"

namespace barn::report {

namespace {

namespace fs = std::filesystem;

// A normalised metric signed so that larger means harder.
double harderWhenLarger(const core::WorldSpec& w, std::size_t k) {
  const double value = w.norm_metrics.toArray()[k];
  return core::DifficultyMetrics::kInfo[k].harder_when_larger ? value : -value;
}

// A difficulty index per world: the sum of the normalised metrics, each signed so that larger
// means harder (less clearance, visibility and width; more dispersion and tortuosity).
double difficultyIndex(const core::WorldSpec& w) {
  double sum = 0.0;
  for (std::size_t k = 0; k < core::DifficultyMetrics::kInfo.size(); ++k) sum += harderWhenLarger(w, k);
  return sum;
}

double orderKey(const core::WorldSpec& w, const std::string& by) {
  if (by == "difficulty") return difficultyIndex(w);
  if (by == "id") return w.id;
  for (std::size_t k = 0; k < core::DifficultyMetrics::kInfo.size(); ++k)
    if (by == core::DifficultyMetrics::kInfo[k].name) return harderWhenLarger(w, k);
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

}  // namespace

void renderScoreBars(const fs::path& record, const std::string& by, const fs::path& output) {
  const bench::CompleteRecord complete = bench::readCompleteRecord(record);
  const bench::RunManifest& manifest = complete.manifest;
  const auto worlds = bench::loadManifestWorlds(manifest);
  const std::vector<bench::EpisodeResult>& results = complete.episodes;
  const core::Protocol preset = core::protocolPreset(bench::recordProtocol(manifest, "manifest"));
  std::map<int, bench::WorldStats> stats;
  for (const bench::WorldStats& w : bench::perWorldStats(results, preset.maxScore())) stats[w.world_id] = w;
  std::map<int, std::pair<double, double>> range;  // world -> (worst, best) trial score
  for (const auto& r : results) {
    const auto [it, fresh] = range.try_emplace(r.world_id, r.score, r.score);
    if (!fresh) it->second = {std::min(it->second.first, r.score), std::max(it->second.second, r.score)};
  }
  std::vector<const core::WorldSpec*> order;
  for (const auto& w : worlds)
    if (stats.count(w.id)) order.push_back(&w);
  std::stable_sort(order.begin(), order.end(),
                   [&](const auto* a, const auto* b) { return orderKey(*a, by) < orderKey(*b, by); });
  const std::string protocol(core::toString(preset.name));

  viz::WorldBars bars;
  bars.title = manifest.controller + ": mean score per world";
  char max_score[32];
  std::snprintf(max_score, sizeof max_score, "%g", preset.maxScore());
  bars.subtitle = worldSetText(manifest, worlds, order.size()) + " x " + std::to_string(manifest.trials) +
                  (manifest.trials == 1 ? " trial, " : " trials, ") + protocol + " (max score " + max_score + ")";
  if (!manifest.source.empty())
    bars.subtitle += "; results imported from " + fs::path(manifest.source).filename().string();
  bars.y_label = "mean score";
  bars.x_label = "worlds, easiest to hardest (by " + by + ")";
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
  viz::renderWorldBars(bars, output);
}

RecordReplay::RecordReplay(const fs::path& record)
    : record_(record), manifest_(bench::readManifest(record / bench::kManifestFile)) {
  if (!manifest_.source.empty())
    throw core::InputError(record.string() + ": imported from " + manifest_.source +
                           " (barn import-out); its episodes cannot be re-simulated");
  worlds_ = bench::loadManifestWorlds(manifest_);
  episode_ = bench::validatedEpisodeConfig(core::ConfigNode::parseString(manifest_.episode_config, "manifest"), record.string());
  std::string type;
  core::ConfigNode::parseString(manifest_.controller_config, "manifest").child("type").read(type);
  rerunnable_ = type != "python";
}

bool RecordReplay::canDraw(int world_id, int trial) const {
  std::error_code ec;
  return rerunnable_ || fs::exists(record_ / "trajectories" / bench::trajectoryFileName(world_id, trial), ec);
}

RecordReplay::Episode RecordReplay::episode(const core::WorldSpec& world, const sim::ObstacleField& field, int trial) const {
  // A recorded trajectory (barn run --trajectories, or a Python run with trajectories=True) is
  // what happened; the episode's outcome comes from the record's rows.
  const fs::path recorded = record_ / "trajectories" / bench::trajectoryFileName(world.id, trial);
  std::error_code ec;
  if (fs::exists(recorded, ec)) {
    if (rows_.empty()) {
      rows_ = bench::readEpisodesCsv(record_ / bench::kEpisodesFile, true);
      if (rows_.empty()) rows_ = bench::readEpisodesCsv(record_ / bench::kJournalFile, true);
    }
    for (const bench::EpisodeResult& row : rows_)
      if (row.world_id == world.id && row.trial == trial) {
        Episode e{row, true};
        e.result.trajectory = bench::readTrajectoryCsv(recorded);
        return e;
      }
  }
  // Otherwise the same seed gives the same episode bit for bit: run it again.
  if (!rerunnable_)
    throw core::InputError(record_.string() + ": world " + std::to_string(world.id) + " trial " + std::to_string(trial) +
                           " has no recorded trajectory, and a Python class cannot be re-run from the record; "
                           "run it with barnbench.run(..., trajectories=True)");
  if (!make_controller_)
    make_controller_ = controllers::makeControllerFactory(core::ConfigNode::parseString(manifest_.controller_config, "manifest"));
  auto controller = make_controller_();
  return {bench::runEpisode(world, field, *controller, episode_, bench::episodeSeed(manifest_.seed, world.id, trial), true),
          false};
}

void RecordReplay::renderWorld(int world_id, const std::vector<int>& trials, viz::TrajectoryColouring colouring,
                               const fs::path& output) const {
  for (int t : trials)
    if (t < 0 || t >= manifest_.trials)
      throw core::InputError("--trial " + std::to_string(t) + ": the record has trials 0.." + std::to_string(manifest_.trials - 1));
  const int id = world_id;
  const auto it = std::find_if(worlds_.begin(), worlds_.end(), [id](const auto& w) { return w.id == id; });
  if (it == worlds_.end()) throw core::InputError("--world " + std::to_string(id) + ": not a world of the record");
  const core::Protocol protocol = bench::episodeProtocol(episode_);
  const sim::ObstacleField field = sim::ObstacleField::fromWorld(*it);
  std::vector<viz::TrajectoryOverlay> overlays;
  for (int t : trials) {
    const Episode replayed = episode(*it, field, t);
    const bench::EpisodeResult& r = replayed.result;
    viz::TrajectoryOverlay overlay;
    overlay.label = "trial " + std::to_string(t) + "  " + std::string(bench::toString(r.outcome));
    char detail[64];
    std::snprintf(detail, sizeof detail, "%.1f s  score %.3f", r.actual_time, r.score);
    overlay.detail = detail;
    for (const auto& s : r.trajectory) overlay.points.push_back({s.pose.x, s.pose.y, s.state});
    if (r.collision) {
      overlay.collided = true;
      overlay.collision_x = r.collision->point.x();
      overlay.collision_y = r.collision->point.y();
      // The samples are control ticks; the contact comes after the last, so the line is
      // carried on to the pose of contact, where the outline is drawn (known when the episode
      // was re-simulated; a recorded row keeps only the contact point).
      if (!replayed.recorded) {
        const std::string state = r.trajectory.empty() ? std::string() : r.trajectory.back().state;
        overlay.points.push_back({r.collision->pose.x, r.collision->pose.y, state});
        overlay.collision_pose = r.collision->pose;
      }
    }
    overlays.push_back(std::move(overlay));
  }
  viz::TrajectoryStyle style;
  style.colouring = colouring;
  style.robot_outline = episode_.robot.collisionRects();
  viz::renderTrajectories(*it, protocol, overlays, output, style);
}

}  // namespace barn::report
