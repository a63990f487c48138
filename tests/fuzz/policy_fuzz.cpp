// Fuzz target: the policy file readers (learning::Policy::parse for LfLH files,
// learning::TransformerPolicy::parse for transformer files, learning::ApplrPolicy::parse for
// APPLR actors: what their load() runs on the file's bytes).
//
// Bad input must end in core::InputError. A policy that loads must also act: one scan of its
// beam count goes through the network (the shapes the header promised must hold).

#include <cstddef>
#include <cstdint>
#include <string>

#include "barn/core/errors.hpp"
#include "barn/learning/applr_policy.hpp"
#include "barn/learning/policy.hpp"
#include "barn/learning/transformer_policy.hpp"

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  using namespace barn;
  const std::string bytes(reinterpret_cast<const char*>(data), size);
  try {
    const learning::Policy policy = learning::Policy::parse(bytes, "fuzz.policy");
    core::LaserScan scan;
    scan.ranges.assign(static_cast<std::size_t>(policy.info().beams), 1.0);
    policy.act(scan, {1.0, 0.0});
  } catch (const core::InputError&) {
  }
  try {
    const learning::TransformerPolicy policy = learning::TransformerPolicy::parse(bytes, "fuzz.policy");
    core::LaserScan scan;
    scan.ranges.assign(static_cast<std::size_t>(policy.info().shape.beams), 1.0);
    policy.act(scan, {1.0, 0.0});
  } catch (const core::InputError&) {
  }
  try {
    const learning::ApplrPolicy policy = learning::ApplrPolicy::parse(bytes, "fuzz.policy");
    core::LaserScan scan;
    scan.ranges.assign(static_cast<std::size_t>(policy.info().beams), 1.0);
    policy.act(scan, 0.5);
  } catch (const core::InputError&) {
  }
  return 0;
}
