// Fuzz target: controller configs through the registry (controllers::prepareController of
// core::ConfigNode::parseString), the path of `barn run --config FILE`: the top level (type and
// its one block, duplicates, extra documents), every controller's fields and validation, the
// policy and external-program paths a config names.
//
// Bad input must end in core::InputError. A config that reads must make a controller, and its
// effective config (what a manifest records) must read again to the same text.

#include <cstddef>
#include <cstdint>
#include <string>

#include "barn/controllers/registry.hpp"
#include "barn/core/config.hpp"
#include "barn/core/errors.hpp"
#include "fuzz_check.hpp"

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  using namespace barn;
  const std::string text(reinterpret_cast<const char*>(data), size);
  controllers::PreparedController prepared;
  try {
    prepared = controllers::prepareController(core::ConfigNode::parseString(text, "fuzz.yaml"));
  } catch (const core::InputError&) {
    return 0;
  }
  // A config that validates makes a controller (external: the process starts only at reset).
  prepared.factory();
  std::string again;
  try {
    again = controllers::prepareController(core::ConfigNode::parseString(prepared.effective_config, "effective.yaml"))
                .effective_config;
  } catch (const core::InputError& e) {
    fuzz::propertyFailed("an effective config does not read back", prepared.effective_config, e.what());
  }
  if (again != prepared.effective_config)
    fuzz::propertyFailed("effective config changed when read back", prepared.effective_config, again);
  return 0;
}
