#include "barn/bench/batch.hpp"

#include <omp.h>

#include "barn/core/rng.hpp"

namespace barn::bench {

std::uint64_t episodeSeed(std::uint64_t run_seed, int world_id, int trial) {
  return core::mixSeed(run_seed, static_cast<std::uint64_t>(world_id), static_cast<std::uint64_t>(trial));
}

std::vector<std::size_t> shardEpisodes(std::size_t total, int index, int count) {
  std::vector<std::size_t> episodes;
  for (std::size_t i = static_cast<std::size_t>(index - 1); i < total; i += static_cast<std::size_t>(count))
    episodes.push_back(i);
  return episodes;
}

std::vector<EpisodeResult> runBatch(const BatchSpec& spec, const ProgressCallback& progress) {
  sim::prepareForThreads();
  // Shared, immutable per-world data, built once before the parallel region.
  std::vector<sim::ObstacleField> fields;
  fields.reserve(spec.worlds.size());
  for (const auto& world : spec.worlds) fields.push_back(sim::ObstacleField::fromWorld(world));

  const std::size_t trials = static_cast<std::size_t>(spec.trials);
  std::vector<std::size_t> indices;
  if (spec.selected) {
    indices = *spec.selected;
  } else {
    for (std::size_t i = 0; i < spec.worlds.size() * trials; ++i) indices.push_back(i);
  }
  const long total = static_cast<long>(indices.size());
  std::vector<EpisodeResult> results(indices.size());
  std::vector<char> ran(indices.size(), 0);
  std::size_t done = 0;
  const int threads = spec.jobs > 0 ? spec.jobs : omp_get_max_threads();

  // Dynamic schedule: episode lengths vary from seconds to the 100 s timeout.
#pragma omp parallel for schedule(dynamic, 1) num_threads(threads)
  for (long k = 0; k < total; ++k) {
    if (spec.stop && spec.stop->load()) continue;
    const std::size_t index = indices[static_cast<std::size_t>(k)];
    const std::size_t w = index / trials;
    const int trial = static_cast<int>(index % trials);
    const core::WorldSpec& world = spec.worlds[w];
    EpisodeResult result;
    try {
      auto controller = spec.make_controller();
      result = runEpisode(world, fields[w], *controller, spec.episode, episodeSeed(spec.seed, world.id, trial),
                          spec.record_trajectories);
    } catch (const std::exception& e) {
      result.world_id = world.id;
      result.seed = episodeSeed(spec.seed, world.id, trial);
      result.outcome = Outcome::Error;
      result.error = e.what();
    }
    result.trial = trial;
    results[static_cast<std::size_t>(k)] = std::move(result);
    ran[static_cast<std::size_t>(k)] = 1;
#pragma omp critical(barn_batch_progress)
    {
      ++done;
      if (progress) progress(results[static_cast<std::size_t>(k)], done, static_cast<std::size_t>(total));
    }
  }
  std::vector<EpisodeResult> finished;
  for (std::size_t k = 0; k < results.size(); ++k)
    if (ran[k]) finished.push_back(std::move(results[k]));
  return finished;
}

}  // namespace barn::bench
