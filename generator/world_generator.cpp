#include "generator/world_generator.hpp"

#include "barn/core/errors.hpp"
#include "barn/core/rng.hpp"
#include "barn/core/text_io.hpp"
#include "generator/barn_astar.hpp"
#include "generator/cellular_automaton.hpp"
#include "generator/cspace.hpp"
#include "generator/difficulty_metrics.hpp"

namespace barn::generator {

std::optional<Derived> deriveFromGrid(const core::Grid& grid, core::Cell start, core::Cell goal) {
  const core::Grid cspace = dilateCspace(grid);
  auto path = barnAStar(cspace, start, goal);
  if (!path) return std::nullopt;
  return Derived{*path, computeMetrics(cspace, *path)};
}

std::optional<core::WorldSpec> generateWorld(const GeneratorParams& params, std::uint64_t seed, int id) {
  core::Rng rng(seed);
  core::Grid grid = cellularAutomatonMap(core::kBarnGridSize, core::kBarnGridSize, params.fill_pct,
                                         params.smooth_iter, rng);
  const core::Grid cspace = dilateCspace(grid);
  const std::vector<int> labels = labelFreeRegions(cspace);
  const Region left = biggestRegionTouchingColumn(cspace, labels, 0);
  const Region right = biggestRegionTouchingColumn(cspace, labels, core::kBarnGridSize - 1);
  if (left.label < 0 || left.label != right.label) return std::nullopt;

  const core::Cell start{left.open_rows[rng.below(left.open_rows.size())], 0};
  const core::Cell goal{right.open_rows[rng.below(right.open_rows.size())], core::kBarnGridSize - 1};
  auto derived = deriveFromGrid(grid, start, goal);
  if (!derived) return std::nullopt;

  core::WorldSpec world;
  world.id = id;
  world.source = core::WorldSource::Generated;
  world.seed = seed;
  world.fill_pct = params.fill_pct;
  world.smooth_iter = params.smooth_iter;
  world.grid = std::move(grid);
  world.start_cell = start;
  world.goal_cell = goal;
  world.path = std::move(derived->path);
  world.metrics = derived->metrics;
  return world;
}

std::uint64_t sweepAttemptSeed(std::uint64_t base_seed, int set_index, int attempt) {
  return core::mixSeed(base_seed, static_cast<std::uint64_t>(set_index), static_cast<std::uint64_t>(attempt));
}

std::vector<core::WorldSpec> generateSweep(const SweepConfig& config) {
  std::vector<core::WorldSpec> worlds;
  int set_index = 0;
  for (double fill : config.fill_pcts) {
    for (int smooth : config.smooth_iters) {
      int accepted = 0;
      for (int attempt = 0; accepted < config.worlds_per_set; ++attempt) {
        if (attempt >= config.max_attempts_per_set)
          throw core::InputError("generator: fill " + core::formatDouble(fill) + ", smoothing " +
                                 std::to_string(smooth) + ": only " + std::to_string(accepted) + " of " +
                                 std::to_string(attempt) + " attempts were usable worlds");
        const std::uint64_t seed = sweepAttemptSeed(config.base_seed, set_index, attempt);
        auto world = generateWorld({fill, smooth}, seed, static_cast<int>(worlds.size()));
        if (!world) continue;  // BARN retries rejected worlds without counting them
        worlds.push_back(std::move(*world));
        ++accepted;
      }
      ++set_index;
    }
  }
  normaliseSet(worlds);
  return worlds;
}

void normaliseSet(std::vector<core::WorldSpec>& worlds) {
  std::vector<core::DifficultyMetrics> raw;
  raw.reserve(worlds.size());
  for (const auto& w : worlds) raw.push_back(w.metrics);
  const MetricsNormalisation norm = metricsNormalisation(raw);
  for (auto& w : worlds) w.norm_metrics = normaliseMetrics(w.metrics, norm);
}

}  // namespace barn::generator
