#pragma once
/// Seeded random numbers that give the same draws on every platform and standard library.
///
/// The standard distributions (`std::uniform_real_distribution`, `std::normal_distribution`)
/// are implementation-defined, so a world generated with libstdc++ could differ from one
/// generated with libc++. Rng draws from `std::mt19937_64`, whose output the standard fixes,
/// and turns it into doubles, integers and Gaussians with its own arithmetic.

#include <cstdint>
#include <random>

namespace barn::core {

/// SplitMix64 finaliser: a well-mixed 64-bit hash, used to derive independent seeds.
std::uint64_t splitMix64(std::uint64_t x);

/// Seed of a sub-stream (world, trial, ...) that does not depend on thread scheduling.
std::uint64_t mixSeed(std::uint64_t base, std::uint64_t a, std::uint64_t b = 0);

class Rng {
 public:
  explicit Rng(std::uint64_t seed) : engine_(seed) {}

  /// Uniform double in [0, 1) with 53 random bits.
  double uniform01();
  /// Uniform integer in [0, n) without modulo bias; n must be > 0.
  std::uint64_t below(std::uint64_t n);
  /// Standard normal N(0, 1) by the Box–Muller transform (one value per call).
  double normal();

 private:
  std::mt19937_64 engine_;
};

}  // namespace barn::core
