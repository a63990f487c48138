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

std::vector<EpisodeResult> runBatch(const BatchSpec& spec, const BatchExecution& execution,
                                    const ProgressCallback& progress) {
  MultiProgressCallback multi;
  if (progress) multi = [&](std::size_t, const EpisodeResult& r, std::size_t done, std::size_t total) { progress(r, done, total); };
  return runBatches({&spec}, execution, multi).front();
}

std::vector<std::vector<EpisodeResult>> runBatches(const std::vector<const BatchSpec*>& specs,
                                                   const BatchExecution& execution,
                                                   const MultiProgressCallback& progress) {
  sim::prepareForThreads();
  // Shared, immutable per-world data, built once per batch before the parallel region.
  std::vector<std::vector<sim::ObstacleField>> fields(specs.size());
  // One flat list of (batch, episode index) for the pool.
  std::vector<std::pair<std::size_t, std::size_t>> jobs;
  for (std::size_t b = 0; b < specs.size(); ++b) {
    const BatchSpec& spec = *specs[b];
    for (const auto& world : spec.worlds) fields[b].push_back(sim::ObstacleField::fromWorld(world));
    const std::size_t trials = static_cast<std::size_t>(spec.trials);
    if (spec.selected) {
      for (std::size_t i : *spec.selected) jobs.emplace_back(b, i);
    } else {
      for (std::size_t i = 0; i < spec.worlds.size() * trials; ++i) jobs.emplace_back(b, i);
    }
  }
  // A controller that cannot run in this configuration fails the run now, not every episode.
  // (A factory that throws is reported by every episode, as its error row.)
  for (const BatchSpec* spec : specs) {
    std::unique_ptr<controllers::Controller> probe;
    try {
      probe = spec->make_controller();
    } catch (const std::exception&) {
      continue;
    }
    checkControllerFits(*probe, spec->episode);
  }
  const long total = static_cast<long>(jobs.size());
  std::vector<EpisodeResult> results(jobs.size());
  std::vector<char> ran(jobs.size(), 0);
  std::size_t done = 0;
  const int threads = execution.jobs > 0 ? execution.jobs : omp_get_max_threads();

  // Dynamic schedule: episode lengths vary from seconds to the 100 s timeout.
#pragma omp parallel for schedule(dynamic, 1) num_threads(threads)
  for (long k = 0; k < total; ++k) {
    if (execution.stop && execution.stop->load()) continue;
    const auto [b, index] = jobs[static_cast<std::size_t>(k)];
    const BatchSpec& spec = *specs[b];
    const std::size_t trials = static_cast<std::size_t>(spec.trials);
    const std::size_t w = index / trials;
    const int trial = static_cast<int>(index % trials);
    const core::WorldSpec& world = spec.worlds[w];
    EpisodeResult result;
    try {
      auto controller = spec.make_controller();
      result = runEpisode(world, fields[b][w], *controller, spec.episode, episodeSeed(spec.seed, world.id, trial),
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
      if (progress) progress(b, results[static_cast<std::size_t>(k)], done, static_cast<std::size_t>(total));
    }
  }
  std::vector<std::vector<EpisodeResult>> finished(specs.size());
  for (std::size_t k = 0; k < results.size(); ++k)
    if (ran[k]) finished[jobs[k].first].push_back(std::move(results[k]));
  return finished;
}

}  // namespace barn::bench
