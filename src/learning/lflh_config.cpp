#include "barn/learning/lflh_config.hpp"

#include "barn/core/config.hpp"
#include "barn/core/text_io.hpp"

namespace barn::learning {

void validate(const CollectConfig& c, core::Errors& e, const std::string& p) {
  core::validateFields(c, e, p);
  e.check(c.command_rate > 0.0 && c.command_rate <= c.record_rate, p + ".command_rate", "must be in (0, record_rate]");
  e.check(c.max_speed > c.min_speed && c.max_speed <= 2.0, p + ".max_speed", "must be in (min_speed, 2] m/s (the Jackal's limit)");
  e.check(c.max_hold >= c.min_hold, p + ".max_hold", "must be >= min_hold");
}

void validate(const HallucinationConfig& c, core::Errors& e, const std::string& p) {
  core::validateFields(c, e, p);
  e.check(c.horizon_max >= c.horizon_min, p + ".horizon_max", "must be >= horizon_min");
  e.check(c.clearance_max >= c.clearance_min, p + ".clearance_max", "must be >= clearance_min");
  e.check(c.constraining_max >= c.constraining_min && c.constraining_max <= 100, p + ".constraining_max",
          "must be in [constraining_min, 100]");
  e.check(c.blocking_max >= c.blocking_min && c.blocking_max <= 100, p + ".blocking_max", "must be in [blocking_min, 100]");
  e.check(c.size_max >= c.size_min && c.size_max <= 5.0, p + ".size_max", "must be in [size_min, 5] m");
  e.check(c.distractor_size_max >= c.distractor_size_min && c.distractor_size_max <= 5.0, p + ".distractor_size_max",
          "must be in [distractor_size_min, 5] m");
  e.check(c.alternative_speeds * c.alternative_turns <= 64, p + ".alternative_turns",
          "alternative_speeds x alternative_turns must be at most 64");
}

void validate(const TrainConfig& c, core::Errors& e, const std::string& p) {
  core::validateFields(c, e, p);
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
