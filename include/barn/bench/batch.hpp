#pragma once
/// Many episodes in parallel: every (world, trial) of a run, with OpenMP.
///
/// The only OpenMP in barnbench lives here. Each episode owns its simulator, controller and
/// RNG; its seed depends on (run seed, world id, trial) only, and results are stored by index,
/// so the output is identical whatever the thread count and schedule.

#include <cstdint>
#include <functional>
#include <vector>

#include "barn/bench/episode.hpp"
#include "barn/controllers/registry.hpp"

namespace barn::bench {

struct BatchSpec {
  std::vector<core::WorldSpec> worlds;
  int trials = 1;
  std::uint64_t seed = 0;          // run seed
  int jobs = 0;                    // threads; 0 = all cores
  EpisodeConfig episode;
  controllers::ControllerFactory make_controller;
  bool record_trajectories = false;
};

/// Seed of one episode: independent of thread scheduling.
std::uint64_t episodeSeed(std::uint64_t run_seed, int world_id, int trial);

/// Called after each finished episode (serialised, in completion order).
using ProgressCallback = std::function<void(const EpisodeResult& finished, std::size_t done, std::size_t total)>;

/// Runs every episode; results ordered by (world order in spec, trial).
std::vector<EpisodeResult> runBatch(const BatchSpec& spec, const ProgressCallback& progress = {});

}  // namespace barn::bench
