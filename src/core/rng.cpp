#include "barn/core/rng.hpp"

#include <cassert>
#include <cmath>
#include <numbers>

namespace barn::core {

std::uint64_t splitMix64(std::uint64_t x) {
  x += 0x9E3779B97F4A7C15ull;
  x = (x ^ (x >> 30)) * 0xBF58476D1CE4E5B9ull;
  x = (x ^ (x >> 27)) * 0x94D049BB133111EBull;
  return x ^ (x >> 31);
}

std::uint64_t mixSeed(std::uint64_t base, std::uint64_t a, std::uint64_t b) {
  return splitMix64(splitMix64(splitMix64(base) ^ a) ^ b);
}

double Rng::uniform01() {
  // The top 53 bits fill a double's mantissa exactly: k / 2^53, k in [0, 2^53).
  return static_cast<double>(engine_() >> 11) * 0x1.0p-53;
}

std::uint64_t Rng::below(std::uint64_t n) {
  assert(n > 0);
  // Reject the incomplete last block of 2^64 so every residue is equally likely.
  const std::uint64_t limit = UINT64_MAX - (UINT64_MAX % n + 1) % n;
  std::uint64_t x = engine_();
  while (x > limit) x = engine_();
  return x % n;
}

double Rng::normal() {
  // 1 - u is in (0, 1], so the log is finite.
  const double u1 = 1.0 - uniform01();
  const double u2 = uniform01();
  return std::sqrt(-2.0 * std::log(u1)) * std::cos(2.0 * std::numbers::pi * u2);
}

}  // namespace barn::core
