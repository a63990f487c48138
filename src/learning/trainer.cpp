#include "barn/learning/trainer.hpp"

#include <algorithm>
#include <chrono>
#include <cmath>

#include "barn/core/errors.hpp"
#include "barn/core/rng.hpp"
#include "barn/core/text_io.hpp"

namespace barn::learning {

namespace {

using Matrix = Eigen::MatrixXf;

// Loss of the network on `columns` of `data`, in chunks (forward only).
double evaluate(Mlp<float>& net, const Dataset& data, const std::vector<std::size_t>& columns) {
  constexpr std::size_t kChunk = 256;
  double sum = 0.0;
  Matrix x, t;
  for (std::size_t start = 0; start < columns.size(); start += kChunk) {
    const std::size_t n = std::min(kChunk, columns.size() - start);
    x.resize(data.inputs.rows(), static_cast<Eigen::Index>(n));
    t.resize(2, static_cast<Eigen::Index>(n));
    for (std::size_t j = 0; j < n; ++j) {
      x.col(static_cast<Eigen::Index>(j)) = data.inputs.col(static_cast<Eigen::Index>(columns[start + j]));
      t.col(static_cast<Eigen::Index>(j)) = data.targets.col(static_cast<Eigen::Index>(columns[start + j]));
    }
    sum += net.loss(x, t) * static_cast<double>(n);
  }
  return columns.empty() ? 0.0 : sum / static_cast<double>(columns.size());
}

}  // namespace

void splitDataset(const Dataset& data, double validation_share, std::vector<std::size_t>& train,
                  std::vector<std::size_t>& validation) {
  train.clear();
  validation.clear();
  // Per recording [start, end): its last share is held out.
  const auto boundaryOf = [&](std::size_t record) {
    const auto next = std::upper_bound(data.recording_starts.begin(), data.recording_starts.end(), record);
    const std::size_t start = next == data.recording_starts.begin() ? 0 : *(next - 1);
    const std::size_t end = next == data.recording_starts.end() ? data.record_count : *next;
    return start + static_cast<std::size_t>(std::floor((1.0 - validation_share) * static_cast<double>(end - start)));
  };
  for (std::size_t c = 0; c < data.size(); ++c) {
    const std::size_t record = data.records[c];
    const std::size_t boundary = boundaryOf(record);
    if (record >= boundary) validation.push_back(c);
    else if (record + data.lookahead < boundary) train.push_back(c);
  }
}

TrainingResult trainPolicy(const Dataset& data, const TrainConfig& config,
                           const std::function<void(const EpochLoss&)>& on_epoch) {
  std::vector<std::size_t> train, validation;
  splitDataset(data, config.validation_share, train, validation);
  if (train.size() < static_cast<std::size_t>(config.batch_size) || validation.empty())
    throw core::InputError("training data: " + std::to_string(train.size()) + " training and " +
                           std::to_string(validation.size()) + " validation columns; need at least one batch (" +
                           std::to_string(config.batch_size) + ") and one validation column");
  const int rows = static_cast<int>(data.inputs.rows());
  const int beams = data.beams;

  core::Rng rng(config.seed);
  Mlp<float> net(rows, config.hidden, 2, config.activation, config.leaky_slope);
  net.initialise(rng);
  MlpParameters<float> grad = MlpParameters<float>::zeros(rows, config.hidden, 2);
  Adam<float> adam(net.parameters(), config.learning_rate);
  core::FastNoise noise(rng.below(~0ull));

  TrainingResult result;
  result.train_columns = train.size();
  result.validation_columns = validation.size();
  // The mean-command predictor: the training targets' mean, scored on the validation columns.
  Eigen::Vector2d mean = Eigen::Vector2d::Zero();
  for (std::size_t c : train) mean += data.targets.col(static_cast<Eigen::Index>(c)).cast<double>();
  mean /= static_cast<double>(train.size());
  for (std::size_t c : validation) result.mean_predictor_loss += (data.targets.col(static_cast<Eigen::Index>(c)).cast<double>() - mean).squaredNorm();
  result.mean_predictor_loss /= static_cast<double>(validation.size());

  const auto start = std::chrono::steady_clock::now();
  const std::size_t batch = static_cast<std::size_t>(config.batch_size);
  Matrix x(rows, config.batch_size), t(2, config.batch_size);
  std::vector<std::size_t> order = train;
  // Fisher-Yates with the run's own generator: the same order on every platform.
  const auto shuffle = [&] {
    for (std::size_t i = order.size() - 1; i > 0; --i) std::swap(order[i], order[static_cast<std::size_t>(rng.below(i + 1))]);
  };
  // batches_per_epoch > 0: epochs of that many batches, read on through the order, which is
  // reshuffled whenever fewer than a batch of it are left (the remainder sits that pass out).
  std::size_t cursor = order.size();
  for (int epoch = 1; epoch <= config.epochs; ++epoch) {
    const bool full_pass = config.batches_per_epoch == 0;
    if (full_pass) shuffle();
    double loss_sum = 0.0;
    std::size_t batches = 0;
    for (std::size_t next = 0;; next += batch) {
      std::size_t first = next;
      if (full_pass) {
        if (first + batch > order.size()) break;
      } else {
        if (batches == static_cast<std::size_t>(config.batches_per_epoch)) break;
        if (cursor + batch > order.size()) {
          shuffle();
          cursor = 0;
        }
        first = cursor;
        cursor += batch;
      }
      for (std::size_t j = 0; j < batch; ++j) {
        const auto col = static_cast<Eigen::Index>(j);
        x.col(col) = data.inputs.col(static_cast<Eigen::Index>(order[first + j]));
        t.col(col) = data.targets.col(static_cast<Eigen::Index>(order[first + j]));
        if (rng.uniform01() < config.flip_probability) mirrorExample(x.col(col).data(), t.col(col).data(), beams);
        if (config.range_noise > 0.0) {
          float* ranges = x.col(col).data();
          for (int i = 0; i < beams; ++i) ranges[i] += static_cast<float>(config.range_noise * noise.normal());
        }
      }
      loss_sum += net.lossAndGradient(x, t, grad);
      adam.step(net.parameters(), grad);
      ++batches;
    }
    EpochLoss loss;
    loss.epoch = epoch;
    loss.train = loss_sum / static_cast<double>(batches);
    loss.validation = evaluate(net, data, validation);
    loss.seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
    result.history.push_back(loss);
    if (on_epoch) on_epoch(loss);
  }
  result.weights = net.parameters();
  return result;
}

std::string lossCsv(const TrainingResult& result) {
  std::string text = "epoch,train_loss,validation_loss,mean_predictor_loss,seconds\n";
  for (const EpochLoss& e : result.history) {
    text += std::to_string(e.epoch) + "," + core::formatDouble(e.train) + "," + core::formatDouble(e.validation) + "," +
            core::formatDouble(result.mean_predictor_loss) + "," + core::formatDouble(std::round(e.seconds * 1000.0) / 1000.0) + "\n";
  }
  return text;
}

}  // namespace barn::learning
