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

#include "barn/core/errors.hpp"
#include "barn/learning/mlp.hpp"

namespace barn::learning {

/// Random smooth driving in empty space (as the published LfLH recordings: ~505 s at 50 Hz per speed).
/// Commands are holds of a random target, reached through a slew-rate ramp, sent at 25 Hz.
struct CollectConfig {
  double duration = 500.0;       // [s] simulated driving time
  double record_rate = 50.0;     // [Hz] odometry and command logging
  double command_rate = 25.0;    // [Hz] new cmd_vel (the original explorer changed it at ~25 Hz)
  double min_speed = 0.15;       // [m/s] lowest held forward speed
  double max_speed = 1.0;        // [m/s] the speed limit of the policy
  double top_speed_share = 0.4;  // [-] share of holds at exactly max_speed (1m log: 44 % at 1.0)
  double max_turn_rate = 1.3;    // [rad/s] held yaw rates are uniform in +-max_turn_rate
  double straight_share = 0.15;  // [-] share of holds with zero yaw rate
  double min_hold = 0.2;         // [s] hold durations are log-uniform in [min_hold, max_hold]
  double max_hold = 6.0;         // [s]
  double linear_slew = 2.0;      // [m/s^2] ramp of the command toward a new target
  double angular_slew = 4.0;     // [rad/s^2]
  std::uint64_t seed = 1;        // [-]

  template <class V> void visit(V& v) {
    v("duration", duration); v("record_rate", record_rate); v("command_rate", command_rate);
    v("min_speed", min_speed); v("max_speed", max_speed); v("top_speed_share", top_speed_share);
    v("max_turn_rate", max_turn_rate); v("straight_share", straight_share);
    v("min_hold", min_hold); v("max_hold", max_hold);
    v("linear_slew", linear_slew); v("angular_slew", angular_slew); v("seed", seed);
  }
};

/// Obstacles around each recorded motion (see hallucination.hpp for the method).
struct HallucinationConfig {
  int stride = 2;                   // [records] one sample every `stride` records
  int renders_per_sample = 1;       // [-] independent obstacle draws per sample
  double horizon_min = 1.0;         // [s] the motion that obstacles hug is the next horizon s,
  double horizon_max = 2.0;         // [s]   horizon uniform in [horizon_min, horizon_max]
  double goal_time = 2.0;           // [s] goal = direction to the pose this far ahead
  double min_goal_distance = 0.2;   // [m] samples whose goal is closer are skipped
  double clearance_min = 0.03;      // [m] gap between a hugging obstacle and the swept footprint,
  double clearance_max = 0.10;      // [m]   uniform in [clearance_min, clearance_max]
  int constraining_min = 4;         // [-] hugging obstacles per sample, uniform count
  int constraining_max = 10;        // [-]
  int blocking_min = 0;             // [-] blocking obstacles per sample (uniform count): pushed
  int blocking_max = 0;             // [-]   forward, not sideways, until they hug the sweep
  double blocking_jitter = 0.3;     // [rad] their push direction = forward +- this
  double direction_jitter = 0.6;    // [rad] push direction = path normal +- this
  double circle_share = 0.5;        // [-] share of circles among obstacles (the rest ellipses)
  double size_min = 0.075;          // [m] circle radius / ellipse major semi-axis, uniform
  double size_max = 0.5;            // [m]
  double max_aspect = 3.0;          // [-] ellipse major / minor semi-axis at most
  int distractors = 5;              // [-] random obstacles kept out of the velocity sector
  double distractor_distance = 3.0; // [m] their centres lie within this of the robot
  double distractor_size_min = 0.2; // [m]
  double distractor_size_max = 0.5; // [m]
  double sector_time = 1.0;         // [s] velocity sector radius = |v| * sector_time
  double sector_half_angle = 1.0472;  // [rad] +-60 degrees around the heading
  int candidates = 0;               // [-] 0: the hugging and blocking obstacles as drawn; > 0: this many
                                    //     drawn (each hugging or blocking, even odds), and kept greedily
                                    //     while one rules out an alternative motion no kept one does,
                                    //     at most constraining_max (hallucination.hpp, step 2c)
  double alternative_speed = 1.0;   // [m/s] alternatives: constant (v, w) over the horizon with v in
  int alternative_speeds = 4;       //   alternative_speed * (1..n) / n
  double alternative_turn_rate = 1.3;  // [rad/s] and w in linspace(-rate, rate, alternative_turns)
  int alternative_turns = 9;        // [-]
  double sweep_step = 0.02;         // [m] footprint corners move at most this between swept poses
  std::uint64_t seed = 2;           // [-]

  template <class V> void visit(V& v) {
    v("stride", stride); v("renders_per_sample", renders_per_sample);
    v("horizon_min", horizon_min); v("horizon_max", horizon_max); v("goal_time", goal_time);
    v("min_goal_distance", min_goal_distance); v("clearance_min", clearance_min); v("clearance_max", clearance_max);
    v("constraining_min", constraining_min); v("constraining_max", constraining_max);
    v("blocking_min", blocking_min); v("blocking_max", blocking_max); v("blocking_jitter", blocking_jitter);
    v("direction_jitter", direction_jitter); v("circle_share", circle_share);
    v("size_min", size_min); v("size_max", size_max); v("max_aspect", max_aspect);
    v("distractors", distractors); v("distractor_distance", distractor_distance);
    v("distractor_size_min", distractor_size_min); v("distractor_size_max", distractor_size_max);
    v("sector_time", sector_time); v("sector_half_angle", sector_half_angle);
    v("candidates", candidates); v("alternative_speed", alternative_speed); v("alternative_speeds", alternative_speeds);
    v("alternative_turn_rate", alternative_turn_rate); v("alternative_turns", alternative_turns);
    v("sweep_step", sweep_step); v("seed", seed);
  }
};

/// The policy network and its training (the published LfLH training, unless said otherwise).
struct TrainConfig {
  int hidden = 256;                 // [-] units in each of the two hidden layers
  Activation activation = Activation::Relu;  // hidden layers: relu | leaky_relu (the published network: leaky_relu)
  double leaky_slope = 0.01;        // [-] leaky_relu's negative slope (the published network: 0.01)
  double range_clip = 2.0;          // [m] ranges are clipped to [0, range_clip]; +inf -> range_clip
  double learning_rate = 3e-4;      // [-] Adam step size
  int batch_size = 32;              // [samples]
  int epochs = 50;                  // [-] epochs (the published training: 1000)
  int batches_per_epoch = 0;        // [-] batches per epoch, drawn on through a reshuffled order (the
                                    //     published training: 100); 0: an epoch is a full pass over the training split
  double validation_share = 0.1;    // [-] the last share of the recording (in time) is held out
  double flip_probability = 0.5;    // [-] mirror augmentation per presented sample
  double range_noise = 0.03;        // [m] Gaussian noise on clipped ranges (training only)
  std::uint64_t seed = 3;           // [-] initial weights, shuffling, augmentation

  template <class V> void visit(V& v) {
    v("hidden", hidden); v("activation", activation); v("leaky_slope", leaky_slope); v("range_clip", range_clip); v("learning_rate", learning_rate);
    v("batch_size", batch_size); v("epochs", epochs); v("batches_per_epoch", batches_per_epoch); v("validation_share", validation_share);
    v("flip_probability", flip_probability); v("range_noise", range_noise); v("seed", seed);
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
