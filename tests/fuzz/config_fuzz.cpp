// Fuzz target: the YAML config reader (core::ConfigNode::parseString + core::readConfig) on
// real config structs: the simulation config (bench::EpisodeConfig, configs/sim/*.yaml) and
// the LfLH training config (learning::LflhPipelineConfig, configs/lflh/*.yaml). Both are header-only
// field lists; the controller configs would pull in the navigation stack's sources.
//
// Bad input must end in core::InputError. A config that reads must also write back (the
// manifest's effective config) and read again to the same text.

#include <cstddef>
#include <cstdint>
#include <string>

#include "barn/bench/episode.hpp"
#include "barn/core/config.hpp"
#include "barn/core/errors.hpp"
#include "barn/learning/lflh_config.hpp"
#include "fuzz_check.hpp"

namespace {

using namespace barn;

// Reads T from `node`; if that works, checks write -> read -> write gives the same text.
template <class T>
void readAndRoundTrip(const core::ConfigNode& node) {
  T config;
  try {
    config = core::readConfig<T>(node);
  } catch (const core::InputError&) {
    return;
  }
  const std::string written = core::writeConfig(config);
  std::string rewritten;
  try {
    rewritten = core::writeConfig(core::readConfig<T>(core::ConfigNode::parseString(written, "written.yaml")));
  } catch (const core::InputError& e) {
    fuzz::propertyFailed("a config that was read does not read back after writing", written, e.what());
  }
  if (rewritten != written) fuzz::propertyFailed("write, read, write changed the config", written, rewritten);
}

}  // namespace

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  const std::string text(reinterpret_cast<const char*>(data), size);
  core::ConfigNode node;
  try {
    node = core::ConfigNode::parseString(text, "fuzz.yaml");
  } catch (const core::InputError&) {
    return 0;
  }
  readAndRoundTrip<bench::EpisodeConfig>(node);
  readAndRoundTrip<learning::LflhPipelineConfig>(node);
  return 0;
}
