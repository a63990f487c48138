#include "barn/learning/trainer.hpp"

#include <gmock/gmock.h>
#include <gtest/gtest.h>

#include <cmath>

namespace barn::learning {
namespace {

// A tiny pipeline: 120 s of driving at 1 m/s, every 4th record (~1,450 demonstrations), a
// 32-unit network.
const Dataset& tinyData() {
  static const Dataset data = [] {
    CollectConfig collect;
    collect.duration = 120.0;
    HallucinationConfig hallucination;
    hallucination.stride = 4;
    return buildDataset(collectExploration(collect, "tiny"), hallucination, 2.0);
  }();
  return data;
}

TrainConfig tinyTraining() {
  TrainConfig c;
  c.hidden = 32;
  c.epochs = 20;
  c.learning_rate = 1e-3;
  return c;
}

TEST(Trainer, TinyConfigurationTrainsInAFewSecondsAndItsLossFalls) {
  // About 0.5 s in a Release build: 20 epochs of ~1,300 columns through a 722-32-32-2 network.
  const TrainingResult result = trainPolicy(tinyData(), tinyTraining());
  ASSERT_EQ(result.history.size(), 20u);
  // Both losses fall: the last five epochs against the first (the training loss by 30 %).
  double train_end = 0.0, validation_end = 0.0;
  for (std::size_t e = 15; e < 20; ++e) {
    train_end += result.history[e].train / 5.0;
    validation_end += result.history[e].validation / 5.0;
  }
  EXPECT_LT(train_end, 0.7 * result.history.front().train);
  EXPECT_LT(validation_end, result.history.front().validation);
  EXPECT_GT(result.validation_columns, 0u);
}

TEST(Trainer, SameSeedGivesIdenticalWeightsAnotherSeedDoesNot) {
  TrainConfig config = tinyTraining();
  config.epochs = 3;
  const TrainingResult a = trainPolicy(tinyData(), config);
  const TrainingResult b = trainPolicy(tinyData(), config);
  EXPECT_EQ(a.weights.w1, b.weights.w1);
  EXPECT_EQ(a.weights.w3, b.weights.w3);
  EXPECT_EQ(a.weights.b3, b.weights.b3);
  EXPECT_EQ(a.history.back().validation, b.history.back().validation);
  config.seed = 4;
  EXPECT_NE(trainPolicy(tinyData(), config).weights.w1, a.weights.w1);
}

TEST(Trainer, TrainsTheActivationItsConfigNames) {
  // leaky_relu trains too, reproducibly, and to other weights than relu from the same seed.
  TrainConfig config = tinyTraining();
  config.epochs = 3;
  const TrainingResult relu = trainPolicy(tinyData(), config);
  config.activation = Activation::LeakyRelu;
  const TrainingResult a = trainPolicy(tinyData(), config);
  const TrainingResult b = trainPolicy(tinyData(), config);
  EXPECT_EQ(a.weights.w1, b.weights.w1);
  EXPECT_NE(a.weights.w1, relu.weights.w1);
  EXPECT_LT(a.history.back().train, a.history.front().train);
  // Its validation loss is the leaky network's (evaluating the same weights as relu differs).
  std::vector<std::size_t> train, validation;
  splitDataset(tinyData(), config.validation_share, train, validation);
  Eigen::MatrixXf x(tinyData().inputs.rows(), static_cast<Eigen::Index>(validation.size()));
  Eigen::MatrixXf t(2, static_cast<Eigen::Index>(validation.size()));
  for (std::size_t j = 0; j < validation.size(); ++j) {
    x.col(static_cast<Eigen::Index>(j)) = tinyData().inputs.col(static_cast<Eigen::Index>(validation[j]));
    t.col(static_cast<Eigen::Index>(j)) = tinyData().targets.col(static_cast<Eigen::Index>(validation[j]));
  }
  Mlp<float> leaky(a.weights, Activation::LeakyRelu, config.leaky_slope);
  Mlp<float> as_relu(a.weights);
  EXPECT_NEAR(leaky.loss(x, t), a.history.back().validation, 1e-5 * a.history.back().validation);
  EXPECT_GT(std::abs(as_relu.loss(x, t) - a.history.back().validation), 1e-4 * a.history.back().validation);
}

TEST(Trainer, BatchesPerEpochSetsTheEpochsLengthAndStaysReproducible) {
  // ~1,300 training columns = 40 batches of 32 per full pass; 7 batches per epoch for 12
  // epochs read on through two passes (84 batches), reshuffling in between.
  TrainConfig config = tinyTraining();
  config.epochs = 12;
  config.batches_per_epoch = 7;
  const TrainingResult a = trainPolicy(tinyData(), config);
  const TrainingResult b = trainPolicy(tinyData(), config);
  ASSERT_EQ(a.history.size(), 12u);
  EXPECT_EQ(a.weights.w1, b.weights.w1);
  EXPECT_EQ(a.history.back().validation, b.history.back().validation);
  EXPECT_LT(a.history.back().train, a.history.front().train);
  // Not the same as full passes.
  config.batches_per_epoch = 0;
  config.epochs = 2;
  EXPECT_NE(trainPolicy(tinyData(), config).weights.w1, a.weights.w1);
}

TEST(Trainer, JoinedRecordingsAreEachSplitLastTenthOut) {
  // Two copies of the tiny data joined: the second's records are numbered on from 6001, and
  // each copy holds out its own last tenth (records 5400.. and 6001 + 5400..).
  Dataset joined = tinyData();
  appendDataset(joined, tinyData());
  ASSERT_EQ(joined.size(), 2 * tinyData().size());
  EXPECT_EQ(joined.record_count, 12002u);
  EXPECT_EQ(joined.recording_starts, (std::vector<std::size_t>{0, 6001}));
  EXPECT_EQ(joined.records[tinyData().size()], 6001u + tinyData().records[0]);
  EXPECT_EQ(joined.inputs.col(static_cast<Eigen::Index>(tinyData().size()) + 3), tinyData().inputs.col(3));
  std::vector<std::size_t> train, validation, train1, validation1;
  splitDataset(tinyData(), 0.1, train1, validation1);
  splitDataset(joined, 0.1, train, validation);
  EXPECT_EQ(train.size(), 2 * train1.size());
  EXPECT_EQ(validation.size(), 2 * validation1.size());
  for (std::size_t c : validation) {
    const std::size_t r = joined.records[c];
    EXPECT_TRUE((r >= 5400 && r < 6001) || r >= 6001 + 5400) << r;
  }
  for (std::size_t c : train) {
    const std::size_t r = joined.records[c];
    EXPECT_TRUE(r + joined.lookahead < 5400 || (r >= 6001 && r + joined.lookahead < 6001 + 5400)) << r;
  }
}

TEST(Trainer, ValidationIsTheLastTenthInTimeAndTrainingNeverLooksIntoIt) {
  std::vector<std::size_t> train, validation;
  splitDataset(tinyData(), 0.1, train, validation);
  // 120 s at 50 Hz = 6001 records; the boundary is floor(0.9 * 6001) = 5400.
  ASSERT_EQ(tinyData().record_count, 6001u);
  for (std::size_t c : validation) EXPECT_GE(tinyData().records[c], 5400u);
  for (std::size_t c : train) EXPECT_LT(tinyData().records[c] + tinyData().lookahead, 5400u);
  // Records 5300..5396 (every 4th: 25) look 100 records ahead into the validation part.
  std::size_t dropped = 0;
  for (std::size_t c = 0; c < tinyData().size(); ++c) dropped += tinyData().records[c] >= 5300 && tinyData().records[c] < 5400;
  EXPECT_EQ(dropped, 25u);
  EXPECT_EQ(train.size() + validation.size() + dropped, tinyData().size());
}

TEST(Trainer, TooLittleDataIsAnInputError) {
  TrainConfig config = tinyTraining();
  config.batch_size = 4000;
  EXPECT_THROW(trainPolicy(tinyData(), config), core::InputError);
}

TEST(Trainer, LossCsvHasOneRowPerEpoch) {
  TrainingResult result;
  result.mean_predictor_loss = 0.5;
  result.history = {{1, 0.4, 0.45, 1.0}, {2, 0.3, 0.35, 2.0}};
  EXPECT_EQ(lossCsv(result),
            "epoch,train_loss,validation_loss,mean_predictor_loss,seconds\n1,0.4,0.45,0.5,1\n2,0.3,0.35,0.5,2\n");
}

}  // namespace
}  // namespace barn::learning
