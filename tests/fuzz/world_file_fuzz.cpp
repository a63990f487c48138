// Fuzz target: the world-file reader (core::parseWorldFile).
//
// Bad input must end in core::InputError. A world that reads must also write back and read
// again to the same text, since formatWorldFile is byte-stable (a silently wrong read shows
// up as a difference).

#include <cstddef>
#include <cstdint>
#include <string>

#include "barn/core/errors.hpp"
#include "barn/core/world_file.hpp"
#include "fuzz_check.hpp"

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  using namespace barn;
  const std::string text(reinterpret_cast<const char*>(data), size);
  core::WorldSpec world;
  try {
    world = core::parseWorldFile(text, "fuzz.yaml");
  } catch (const core::InputError&) {
    return 0;
  }
  const std::string written = core::formatWorldFile(world);
  std::string rewritten;
  try {
    rewritten = core::formatWorldFile(core::parseWorldFile(written, "written.yaml"));
  } catch (const core::InputError& e) {
    fuzz::propertyFailed("a world that was read does not read back after writing", written, e.what());
  }
  if (rewritten != written) fuzz::propertyFailed("write, read, write changed the world file", written, rewritten);
  return 0;
}
