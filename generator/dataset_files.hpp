#pragma once
/// The original BARN dataset's folder layout (DS benchmarking_dataset/): one .npy file per
/// world and kind of array, e.g. grid_files/grid_7.npy. Import and export both name files here.

#include <array>
#include <filesystem>
#include <string>

namespace barn::generator {

/// One kind of array of the dataset: the folder its files sit in and their name stem.
struct DatasetArrayFiles {
  const char* folder;  // e.g. "grid_files"
  const char* stem;    // e.g. "grid"
};

inline constexpr DatasetArrayFiles kGridFiles{"grid_files", "grid"};                  // int64 (30, 30)
inline constexpr DatasetArrayFiles kCspaceFiles{"cspace_files", "cspace"};            // int64 (30, 30)
inline constexpr DatasetArrayFiles kPathFiles{"path_files", "path"};                  // int64 (n, 2)
inline constexpr DatasetArrayFiles kMetricsFiles{"metrics_files", "metrics"};         // float64 (5,)
inline constexpr DatasetArrayFiles kNormMetricsFiles{"norm_metrics_files", "norm_metrics"};  // float64 (5,)

inline constexpr std::array<DatasetArrayFiles, 5> kDatasetArrays = {kGridFiles, kCspaceFiles, kPathFiles, kMetricsFiles,
                                                                    kNormMetricsFiles};

/// The file of world `id`'s array of kind `files`, relative to the dataset folder.
inline std::filesystem::path datasetFile(DatasetArrayFiles files, int id) {
  return std::filesystem::path(files.folder) / (std::string(files.stem) + "_" + std::to_string(id) + ".npy");
}

}  // namespace barn::generator
