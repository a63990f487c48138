// Fidelity against the original BARN dataset (BARN_DATASET_DIR, see tests/external_data.hpp).
// These tests skip, saying why, where the dataset is absent; everything else runs anywhere.

#include "generator/dataset_import.hpp"

#include <filesystem>
#include <random>
#include <string>
#include <vector>

#include <gtest/gtest.h>

#include "barn/core/protocol.hpp"
#include "barn/core/text_io.hpp"
#include "barn/core/world_file.hpp"
#include "generator/dataset_export.hpp"
#include "tests/external_data.hpp"

namespace barn::generator {
namespace {

const std::filesystem::path kDatasetDir = barn::test::externalData("BARN_DATASET_DIR");

class BarnDataset : public ::testing::Test {
 protected:
  void SetUp() override {
    if (!std::filesystem::is_directory(kDatasetDir / "grid_files"))
      GTEST_SKIP() << "set BARN_DATASET_DIR to a copy of the original BARN dataset to run this test";
    dataset_ = readDataset(kDatasetDir);
  }
  std::vector<DatasetWorld> dataset_;
};

TEST_F(BarnDataset, RecomputesEveryPathMetricAndCspaceExactly) {
  ASSERT_EQ(dataset_.size(), 150u);
  const VerifyReport report = verifyDataset(dataset_, 1e-9);
  EXPECT_EQ(report.paths_identical, 150);
  EXPECT_EQ(report.metrics_equal, 150);
  EXPECT_EQ(report.cspaces_identical, 150);
  for (const auto& line : report.mismatches) ADD_FAILURE() << line;
}

TEST_F(BarnDataset, OptimalTimeFollowsRunPy) {
  // The official harness: world 108's reference polyline is 10.66037 m under INIT x = -2.
  const auto worlds = importDataset(dataset_);
  const core::Protocol barn2023 = core::protocolPreset("barn2023");
  EXPECT_NEAR(core::referencePathLength(worlds[108].path, barn2023), 10.66037, 5e-6);
  EXPECT_NEAR(core::optimalTime(worlds[108].path, barn2023), 10.66037 / 2.0, 5e-6);
}

TEST_F(BarnDataset, ImportedWorldFilesReadBackIdentically) {
  const auto worlds = importDataset(dataset_);
  for (const auto& w : worlds) {
    const std::string text = core::formatWorldFile(w);
    const core::WorldSpec back = core::parseWorldFile(text, core::worldFileName(w.id));
    EXPECT_EQ(core::formatWorldFile(back), text) << "world " << w.id;
    EXPECT_EQ(back.path, w.path);
    EXPECT_EQ(back.grid, w.grid);
  }
}

TEST_F(BarnDataset, ExportOfTheImportGivesTheDatasetsArraysBack) {
  const std::filesystem::path dir =
      std::filesystem::temp_directory_path() / ("barn_dataset_round_trip_" + std::to_string(std::random_device{}()));
  core::writeFilesAtomic(dir, datasetFiles(importDataset(dataset_)));
  const std::vector<DatasetWorld> back = readDataset(dir);
  std::filesystem::remove_all(dir);
  ASSERT_EQ(back.size(), dataset_.size());
  for (std::size_t i = 0; i < dataset_.size(); ++i) {
    EXPECT_EQ(back[i].id, dataset_[i].id);
    EXPECT_EQ(back[i].grid, dataset_[i].grid) << "world " << dataset_[i].id;
    EXPECT_EQ(back[i].path, dataset_[i].path) << "world " << dataset_[i].id;
    EXPECT_EQ(back[i].metrics.toArray(), dataset_[i].metrics.toArray()) << "world " << dataset_[i].id;
    EXPECT_EQ(back[i].cspace, dataset_[i].cspace) << "world " << dataset_[i].id;
    // norm_metrics are not compared: the import z-scores over the worlds it imports (150 here),
    // the dataset over all 300.
  }
}

}  // namespace
}  // namespace barn::generator
