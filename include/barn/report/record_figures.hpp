#pragma once
/// The figures of one run record, shared by `barn plot` and `barn report`: the per-world score
/// bars, and episodes re-simulated from the record and drawn on their world.

#include <filesystem>
#include <string>
#include <vector>

#include "barn/bench/episode.hpp"
#include "barn/bench/run_record.hpp"
#include "barn/controllers/registry.hpp"
#include "barn/viz/plots.hpp"

namespace barn::report {

/// The record's per-world score bars (mean over trials, min-to-max whiskers, outcome strip),
/// worlds ordered by `by` (difficulty, id or a metric name), written to `output` (.png, .pdf or
/// .svg).
void renderScoreBars(const std::filesystem::path& record, const std::string& by, const std::filesystem::path& output);

/// A record's episodes: their recorded trajectories where the record has them (trajectories/),
/// else re-simulated (the same seed gives the same episode bit for bit).
class RecordReplay {
 public:
  /// InputError for an imported record (nothing to re-simulate).
  explicit RecordReplay(const std::filesystem::path& record);
  /// Trial `trial` of `world` (one of the record's), with its trajectory, and whether that was
  /// recorded (else re-run). InputError if it was not recorded and cannot be re-run (a Python
  /// class).
  struct Episode {
    bench::EpisodeResult result;
    bool recorded = false;  // a recorded row keeps the contact point, not the pose at contact
  };
  Episode episode(const core::WorldSpec& world, const sim::ObstacleField& field, int trial) const;
  /// Whether episode() can give trial `trial` of world `world_id`: recorded, or re-runnable.
  bool canDraw(int world_id, int trial) const;

  /// Draws the `trials` of world `world_id` (InputError if either is not the record's) on the
  /// world: paths coloured by state or by trial, each trial's outcome, AT and score in the
  /// legend, the robot's outline at a collision.
  void renderWorld(int world_id, const std::vector<int>& trials, viz::TrajectoryColouring colouring,
                   const std::filesystem::path& output) const;

  const bench::RunManifest& manifest() const { return manifest_; }

 private:
  std::filesystem::path record_;
  bench::RunManifest manifest_;
  std::vector<core::WorldSpec> worlds_;
  bool rerunnable_ = true;                                    // false for a Python class's record
  mutable controllers::ControllerFactory make_controller_;  // made at the first re-run
  mutable std::vector<bench::EpisodeResult> rows_;         // read at the first recorded trajectory
  bench::EpisodeConfig episode_;
};

}  // namespace barn::report
