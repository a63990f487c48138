// Fidelity against the original BARN dataset (BARN_DATASET_DIR, see tests/external_data.hpp).
// These tests skip, saying why, where the dataset is absent; everything else runs anywhere.

#include "generator/dataset_import.hpp"

#include <cmath>
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

// A 300-world set with random metrics and z-scores over all of it, as the BARN dataset stores.
std::vector<DatasetWorld> syntheticDataset() {
  std::mt19937 rng(7);
  std::vector<DatasetWorld> worlds(300);
  for (std::size_t i = 0; i < worlds.size(); ++i) {
    worlds[i].id = static_cast<int>(i);
    worlds[i].has_metrics = worlds[i].has_norm_metrics = true;
    // The later worlds denser, as in BARN's sweep: a different mean and spread per half.
    std::normal_distribution<double> metric(i < 150 ? 5.0 : 3.0, i < 150 ? 1.5 : 0.7);
    worlds[i].metrics = core::DifficultyMetrics::fromArray({metric(rng), metric(rng), metric(rng), metric(rng), metric(rng)});
  }
  for (std::size_t k = 0; k < 5; ++k) {
    double sum = 0.0, square = 0.0;
    for (const auto& w : worlds) sum += w.metrics.toArray()[k], square += w.metrics.toArray()[k] * w.metrics.toArray()[k];
    const double mean = sum / 300.0, sd = std::sqrt(square / 300.0 - mean * mean);
    for (auto& w : worlds) {
      auto z = w.norm_metrics.toArray();
      z[k] = (w.metrics.toArray()[k] - mean) / sd;
      w.norm_metrics = core::DifficultyMetrics::fromArray(z);
    }
  }
  return worlds;
}

MetricsSummary summaryOf(const std::vector<DatasetWorld>& worlds) {
  MetricsSummary s;
  s.worlds = static_cast<int>(worlds.size());
  for (std::size_t k = 0; k < 5; ++k) {
    double sum = 0.0, square = 0.0;
    for (const auto& w : worlds) sum += w.metrics.toArray()[k], square += w.metrics.toArray()[k] * w.metrics.toArray()[k];
    s.mean[k] = sum / s.worlds;
    s.sd[k] = std::sqrt(square / s.worlds - s.mean[k] * s.mean[k]);
  }
  return s;
}

TEST(AbsentWorldsMetrics, GivesTheMeanAndSpreadOfTheWorldsNotPresent) {
  const auto all = syntheticDataset();
  const std::vector<DatasetWorld> present(all.begin(), all.begin() + 137);
  const std::vector<DatasetWorld> absent(all.begin() + 137, all.end());
  const auto halves = absentWorldsMetrics(present);
  ASSERT_TRUE(halves.has_value());
  const MetricsSummary want_present = summaryOf(present), want_absent = summaryOf(absent);
  EXPECT_EQ(halves->present.worlds, 137);
  EXPECT_EQ(halves->absent.worlds, 163);
  for (std::size_t k = 0; k < 5; ++k) {
    EXPECT_NEAR(halves->present.mean[k], want_present.mean[k], 1e-9) << k;
    EXPECT_NEAR(halves->present.sd[k], want_present.sd[k], 1e-9) << k;
    EXPECT_NEAR(halves->absent.mean[k], want_absent.mean[k], 1e-9) << k;
    EXPECT_NEAR(halves->absent.sd[k], want_absent.sd[k], 1e-9) << k;
  }
  // The synthetic set's halves differ (the denser half is absent), so this is not a tautology.
  EXPECT_GT(halves->present.mean[0] - halves->absent.mean[0], 1.0);
}

TEST(AbsentWorldsMetrics, NothingForACompleteSetOrZScoresOverDifferentSets) {
  auto all = syntheticDataset();
  EXPECT_FALSE(absentWorldsMetrics(all).has_value());
  std::vector<DatasetWorld> present(all.begin(), all.begin() + 150);
  present[3].norm_metrics.tortuosity += 0.5;  // not a z-score of the same set any more
  EXPECT_FALSE(absentWorldsMetrics(present).has_value());
  present[3] = all[3];
  ASSERT_TRUE(absentWorldsMetrics(present).has_value());
  present[4].has_norm_metrics = false;  // a world whose z-scores are missing: no split of the set
  EXPECT_FALSE(absentWorldsMetrics(present).has_value());
  present.resize(1);
  EXPECT_FALSE(absentWorldsMetrics(present).has_value());
}

}  // namespace
}  // namespace barn::generator
