// Worlds written in the BARN dataset's layout read back through the import unchanged (the
// original dataset's own round trip is in dataset_import_test.cpp, beside its other fidelity tests).

#include "generator/dataset_export.hpp"

#include <gtest/gtest.h>

#include <filesystem>
#include <random>
#include <string>
#include <vector>

#include "barn/core/npy.hpp"
#include "barn/core/text_io.hpp"
#include "barn/core/world_file.hpp"
#include "generator/cspace.hpp"
#include "generator/dataset_files.hpp"
#include "generator/dataset_import.hpp"

namespace barn::generator {
namespace {

namespace fs = std::filesystem;

const fs::path kWorlds = fs::path(BARN_SOURCE_DIR) / "worlds";

class DatasetExport : public testing::Test {
 protected:
  void SetUp() override {
    dir_ = fs::temp_directory_path() / ("barn_dataset_export_test_" + std::to_string(std::random_device{}()));
    fs::remove_all(dir_);
  }
  void TearDown() override { fs::remove_all(dir_); }
  fs::path dir_;
};

/// Every 25th committed world: each parameter set once.
std::vector<core::WorldSpec> someWorlds() {
  std::vector<core::WorldSpec> worlds;
  for (int id = 0; id < 300; id += 25) worlds.push_back(core::readWorldFile(kWorlds / core::worldFileName(id)));
  return worlds;
}

TEST_F(DatasetExport, ArraysHaveTheDatasetsDtypesAndShapes) {
  const core::WorldSpec world = core::readWorldFile(kWorlds / core::worldFileName(3));
  core::writeFilesAtomic(dir_, datasetFiles({world}));
  for (const DatasetArrayFiles kind : {kGridFiles, kCspaceFiles})
    EXPECT_EQ(core::readNpyInt64(dir_ / datasetFile(kind, 3)).shape, (std::vector<std::size_t>{30, 30})) << kind.folder;
  EXPECT_EQ(core::readNpyInt64(dir_ / datasetFile(kPathFiles, 3)).shape, (std::vector<std::size_t>{world.path.size(), 2}));
  for (const DatasetArrayFiles kind : {kMetricsFiles, kNormMetricsFiles})
    EXPECT_EQ(core::readNpyFloat64(dir_ / datasetFile(kind, 3)).shape, std::vector<std::size_t>{5}) << kind.folder;
}

TEST_F(DatasetExport, ReadsBackThroughTheImportUnchanged) {
  const std::vector<core::WorldSpec> worlds = someWorlds();
  core::writeFilesAtomic(dir_, datasetFiles(worlds));
  const std::vector<DatasetWorld> dataset = readDataset(dir_);
  ASSERT_EQ(dataset.size(), worlds.size());
  for (std::size_t i = 0; i < worlds.size(); ++i) {
    const core::WorldSpec& w = worlds[i];
    const DatasetWorld& d = dataset[i];
    EXPECT_EQ(d.id, w.id);
    EXPECT_EQ(d.grid, w.grid) << "world " << w.id;
    EXPECT_EQ(d.path, w.path) << "world " << w.id;
    ASSERT_TRUE(d.has_metrics && d.has_cspace && d.has_norm_metrics) << "world " << w.id;
    // Bit for bit: the .npy data block holds the doubles themselves.
    EXPECT_EQ(d.metrics.toArray(), w.metrics.toArray()) << "world " << w.id;
    EXPECT_EQ(d.norm_metrics.toArray(), w.norm_metrics.toArray()) << "world " << w.id;
    EXPECT_EQ(d.cspace, dilateCspace(w.grid)) << "world " << w.id;
  }
  const std::vector<core::WorldSpec> imported = importDataset(dataset);
  for (std::size_t i = 0; i < worlds.size(); ++i) {
    EXPECT_EQ(imported[i].grid, worlds[i].grid);
    EXPECT_EQ(imported[i].path, worlds[i].path);
    EXPECT_EQ(imported[i].start_cell, worlds[i].start_cell);
    EXPECT_EQ(imported[i].goal_cell, worlds[i].goal_cell);
    EXPECT_EQ(imported[i].metrics.toArray(), worlds[i].metrics.toArray());
  }
}

}  // namespace
}  // namespace barn::generator
