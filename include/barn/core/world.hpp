#pragma once
/// A BARN world as barnbench stores it: the occupancy grid plus everything derived from it
/// by the generator (start and goal cells, A* path, difficulty metrics).
///
/// A WorldSpec is immutable shared data once loaded: every episode on the world reads it,
/// none changes it.

#include <array>
#include <cstdint>
#include <optional>
#include <string>
#include <string_view>
#include <vector>

#include "barn/core/grid.hpp"

namespace barn::core {

/// What one difficulty metric is called and which way it grows harder.
struct DifficultyMetricInfo {
  std::string_view name;    // as in world files and index.csv
  bool harder_when_larger;  // true: a larger value makes a world harder (dispersion, tortuosity)
};

/// The five BARN difficulty metrics (Perille et al. 2020), in the dataset's order.
struct DifficultyMetrics {
  double closest_wall = 0.0;              // mean distance to the closest C-space obstacle [cells]
  double avg_visibility = 0.0;            // mean free run over 8 directions [cells]
  double dispersion = 0.0;                // mean wall/no-wall changes over 16 rays [-]
  double characteristic_dimension = 0.0;  // mean narrowest free axis [cells]
  double tortuosity = 0.0;                // path arc length / chord length [-]

  /// Per metric, in toArray()'s order. Less room (clearance, visibility, narrowest width) and
  /// more clutter (dispersion) or winding (tortuosity) make a world harder (Perille et al. 2020).
  static constexpr std::array<DifficultyMetricInfo, 5> kInfo = {{{"closest_wall", false},
                                                                  {"avg_visibility", false},
                                                                  {"dispersion", true},
                                                                  {"characteristic_dimension", false},
                                                                  {"tortuosity", true}}};
  static constexpr std::array<std::string_view, 5> kNames = {kInfo[0].name, kInfo[1].name, kInfo[2].name,
                                                             kInfo[3].name, kInfo[4].name};

  std::array<double, 5> toArray() const {
    return {closest_wall, avg_visibility, dispersion, characteristic_dimension, tortuosity};
  }
  static DifficultyMetrics fromArray(const std::array<double, 5>& a) {
    return {a[0], a[1], a[2], a[3], a[4]};
  }
};

/// Where a world came from.
enum class WorldSource {
  Generated,    ///< barnbench's own generator, reproducible from `seed`
  BarnDataset,  ///< imported from the original BARN dataset (no seed was ever recorded)
};
std::string_view toString(WorldSource source);

struct WorldSpec {
  int id = 0;                               // world index (0..299 for the canonical sets)
  WorldSource source = WorldSource::Generated;
  std::optional<std::uint64_t> seed;        // generator seed; none for imported worlds
  double fill_pct = 0.0;                    // generator initial fill probability [-]
  int smooth_iter = 0;                      // generator smoothing iterations [-]
  Grid grid;                                // (30 x 30) obstacle cells, 1 = obstacle
  Cell start_cell;                          // in column 0
  Cell goal_cell;                           // in column 29
  std::vector<Cell> path;                   // A* path on the C-space, start cell duplicated (as BARN)
  DifficultyMetrics metrics;                // raw metrics
  DifficultyMetrics norm_metrics;           // z-scores over the world's set
};

}  // namespace barn::core
