#pragma once
/// BARN's five difficulty metrics (GEN difficulty_quant.py), in the versions that produced
/// the published dataset (2020-09-08), and their z-score normalisation over a world set.
/// Every metric is computed on the C-space grid and averaged over the path cells, the
/// duplicated start cell included.

#include <vector>

#include "barn/core/grid.hpp"
#include "barn/core/world.hpp"

namespace barn::generator {

/// Old average visibility of one cell: walk the 8 directions from the cell, counting 1 per
/// free cell (the cell itself included) until a blocked cell; a direction that leaves the
/// map first is dropped; the result is floor(sum / kept directions) (Python 2 division).
int cellVisibility(const core::Grid& cspace, core::Cell cell);

/// Dispersion of one cell: 16 rays of radius 3, each "wall" or "no wall"; the number of
/// changes between cyclically consecutive rays. Reproduces the literal "+2" step rule, so the
/// rays with a -2 component take three steps. -1 for a blocked cell.
int cellDispersion(const core::Grid& cspace, core::Cell cell);

/// Characteristic dimension of one cell: over the 4 axes, the free length on both sides
/// (1 or sqrt(2) per free cell, the cell excluded); the minimum over axes. -1 if blocked.
double cellCharacteristicDimension(const core::Grid& cspace, core::Cell cell);

/// Arc length / chord length of the path, in cells.
double tortuosity(const std::vector<core::Cell>& path);

/// All five metrics of a world, from its C-space and A* path.
core::DifficultyMetrics computeMetrics(const core::Grid& cspace, const std::vector<core::Cell>& path);

/// Mean and population standard deviation (ddof 0, as np.std) of each metric over a set.
struct MetricsNormalisation {
  core::DifficultyMetrics mean;
  core::DifficultyMetrics std_dev;
};
MetricsNormalisation metricsNormalisation(const std::vector<core::DifficultyMetrics>& set);

/// z-scores of `raw` under `norm` (a metric with zero spread maps to 0).
core::DifficultyMetrics normaliseMetrics(const core::DifficultyMetrics& raw, const MetricsNormalisation& norm);

}  // namespace barn::generator
