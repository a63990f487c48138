#pragma once
/// Many episodes in parallel: every (world, trial) of a run, with OpenMP.
///
/// The only OpenMP in barnbench lives here. Each episode owns its simulator, controller and
/// RNG; its seed depends on (run seed, world id, trial) only, and results are stored by index,
/// so the output is identical whatever the thread count and schedule.

#include <atomic>
#include <cstdint>
#include <functional>
#include <optional>
#include <vector>

#include "barn/bench/episode.hpp"
#include "barn/controllers/registry.hpp"

namespace barn::bench {

/// What a batch runs: the experiment (worlds, trials, seed, episode config, controller) and
/// which of its episodes. Together with the episode code this fixes every result.
struct BatchSpec {
  std::vector<core::WorldSpec> worlds;
  int trials = 1;
  std::uint64_t seed = 0;          // run seed
  EpisodeConfig episode;
  controllers::ControllerFactory make_controller;
  bool record_trajectories = false;
  /// Episode indices to run (index = world position * trials + trial), ascending; unset = all.
  /// Shards and resumed runs pass their subset (which may be empty).
  std::optional<std::vector<std::size_t>> selected;
};

/// How batches are run: never changes a result, only how fast they come and whether the run
/// stops early.
struct BatchExecution {
  int jobs = 0;  // threads; 0 = all cores
  /// Set (e.g. by a SIGINT handler) to stop starting new episodes; running ones finish.
  const std::atomic<bool>* stop = nullptr;
};

/// The episode indices of shard `index` (1-based) of `count`: every count-th episode,
/// starting at index - 1, so shards interleave and balance easy and hard worlds.
std::vector<std::size_t> shardEpisodes(std::size_t total, int index, int count);

/// Seed of one episode: independent of thread scheduling.
std::uint64_t episodeSeed(std::uint64_t run_seed, int world_id, int trial);

/// Called after each finished episode (serialised, in completion order).
using ProgressCallback = std::function<void(const EpisodeResult& finished, std::size_t done, std::size_t total)>;

/// Runs the selected episodes; results ordered by (world order in spec, trial). Episodes
/// skipped because `stop` was set are missing from the result.
std::vector<EpisodeResult> runBatch(const BatchSpec& spec, const BatchExecution& execution = {},
                                    const ProgressCallback& progress = {});

/// Called after each finished episode of a multi-batch, with the index of its batch.
using MultiProgressCallback =
    std::function<void(std::size_t batch, const EpisodeResult& finished, std::size_t done, std::size_t total)>;

/// Runs the episodes of several batches (e.g. the cells of a parameter sweep) in one parallel
/// pool, so no core idles at the end of a batch. Results per batch, ordered as runBatch orders
/// them.
std::vector<std::vector<EpisodeResult>> runBatches(const std::vector<const BatchSpec*>& specs,
                                                   const BatchExecution& execution = {},
                                                   const MultiProgressCallback& progress = {});

}  // namespace barn::bench
