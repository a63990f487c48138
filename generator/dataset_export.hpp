#pragma once
/// Worlds written in the original BARN dataset's layout (dataset_files.hpp), with the dtypes
/// and shapes of the dataset's own files: what `barn import-barn` reads back, and the path
/// files the official harness's run.py takes its optimal time from.

#include <string>
#include <vector>

#include "barn/core/text_io.hpp"
#include "barn/core/world.hpp"

namespace barn::generator {

/// grid_N.npy: int64 (30, 30), 1 = obstacle, row r along world x.
std::string gridNpy(const core::Grid& grid);
/// path_N.npy: int64 (n, 2) of (row, col) cells, the start cell twice as BARN stores it.
std::string pathNpy(const std::vector<core::Cell>& path);
/// metrics_N.npy / norm_metrics_N.npy: float64 (5,), in DifficultyMetrics::kNames order.
std::string metricsNpy(const core::DifficultyMetrics& metrics);

/// Every dataset file of `worlds`, named relative to the dataset folder: grid, cspace (the
/// 5 x 5 dilation of the grid, recomputed), path, metrics and norm_metrics (the z-scores the
/// world files hold) per world.
std::vector<core::FileContent> datasetFiles(const std::vector<core::WorldSpec>& worlds);

}  // namespace barn::generator
