#pragma once
/// LfLH step 3: behaviour cloning of the hallucinated demonstrations (as the published LfLH training).
///
/// Split: the last `validation_share` of the recording in time is held out (of each recording,
/// for data joined by appendDataset: the published split, 90/10 per demonstration file); training columns
/// whose look-ahead window reaches into it are dropped, so no motion is seen on both sides.
/// Each epoch is one pass over the training columns in a seeded shuffled order, in batches of
/// batch_size (the remainder sits this epoch out); with batches_per_epoch > 0 an epoch is that
/// many batches instead, read on through the shuffled order across epochs and reshuffled when
/// it runs out (the published training: 1000 epochs of 100 batches). Each presented column is mirrored
/// with probability flip_probability and its ranges get N(0, range_noise^2) noise after
/// clipping, as in the original; validation uses the columns as they are.

#include <cstddef>
#include <functional>
#include <string>
#include <vector>

#include "barn/learning/hallucination.hpp"
#include "barn/learning/lflh_config.hpp"
#include "barn/learning/mlp.hpp"

namespace barn::learning {

/// Losses after one epoch (mean over samples of the squared v error + squared w error).
struct EpochLoss {
  int epoch = 0;                  // [-] 1-based
  double train = 0.0;             // mean batch loss over the epoch (augmented inputs)
  double validation = 0.0;        // on the held-out columns
  double seconds = 0.0;           // [s] wall time since training started
};

struct TrainingResult {
  MlpParameters<float> weights;
  std::vector<EpochLoss> history;
  double mean_predictor_loss = 0.0;  // validation loss of always predicting the training mean
  std::size_t train_columns = 0;
  std::size_t validation_columns = 0;
};

/// Indices of the training and validation columns of `data` (see the header comment).
void splitDataset(const Dataset& data, double validation_share, std::vector<std::size_t>& train,
                  std::vector<std::size_t>& validation);

/// Trains the policy network; `on_epoch` (if set) is called after every epoch. Deterministic:
/// the same data and config give the same weights bit for bit on one machine.
TrainingResult trainPolicy(const Dataset& data, const TrainConfig& config,
                           const std::function<void(const EpochLoss&)>& on_epoch = {});

/// The loss history as CSV: epoch,train_loss,validation_loss,mean_predictor_loss,seconds.
std::string lossCsv(const TrainingResult& result);

}  // namespace barn::learning
