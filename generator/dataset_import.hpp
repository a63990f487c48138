#pragma once
/// Import of the original BARN dataset (Perille et al. 2020; layout in dataset_files.hpp): grid_files/grid_N.npy,
/// path_files/path_N.npy, metrics_files/metrics_N.npy and, for --verify, cspace_files/ and
/// norm_metrics_files/ (which also give a partial dataset's missing worlds' metrics).

#include <array>
#include <filesystem>
#include <optional>
#include <string>
#include <vector>

#include "barn/core/world.hpp"

namespace barn::generator {

/// One world of the dataset as stored, before any recomputation.
struct DatasetWorld {
  int id = 0;
  core::Grid grid;                             // grid_N.npy
  std::vector<core::Cell> path;                // path_N.npy (start duplicated)
  bool has_metrics = false;
  core::DifficultyMetrics metrics;             // metrics_N.npy, if present
  bool has_cspace = false;
  core::Grid cspace;                           // cspace_N.npy, if present
  bool has_norm_metrics = false;
  core::DifficultyMetrics norm_metrics;        // norm_metrics_N.npy, if present
};

/// Reads every world of the dataset folder (ids from grid_files/grid_N.npy, ascending).
/// Throws InputError naming the file on a missing, truncated or ill-shaped array.
std::vector<DatasetWorld> readDataset(const std::filesystem::path& dataset_dir);

/// The generator parameters BARN used for dataset world `id` (sweep order, inferred from the
/// dataset: fill = 0.15 + 0.05 floor(id / 75), smoothing = 2 + floor((id mod 75) / 25)).
void inferredSweepParams(int id, double& fill_pct, int& smooth_iter);

/// Our world files for the dataset: the stored path (official OT) and the stored metrics
/// (recomputed where the file is absent), z-scores over the imported set.
std::vector<core::WorldSpec> importDataset(const std::vector<DatasetWorld>& dataset);

/// Result of recomputing a dataset world from its grid.
struct VerifyReport {
  int worlds = 0;
  int paths_identical = 0;
  int metrics_equal = 0;      // all five within `metric_tolerance`
  int cspaces_identical = 0;
  int cspaces_present = 0;
  int norm_metrics_equal = 0;
  int norm_metrics_present = 0;
  bool norm_metrics_compared = false;  // only for the complete 300-world dataset
  std::vector<std::string> mismatches;  // one line per difference, "world 12: path differs ..."
  bool ok() const { return mismatches.empty(); }
};

/// Recomputes C-space, A* path (start and goal from the stored path's ends) and metrics of
/// every world and compares them with the stored arrays.
VerifyReport verifyDataset(const std::vector<DatasetWorld>& dataset, double metric_tolerance = 1e-9);

/// Each difficulty metric's mean and (population) standard deviation over a set of worlds.
struct MetricsSummary {
  int worlds = 0;
  std::array<double, 5> mean{};
  std::array<double, 5> sd{};
};

/// The worlds of a partial dataset and the ones it lacks, as far as their metrics go. The
/// stored norm_metrics are z-scores over all 300 worlds, so with the raw metrics of the worlds
/// present they fix each metric's mean and spread over all 300, and so over the absent ones:
/// how the missing worlds compare in difficulty, without them.
struct DatasetHalves {
  MetricsSummary present;
  MetricsSummary absent;
};

/// Empty for a complete dataset, where a world lacks either array or fewer than two are present, or where the
/// z-scores do not follow one mean and spread per metric (then they are not over a common set).
std::optional<DatasetHalves> absentWorldsMetrics(const std::vector<DatasetWorld>& dataset);

}  // namespace barn::generator
