#pragma once
/// Configuration of the LfLH pipeline (Learning from Learned Hallucination, Wang et al. 2021):
/// collect motions in open space, hallucinate obstacles around them, train the policy.
///
/// One file per speed limit (configs/lflh/1ms.yaml, 2ms.yaml). The robot, its physics and its
/// LiDAR are the simulator's defaults, so the rendered scans are the scans `barn run` produces.

#include <cstdint>
#include <filesystem>
#include <string>
#include <vector>

#include "barn/core/config.hpp"
#include "barn/core/errors.hpp"
#include "barn/learning/mlp.hpp"

namespace barn::learning {

/// Random smooth driving in empty space (as the published LfLH recordings: ~505 s at 50 Hz per speed).
/// Commands are holds of a random target, reached through a slew-rate ramp, sent at 25 Hz.
struct CollectConfig {
  double duration = 500.0;
  double record_rate = 50.0;
  double command_rate = 25.0;
  double min_speed = 0.15;
  double max_speed = 1.0;
  double top_speed_share = 0.4;
  double max_turn_rate = 1.3;
  double straight_share = 0.15;
  double min_hold = 0.2;
  double max_hold = 6.0;
  double linear_slew = 2.0;
  double angular_slew = 4.0;
  std::uint64_t seed = 1;

  template <class V> void visit(V& v) {
    v("duration", duration, {.unit = "s", .range = core::openClosed(0.0, 1e5), .doc = "simulated driving time"});
    v("record_rate", record_rate,
      {.unit = "Hz", .range = core::openClosed(0.0, 200.0), .doc = "odometry and command logging"});
    v("command_rate", command_rate, {.unit = "Hz", .doc = "new cmd_vel (the original explorer changed it at ~25 Hz)"});
    v("min_speed", min_speed, {.unit = "m/s", .range = core::kNonNegative, .doc = "lowest held forward speed"});
    v("max_speed", max_speed, {.unit = "m/s", .doc = "the speed limit of the policy"});
    v("top_speed_share", top_speed_share,
      {.range = core::kUnit, .doc = "share of holds at exactly max_speed (1m log: 44 % at 1.0)"});
    v("max_turn_rate", max_turn_rate,
      {.unit = "rad/s", .range = core::openClosed(0.0, 4.0), .doc = "held yaw rates are uniform in +-max_turn_rate"});
    v("straight_share", straight_share, {.range = core::kUnit, .doc = "share of holds with zero yaw rate"});
    v("min_hold", min_hold,
      {.unit = "s", .range = core::kPositive, .doc = "hold durations are log-uniform in [min_hold, max_hold]"});
    v("max_hold", max_hold, {.unit = "s"});
    v("linear_slew", linear_slew,
      {.unit = "m/s^2", .range = core::kPositive, .doc = "ramp of the command toward a new target"});
    v("angular_slew", angular_slew, {.unit = "rad/s^2", .range = core::kPositive});
    v("seed", seed);
  }
};

/// Obstacles around each recorded motion (see hallucination.hpp for the method).
struct HallucinationConfig {
  int stride = 2;
  int renders_per_sample = 1;
  double horizon_min = 1.0;
  double horizon_max = 2.0;
  double goal_time = 2.0;
  double min_goal_distance = 0.2;
  double clearance_min = 0.03;
  double clearance_max = 0.10;
  int constraining_min = 4;
  int constraining_max = 10;
  int blocking_min = 0;
  int blocking_max = 0;
  double blocking_jitter = 0.3;
  double direction_jitter = 0.6;
  double circle_share = 0.5;
  double size_min = 0.075;
  double size_max = 0.5;
  double max_aspect = 3.0;
  int distractors = 5;
  double distractor_distance = 3.0;
  double distractor_size_min = 0.2;
  double distractor_size_max = 0.5;
  double sector_time = 1.0;
  double sector_half_angle = 1.0472;
  int candidates = 0;
  double alternative_speed = 1.0;
  int alternative_speeds = 4;
  double alternative_turn_rate = 1.3;
  int alternative_turns = 9;
  double sweep_step = 0.02;
  std::uint64_t seed = 2;

  template <class V> void visit(V& v) {
    v("stride", stride, {.unit = "records", .range = core::atLeast(1), .doc = "one sample every `stride` records"});
    v("renders_per_sample", renders_per_sample,
      {.range = core::closed(1, 100), .doc = "independent obstacle draws per sample"});
    v("horizon_min", horizon_min,
      {.unit = "s", .range = core::kPositive, .doc = "the motion that obstacles hug is the next horizon s,"});
    v("horizon_max", horizon_max, {.unit = "s", .doc = "horizon uniform in [horizon_min, horizon_max]"});
    v("goal_time", goal_time,
      {.unit = "s", .range = core::kPositive, .doc = "goal = direction to the pose this far ahead"});
    v("min_goal_distance", min_goal_distance,
      {.unit = "m", .range = core::kPositive, .doc = "samples whose goal is closer are skipped"});
    v("clearance_min", clearance_min,
      {.unit = "m", .range = core::kNonNegative, .doc = "gap between a hugging obstacle and the swept footprint,"});
    v("clearance_max", clearance_max, {.unit = "m", .doc = "uniform in [clearance_min, clearance_max]"});
    v("constraining_min", constraining_min,
      {.range = core::kNonNegative, .doc = "hugging obstacles per sample, uniform count"});
    v("constraining_max", constraining_max);
    v("blocking_min", blocking_min,
      {.range = core::kNonNegative, .doc = "blocking obstacles per sample (uniform count): pushed"});
    v("blocking_max", blocking_max, {.doc = "forward, not sideways, until they hug the sweep"});
    v("blocking_jitter", blocking_jitter,
      {.unit = "rad", .range = core::closed(0.0, 1.5), .doc = "their push direction = forward +- this"});
    v("direction_jitter", direction_jitter,
      {.unit = "rad", .range = core::closedOpen(0.0, 1.5), .doc = "push direction = path normal +- this"});
    v("circle_share", circle_share,
      {.range = core::kUnit, .doc = "share of circles among obstacles (the rest ellipses)"});
    v("size_min", size_min,
      {.unit = "m", .range = core::kPositive, .doc = "circle radius / ellipse major semi-axis, uniform"});
    v("size_max", size_max, {.unit = "m"});
    v("max_aspect", max_aspect, {.range = core::closed(1.0, 10.0), .doc = "ellipse major / minor semi-axis at most"});
    v("distractors", distractors,
      {.range = core::closed(0, 100), .doc = "random obstacles kept out of the velocity sector"});
    v("distractor_distance", distractor_distance,
      {.unit = "m", .range = core::kPositive, .doc = "their centres lie within this of the robot"});
    v("distractor_size_min", distractor_size_min, {.unit = "m", .range = core::kPositive});
    v("distractor_size_max", distractor_size_max, {.unit = "m"});
    v("sector_time", sector_time,
      {.unit = "s", .range = core::kNonNegative, .doc = "velocity sector radius = |v| * sector_time"});
    v("sector_half_angle", sector_half_angle,
      {.unit = "rad", .range = core::closed(0.0, 1.5707963267948966), .doc = "+-60 degrees around the heading"});
    v("candidates", candidates,
      {.range = core::closed(0, 1000), .doc = "0: the hugging and blocking obstacles as drawn; > 0: this many drawn (each hugging or blocking, even odds), and kept greedily while one rules out an alternative motion no kept one does, at most constraining_max (hallucination.hpp, step 2c)"});
    v("alternative_speed", alternative_speed,
      {.unit = "m/s", .range = core::openClosed(0.0, 10.0), .doc = "alternatives: constant (v, w) over the horizon with v in"});
    v("alternative_speeds", alternative_speeds, {.range = core::closed(1, 8), .doc = "alternative_speed * (1..n) / n"});
    v("alternative_turn_rate", alternative_turn_rate,
      {.unit = "rad/s", .range = core::closed(0.0, 10.0), .doc = "and w in linspace(-rate, rate, alternative_turns)"});
    v("alternative_turns", alternative_turns, {.range = core::closed(1, 63)});
    v("sweep_step", sweep_step,
      {.unit = "m", .range = core::closed(0.001, 0.1), .doc = "footprint corners move at most this between swept poses"});
    v("seed", seed);
  }
};

/// The policy network and its training (the published LfLH training, unless said otherwise).
struct TrainConfig {
  int hidden = 256;
  Activation activation = Activation::Relu;
  double leaky_slope = 0.01;
  double range_clip = 2.0;
  double learning_rate = 3e-4;
  int batch_size = 32;
  int epochs = 50;
  int batches_per_epoch = 0;
  double validation_share = 0.1;
  double flip_probability = 0.5;
  double range_noise = 0.03;
  std::uint64_t seed = 3;

  template <class V> void visit(V& v) {
    v("hidden", hidden, {.range = core::closed(1, 4096), .doc = "units in each of the two hidden layers"});
    v("activation", activation, {.doc = "hidden layers: relu | leaky_relu (the published network: leaky_relu)"});
    v("leaky_slope", leaky_slope,
      {.range = core::open(0.0, 1.0), .doc = "leaky_relu's negative slope (the published network: 0.01)"});
    v("range_clip", range_clip,
      {.unit = "m", .range = core::openClosed(0.0, 30.0), .doc = "ranges are clipped to [0, range_clip]; +inf -> range_clip"});
    v("learning_rate", learning_rate, {.range = core::open(0.0, 1.0), .doc = "Adam step size"});
    v("batch_size", batch_size, {.unit = "samples", .range = core::closed(1, 4096)});
    v("epochs", epochs, {.range = core::closed(1, 100000), .doc = "epochs (the published training: 1000)"});
    v("batches_per_epoch", batches_per_epoch,
      {.range = core::closed(0, 1000000), .doc = "batches per epoch, drawn on through a reshuffled order (the published training: 100); 0: an epoch is a full pass over the training split"});
    v("validation_share", validation_share,
      {.range = core::open(0.0, 1.0), .doc = "the last share of the recording (in time) is held out"});
    v("flip_probability", flip_probability, {.range = core::kUnit, .doc = "mirror augmentation per presented sample"});
    v("range_noise", range_noise,
      {.unit = "m", .range = core::kNonNegative, .doc = "Gaussian noise on clipped ranges (training only)"});
    v("seed", seed, {.doc = "initial weights, shuffling, augmentation"});
  }
};

struct LflhPipelineConfig {
  std::string name = "lflh_1ms";  // names the recording (exploration_<name>.csv) and the policy
  CollectConfig collect;
  HallucinationConfig hallucination;
  TrainConfig train;
  /// Other LfLH config files (relative to this one's folder) whose recordings, from the same
  /// data folder and hallucinated with their own settings, join the training data (the
  /// published 2 m/s policy was trained on the 1 m/s and the 2 m/s data).
  std::vector<std::string> also_train_on;

  template <class V> void visit(V& v) {
    v("name", name); v("collect", collect); v("hallucination", hallucination); v("train", train);
    v("also_train_on", also_train_on);
  }
};

void validate(const CollectConfig& config, core::Errors& errors, const std::string& prefix = "collect");
void validate(const HallucinationConfig& config, core::Errors& errors, const std::string& prefix = "hallucination");
void validate(const TrainConfig& config, core::Errors& errors, const std::string& prefix = "train");
void validate(const LflhPipelineConfig& config, core::Errors& errors);

/// Reads and validates an LfLH config file; one InputError lists every problem.
LflhPipelineConfig readLflhPipelineConfig(const std::filesystem::path& path);

/// FNV-1a of the effective config text (defaults included): what a policy was trained with.
std::uint64_t configHash(const LflhPipelineConfig& config);
/// FNV-1a of the effective `collect` section: ties a recording to the settings that made it.
std::uint64_t collectHash(const CollectConfig& config);

}  // namespace barn::learning
