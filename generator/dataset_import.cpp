#include "generator/dataset_import.hpp"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <string>

#include "barn/core/errors.hpp"
#include "barn/core/npy.hpp"
#include "generator/cspace.hpp"
#include "generator/dataset_files.hpp"
#include "generator/difficulty_metrics.hpp"
#include "generator/world_generator.hpp"

namespace barn::generator {

namespace {

namespace fs = std::filesystem;

constexpr int kDatasetSize = 300;

core::Grid readGridNpy(const fs::path& path) {
  const core::NpyInt64Array array = core::readNpyInt64(path);
  if (array.shape != std::vector<std::size_t>{core::kBarnGridSize, core::kBarnGridSize})
    throw core::InputError(path.string() + ": expected a (30, 30) grid");
  core::Grid grid(core::kBarnGridSize, core::kBarnGridSize);
  for (int r = 0; r < core::kBarnGridSize; ++r) {
    for (int c = 0; c < core::kBarnGridSize; ++c) {
      const std::int64_t v = array.values[static_cast<std::size_t>(r * core::kBarnGridSize + c)];
      if (v != 0 && v != 1)
        throw core::InputError(path.string() + ": cell (" + std::to_string(r) + ", " + std::to_string(c) +
                               ") is " + std::to_string(v) + ", expected 0 or 1");
      grid.at(r, c) = static_cast<std::int8_t>(v);
    }
  }
  return grid;
}

std::vector<core::Cell> readPathNpy(const fs::path& path) {
  const core::NpyInt64Array array = core::readNpyInt64(path);
  if (array.shape.size() != 2 || array.shape[1] != 2 || array.shape[0] < 2)
    throw core::InputError(path.string() + ": expected an (n, 2) path with n >= 2");
  std::vector<core::Cell> cells;
  for (std::size_t i = 0; i < array.shape[0]; ++i) {
    const std::int64_t r = array.values[2 * i];
    const std::int64_t c = array.values[2 * i + 1];
    if (r < 0 || r >= core::kBarnGridSize || c < 0 || c >= core::kBarnGridSize)
      throw core::InputError(path.string() + ": row " + std::to_string(i) + " is outside the 30 x 30 grid");
    cells.push_back({static_cast<int>(r), static_cast<int>(c)});
  }
  return cells;
}

core::DifficultyMetrics readMetricsNpy(const fs::path& path) {
  const core::NpyFloat64Array array = core::readNpyFloat64(path);
  if (array.shape != std::vector<std::size_t>{5}) throw core::InputError(path.string() + ": expected 5 metrics");
  for (std::size_t k = 0; k < 5; ++k)
    if (!std::isfinite(array.values[k]))
      throw core::InputError(path.string() + ": " + std::string(core::DifficultyMetrics::kNames[k]) + " is " +
                             std::to_string(array.values[k]) + ", expected a finite number");
  return core::DifficultyMetrics::fromArray({array.values[0], array.values[1], array.values[2], array.values[3], array.values[4]});
}

std::string cellsText(const std::vector<core::Cell>& cells) {
  std::string text;
  for (const auto& c : cells) text += "(" + std::to_string(c.row) + "," + std::to_string(c.col) + ")";
  return text;
}

}  // namespace

std::vector<DatasetWorld> readDataset(const fs::path& dataset_dir) {
  const fs::path grid_dir = dataset_dir / kGridFiles.folder;
  std::error_code ec;
  if (!fs::is_directory(grid_dir, ec))
    throw core::InputError(dataset_dir.string() + ": not a BARN dataset folder (no grid_files/)");
  std::vector<int> ids;
  for (const auto& entry : fs::directory_iterator(grid_dir, ec)) {
    const std::string name = entry.path().filename().string();
    int id = -1;
    char tail = 0;
    if (std::sscanf(name.c_str(), "grid_%d.np%c", &id, &tail) == 2 && tail == 'y' && id >= 0 &&
        name == datasetFile(kGridFiles, id).filename().string())
      ids.push_back(id);
  }
  if (ids.empty()) throw core::InputError(grid_dir.string() + ": no grid_N.npy files");
  std::sort(ids.begin(), ids.end());

  std::vector<DatasetWorld> worlds;
  for (int id : ids) {
    DatasetWorld w;
    w.id = id;
    w.grid = readGridNpy(dataset_dir / datasetFile(kGridFiles, id));
    const fs::path path_file = dataset_dir / datasetFile(kPathFiles, id);
    if (!fs::exists(path_file)) throw core::InputError(path_file.string() + ": missing (every grid needs its path)");
    w.path = readPathNpy(path_file);
    if (const fs::path f = dataset_dir / datasetFile(kMetricsFiles, id); fs::exists(f)) {
      w.metrics = readMetricsNpy(f);
      w.has_metrics = true;
    }
    if (const fs::path f = dataset_dir / datasetFile(kCspaceFiles, id); fs::exists(f)) {
      w.cspace = readGridNpy(f);
      w.has_cspace = true;
    }
    if (const fs::path f = dataset_dir / datasetFile(kNormMetricsFiles, id); fs::exists(f)) {
      w.norm_metrics = readMetricsNpy(f);
      w.has_norm_metrics = true;
    }
    const std::string name = path_file.string();
    if (w.grid.at(w.path.front()))
      throw core::InputError(name + ": start cell lies inside an obstacle of grid_" + std::to_string(id) + ".npy");
    if (w.grid.at(w.path.back()))
      throw core::InputError(name + ": goal cell lies inside an obstacle of grid_" + std::to_string(id) + ".npy");
    worlds.push_back(std::move(w));
  }
  return worlds;
}

void inferredSweepParams(int id, double& fill_pct, int& smooth_iter) {
  if (id < 0 || id >= kDatasetSize) {
    fill_pct = 0.0;
    smooth_iter = 0;
    return;
  }
  constexpr double kFills[4] = {0.15, 0.20, 0.25, 0.30};
  fill_pct = kFills[id / 75];
  smooth_iter = 2 + (id % 75) / 25;
}

std::vector<core::WorldSpec> importDataset(const std::vector<DatasetWorld>& dataset) {
  std::vector<core::WorldSpec> worlds;
  for (const DatasetWorld& d : dataset) {
    core::WorldSpec w;
    w.id = d.id;
    w.source = core::WorldSource::BarnDataset;
    inferredSweepParams(d.id, w.fill_pct, w.smooth_iter);
    w.grid = d.grid;
    w.start_cell = d.path.front();
    w.goal_cell = d.path.back();
    w.path = d.path;  // the stored path defines the official OT
    w.metrics = d.has_metrics ? d.metrics : computeMetrics(dilateCspace(d.grid), d.path);
    worlds.push_back(std::move(w));
  }
  normaliseSet(worlds);
  return worlds;
}

VerifyReport verifyDataset(const std::vector<DatasetWorld>& dataset, double metric_tolerance) {
  VerifyReport report;
  std::vector<core::WorldSpec> recomputed_set;
  for (const DatasetWorld& d : dataset) {
    ++report.worlds;
    const std::string label = "world " + std::to_string(d.id) + ": ";
    const core::Grid cspace = dilateCspace(d.grid);
    if (d.has_cspace) {
      ++report.cspaces_present;
      if (cspace == d.cspace) ++report.cspaces_identical;
      else report.mismatches.push_back(label + "cspace differs from the 5 x 5 dilation of the grid");
    }
    const auto derived = deriveFromGrid(d.grid, d.path.front(), d.path.back());
    if (!derived) {
      report.mismatches.push_back(label + "A* finds no path");
      continue;
    }
    if (derived->path == d.path) ++report.paths_identical;
    else report.mismatches.push_back(label + "path differs: stored " + cellsText(d.path) + ", recomputed " + cellsText(derived->path));
    if (d.has_metrics) {
      const auto stored = d.metrics.toArray();
      const auto ours = derived->metrics.toArray();
      bool equal = true;
      for (std::size_t k = 0; k < 5; ++k) {
        if (std::abs(stored[k] - ours[k]) > metric_tolerance) {
          equal = false;
          char line[200];
          std::snprintf(line, sizeof(line), "%s differs: stored %.17g, recomputed %.17g",
                        std::string(core::DifficultyMetrics::kNames[k]).c_str(), stored[k], ours[k]);
          report.mismatches.push_back(label + line);
        }
      }
      report.metrics_equal += equal;
    }
    core::WorldSpec w;
    w.id = d.id;
    w.metrics = derived->metrics;
    recomputed_set.push_back(std::move(w));
  }
  // The stored z-scores are over all 300 worlds; they can only be recomputed from the full set.
  report.norm_metrics_compared = static_cast<int>(dataset.size()) == kDatasetSize &&
                                 static_cast<int>(recomputed_set.size()) == kDatasetSize;
  if (report.norm_metrics_compared) {
    normaliseSet(recomputed_set);
    for (std::size_t i = 0; i < dataset.size(); ++i) {
      if (!dataset[i].has_norm_metrics) continue;
      ++report.norm_metrics_present;
      const auto stored = dataset[i].norm_metrics.toArray();
      const auto ours = recomputed_set[i].norm_metrics.toArray();
      bool equal = true;
      for (std::size_t k = 0; k < 5; ++k) equal = equal && std::abs(stored[k] - ours[k]) <= metric_tolerance;
      if (equal) ++report.norm_metrics_equal;
      else report.mismatches.push_back("world " + std::to_string(dataset[i].id) + ": norm_metrics differ");
    }
  }
  return report;
}

std::optional<DatasetHalves> absentWorldsMetrics(const std::vector<DatasetWorld>& dataset) {
  // Each world's raw metrics and z-scores, as arrays.
  std::vector<std::array<double, 5>> raw, z_scores;
  for (const DatasetWorld& d : dataset)
    if (d.has_metrics && d.has_norm_metrics) {
      raw.push_back(d.metrics.toArray());
      z_scores.push_back(d.norm_metrics.toArray());
    }
  const int n = static_cast<int>(raw.size());
  // Every world present must carry both, or the present and absent sums would not split the set.
  if (n < 2 || n != static_cast<int>(dataset.size()) || n >= kDatasetSize) return std::nullopt;
  DatasetHalves halves;
  halves.present.worlds = n;
  halves.absent.worlds = kDatasetSize - n;
  for (std::size_t k = 0; k < 5; ++k) {
    // x = mean + sd z for every world: the least-squares line through (z, x).
    double sum_z = 0.0, sum_x = 0.0, sum_zz = 0.0, sum_zx = 0.0, sum_xx = 0.0;
    for (std::size_t i = 0; i < raw.size(); ++i) {
      const double z = z_scores[i][k], x = raw[i][k];
      sum_z += z, sum_x += x, sum_zz += z * z, sum_zx += z * x, sum_xx += x * x;
    }
    const double spread_z = n * sum_zz - sum_z * sum_z;
    if (!(spread_z > 0.0)) return std::nullopt;  // every z alike: the line is not determined
    const double sd_all = (n * sum_zx - sum_z * sum_x) / spread_z;
    const double mean_all = (sum_x - sd_all * sum_z) / n;
    for (std::size_t i = 0; i < raw.size(); ++i) {
      const double x = raw[i][k];
      if (std::abs(mean_all + sd_all * z_scores[i][k] - x) > 1e-6 * (1.0 + std::abs(x))) return std::nullopt;
    }
    halves.present.mean[k] = sum_x / n;
    halves.present.sd[k] = std::sqrt(std::max(0.0, sum_xx / n - halves.present.mean[k] * halves.present.mean[k]));
    // The absent worlds' sums are the whole set's less the present ones'.
    const double absent = halves.absent.worlds;
    const double mean_absent = (kDatasetSize * mean_all - sum_x) / absent;
    const double square_absent = (kDatasetSize * (sd_all * sd_all + mean_all * mean_all) - sum_xx) / absent;
    halves.absent.mean[k] = mean_absent;
    halves.absent.sd[k] = std::sqrt(std::max(0.0, square_absent - mean_absent * mean_absent));
  }
  return halves;
}

}  // namespace barn::generator
