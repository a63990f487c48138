#include "generator/dataset_export.hpp"

#include "barn/core/npy.hpp"
#include "generator/cspace.hpp"
#include "generator/dataset_files.hpp"

namespace barn::generator {

std::string gridNpy(const core::Grid& grid) {
  core::NpyInt64Array array;
  array.shape = {static_cast<std::size_t>(grid.rows()), static_cast<std::size_t>(grid.cols())};
  for (int r = 0; r < grid.rows(); ++r)
    for (int c = 0; c < grid.cols(); ++c) array.values.push_back(grid.at(r, c));
  return core::formatNpyInt64(array);
}

std::string pathNpy(const std::vector<core::Cell>& path) {
  core::NpyInt64Array array;
  array.shape = {path.size(), 2};
  for (const core::Cell& cell : path) {
    array.values.push_back(cell.row);
    array.values.push_back(cell.col);
  }
  return core::formatNpyInt64(array);
}

std::string metricsNpy(const core::DifficultyMetrics& metrics) {
  const auto values = metrics.toArray();
  return core::formatNpyFloat64({{values.size()}, {values.begin(), values.end()}});
}

std::vector<core::FileContent> datasetFiles(const std::vector<core::WorldSpec>& worlds) {
  std::vector<core::FileContent> files;
  for (const core::WorldSpec& w : worlds) {
    files.push_back({datasetFile(kGridFiles, w.id).string(), gridNpy(w.grid)});
    files.push_back({datasetFile(kCspaceFiles, w.id).string(), gridNpy(dilateCspace(w.grid))});
    files.push_back({datasetFile(kPathFiles, w.id).string(), pathNpy(w.path)});
    files.push_back({datasetFile(kMetricsFiles, w.id).string(), metricsNpy(w.metrics)});
    files.push_back({datasetFile(kNormMetricsFiles, w.id).string(), metricsNpy(w.norm_metrics)});
  }
  return files;
}

}  // namespace barn::generator
