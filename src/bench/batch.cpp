#include "barn/bench/batch.hpp"

#include <omp.h>

#include "barn/core/rng.hpp"

namespace barn::bench {

std::uint64_t episodeSeed(std::uint64_t run_seed, int world_id, int trial) {
  return core::mixSeed(run_seed, static_cast<std::uint64_t>(world_id), static_cast<std::uint64_t>(trial));
}

std::vector<EpisodeResult> runBatch(const BatchSpec& spec, const ProgressCallback& progress) {
  sim::prepareForThreads();
  // Shared, immutable per-world data, built once before the parallel region.
  std::vector<sim::ObstacleField> fields;
  fields.reserve(spec.worlds.size());
  for (const auto& world : spec.worlds) fields.push_back(sim::ObstacleField::fromWorld(world));

  const long trials = spec.trials;
  const long total = static_cast<long>(spec.worlds.size()) * trials;
  std::vector<EpisodeResult> results(static_cast<std::size_t>(total));
  std::size_t done = 0;
  const int threads = spec.jobs > 0 ? spec.jobs : omp_get_max_threads();

  // Dynamic schedule: episode lengths vary from seconds to the 100 s timeout.
#pragma omp parallel for schedule(dynamic, 1) num_threads(threads)
  for (long index = 0; index < total; ++index) {
    const auto w = static_cast<std::size_t>(index / trials);
    const int trial = static_cast<int>(index % trials);
    const core::WorldSpec& world = spec.worlds[w];
    EpisodeResult result;
    try {
      auto controller = spec.make_controller();
      result = runEpisode(world, fields[w], *controller, spec.episode, episodeSeed(spec.seed, world.id, trial),
                          spec.record_trajectories);
    } catch (const std::exception& e) {
      result.world_id = world.id;
      result.outcome = Outcome::Error;
      result.error = e.what();
    }
    result.trial = trial;
    results[static_cast<std::size_t>(index)] = std::move(result);
#pragma omp critical(barn_batch_progress)
    {
      ++done;
      if (progress) progress(results[static_cast<std::size_t>(index)], done, static_cast<std::size_t>(total));
    }
  }
  return results;
}

}  // namespace barn::bench
