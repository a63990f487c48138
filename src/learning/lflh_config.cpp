#include "barn/learning/lflh_config.hpp"

#include "barn/core/config.hpp"
#include "barn/core/text_io.hpp"

namespace barn::learning {

void validate(const CollectConfig& c, core::Errors& e, const std::string& p) {
  e.check(c.duration > 0.0 && c.duration <= 1e5, p + ".duration", "must be in (0, 100000] s");
  e.check(c.record_rate > 0.0 && c.record_rate <= 200.0, p + ".record_rate", "must be in (0, 200] Hz (the physics rate)");
  e.check(c.command_rate > 0.0 && c.command_rate <= c.record_rate, p + ".command_rate", "must be in (0, record_rate]");
  e.check(c.min_speed >= 0.0, p + ".min_speed", "must be >= 0");
  e.check(c.max_speed > c.min_speed && c.max_speed <= 2.0, p + ".max_speed", "must be in (min_speed, 2] m/s (the Jackal's limit)");
  e.check(c.top_speed_share >= 0.0 && c.top_speed_share <= 1.0, p + ".top_speed_share", "must be in [0, 1]");
  e.check(c.max_turn_rate > 0.0 && c.max_turn_rate <= 4.0, p + ".max_turn_rate", "must be in (0, 4] rad/s");
  e.check(c.straight_share >= 0.0 && c.straight_share <= 1.0, p + ".straight_share", "must be in [0, 1]");
  e.check(c.min_hold > 0.0, p + ".min_hold", "must be > 0");
  e.check(c.max_hold >= c.min_hold, p + ".max_hold", "must be >= min_hold");
  e.check(c.linear_slew > 0.0, p + ".linear_slew", "must be > 0");
  e.check(c.angular_slew > 0.0, p + ".angular_slew", "must be > 0");
}

void validate(const HallucinationConfig& c, core::Errors& e, const std::string& p) {
  e.check(c.stride >= 1, p + ".stride", "must be >= 1");
  e.check(c.renders_per_sample >= 1 && c.renders_per_sample <= 100, p + ".renders_per_sample", "must be in [1, 100]");
  e.check(c.horizon_min > 0.0, p + ".horizon_min", "must be > 0");
  e.check(c.horizon_max >= c.horizon_min, p + ".horizon_max", "must be >= horizon_min");
  e.check(c.goal_time > 0.0, p + ".goal_time", "must be > 0");
  e.check(c.min_goal_distance > 0.0, p + ".min_goal_distance", "must be > 0");
  e.check(c.clearance_min >= 0.0, p + ".clearance_min", "must be >= 0");
  e.check(c.clearance_max >= c.clearance_min, p + ".clearance_max", "must be >= clearance_min");
  e.check(c.constraining_min >= 0, p + ".constraining_min", "must be >= 0");
  e.check(c.constraining_max >= c.constraining_min && c.constraining_max <= 100, p + ".constraining_max",
          "must be in [constraining_min, 100]");
  e.check(c.blocking_min >= 0, p + ".blocking_min", "must be >= 0");
  e.check(c.blocking_max >= c.blocking_min && c.blocking_max <= 100, p + ".blocking_max", "must be in [blocking_min, 100]");
  e.check(c.blocking_jitter >= 0.0 && c.blocking_jitter <= 1.5, p + ".blocking_jitter", "must be in [0, 1.5]");
  e.check(c.direction_jitter >= 0.0 && c.direction_jitter < 1.5, p + ".direction_jitter", "must be in [0, 1.5) rad");
  e.check(c.circle_share >= 0.0 && c.circle_share <= 1.0, p + ".circle_share", "must be in [0, 1]");
  e.check(c.size_min > 0.0, p + ".size_min", "must be > 0");
  e.check(c.size_max >= c.size_min && c.size_max <= 5.0, p + ".size_max", "must be in [size_min, 5] m");
  e.check(c.max_aspect >= 1.0 && c.max_aspect <= 10.0, p + ".max_aspect", "must be in [1, 10]");
  e.check(c.distractors >= 0 && c.distractors <= 100, p + ".distractors", "must be in [0, 100]");
  e.check(c.distractor_distance > 0.0, p + ".distractor_distance", "must be > 0");
  e.check(c.distractor_size_min > 0.0, p + ".distractor_size_min", "must be > 0");
  e.check(c.distractor_size_max >= c.distractor_size_min && c.distractor_size_max <= 5.0, p + ".distractor_size_max",
          "must be in [distractor_size_min, 5] m");
  e.check(c.sector_time >= 0.0, p + ".sector_time", "must be >= 0");
  e.check(c.sector_half_angle >= 0.0 && c.sector_half_angle <= 1.5707963267948966, p + ".sector_half_angle",
          "must be in [0, pi/2] rad (the sector must be convex)");
  e.check(c.candidates >= 0 && c.candidates <= 1000, p + ".candidates", "must be in [0, 1000]");
  e.check(c.alternative_speed > 0.0 && c.alternative_speed <= 10.0, p + ".alternative_speed", "must be in (0, 10] m/s");
  e.check(c.alternative_speeds >= 1 && c.alternative_speeds <= 8, p + ".alternative_speeds", "must be in [1, 8]");
  e.check(c.alternative_turn_rate >= 0.0 && c.alternative_turn_rate <= 10.0, p + ".alternative_turn_rate",
          "must be in [0, 10] rad/s");
  e.check(c.alternative_turns >= 1 && c.alternative_turns <= 63, p + ".alternative_turns", "must be in [1, 63]");
  e.check(c.alternative_speeds * c.alternative_turns <= 64, p + ".alternative_turns",
          "alternative_speeds x alternative_turns must be at most 64");
  e.check(c.sweep_step >= 0.001 && c.sweep_step <= 0.1, p + ".sweep_step", "must be in [0.001, 0.1] m");
}

void validate(const TrainConfig& c, core::Errors& e, const std::string& p) {
  e.check(c.hidden >= 1 && c.hidden <= 4096, p + ".hidden", "must be in [1, 4096]");
  e.check(c.leaky_slope > 0.0 && c.leaky_slope < 1.0, p + ".leaky_slope", "must be in (0, 1)");
  e.check(c.range_clip > 0.0 && c.range_clip <= 30.0, p + ".range_clip", "must be in (0, 30] m");
  e.check(c.learning_rate > 0.0 && c.learning_rate < 1.0, p + ".learning_rate", "must be in (0, 1)");
  e.check(c.batch_size >= 1 && c.batch_size <= 4096, p + ".batch_size", "must be in [1, 4096]");
  e.check(c.epochs >= 1 && c.epochs <= 100000, p + ".epochs", "must be in [1, 100000]");
  e.check(c.batches_per_epoch >= 0 && c.batches_per_epoch <= 1000000, p + ".batches_per_epoch", "must be in [0, 1000000]");
  e.check(c.validation_share > 0.0 && c.validation_share < 1.0, p + ".validation_share", "must be in (0, 1)");
  e.check(c.flip_probability >= 0.0 && c.flip_probability <= 1.0, p + ".flip_probability", "must be in [0, 1]");
  e.check(c.range_noise >= 0.0, p + ".range_noise", "must be >= 0");
}

void validate(const LflhPipelineConfig& c, core::Errors& e) {
  e.check(!c.name.empty() && c.name.find_first_of("/\\ ") == std::string::npos, "name",
          "must be a non-empty file name part (no spaces or slashes)");
  validate(c.collect, e);
  validate(c.hallucination, e);
  validate(c.train, e);
  for (std::size_t i = 0; i < c.also_train_on.size(); ++i)
    e.check(!c.also_train_on[i].empty(), "also_train_on[" + std::to_string(i) + "]", "must name an LfLH config file");
}

LflhPipelineConfig readLflhPipelineConfig(const std::filesystem::path& path) {
  LflhPipelineConfig config = core::readConfig<LflhPipelineConfig>(core::ConfigNode::parseFile(path));
  core::Errors errors(path.string());
  validate(config, errors);
  errors.throwIfAny();
  return config;
}

std::uint64_t configHash(const LflhPipelineConfig& config) { return core::fnv1a64(core::writeConfig(config)); }
std::uint64_t collectHash(const CollectConfig& config) { return core::fnv1a64(core::writeConfig(config)); }

}  // namespace barn::learning
