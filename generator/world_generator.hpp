#pragma once
/// BARN worlds from seeds: one world (GEN gen_world_ca.py main) and the canonical 300-world
/// sweep (GEN generator.py), with barnbench's recorded seeds so every world can be remade.

#include <cstdint>
#include <optional>
#include <vector>

#include "barn/core/world.hpp"

namespace barn::generator {

struct GeneratorParams {
  double fill_pct = 0.15;  // initial fill probability [-]
  int smooth_iter = 2;     // smoothing passes [-]
};

/// Everything BARN derives from an obstacle grid once the start and goal cells are known:
/// the A* path and the raw metrics. nullopt if A* finds no path.
struct Derived {
  std::vector<core::Cell> path;     // start cell duplicated
  core::DifficultyMetrics metrics;  // raw
};
std::optional<Derived> deriveFromGrid(const core::Grid& grid, core::Cell start, core::Cell goal);

/// One generation attempt with a seeded std::mt19937_64: cellular automaton, C-space, the
/// largest left and right regions, start and goal rows drawn from them, A*, metrics.
/// nullopt when BARN would discard the attempt (regions not connected, or no A* path).
/// `norm_metrics` is left at zero; it depends on the whole set.
std::optional<core::WorldSpec> generateWorld(const GeneratorParams& params, std::uint64_t seed, int id);

/// The canonical sweep: fill 0.15/0.20/0.25/0.30 (outer) x smoothing 2/3/4 (inner) x
/// `worlds_per_set` accepted worlds, in BARN's order (world id = index in the sweep).
struct SweepConfig {
  std::uint64_t base_seed = 2022;                    // every attempt's seed derives from it
  int worlds_per_set = 25;                           // accepted worlds per parameter set
  std::vector<double> fill_pcts = {0.15, 0.20, 0.25, 0.30};
  std::vector<int> smooth_iters = {2, 3, 4};
  int max_attempts_per_set = 1000000;                // give up (InputError) past this many
};

/// Seed of attempt `attempt` of parameter set `set_index` in the sweep.
std::uint64_t sweepAttemptSeed(std::uint64_t base_seed, int set_index, int attempt);

/// Runs the sweep and z-normalises the metrics over the resulting set.
std::vector<core::WorldSpec> generateSweep(const SweepConfig& config);

/// Replaces every world's norm_metrics by z-scores over the given set (population std).
void normaliseSet(std::vector<core::WorldSpec>& worlds);

}  // namespace barn::generator
