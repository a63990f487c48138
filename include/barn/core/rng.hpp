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



/// A stream of SplitMix64 outputs: 64 good bits per call for about a nanosecond. For the
/// LiDAR's per-beam noise, where mt19937_64 would cost more than casting the rays.
class SplitMix64 {
 public:
  using result_type = std::uint64_t;
  explicit SplitMix64(std::uint64_t seed) : state_(seed) {}
  std::uint64_t operator()() {
    state_ += 0x9E3779B97F4A7C15ull;
    std::uint64_t z = state_;
    z = (z ^ (z >> 30)) * 0xBF58476D1CE4E5B9ull;
    z = (z ^ (z >> 27)) * 0x94D049BB133111EBull;
    return z ^ (z >> 31);
  }

 private:
  std::uint64_t state_;
};

/// SplitMix64 finaliser of x: a well-mixed 64-bit hash, used to derive independent seeds.
inline std::uint64_t splitMix64(std::uint64_t x) { return SplitMix64(x)(); }

/// Uniform double in [0, 1) from the top 53 bits of a 64-bit draw.
inline double toUnit(std::uint64_t bits) { return static_cast<double>(bits >> 11) * 0x1.0p-53; }

namespace detail {
/// Marsaglia & Tsang's ziggurat for N(0, 1) with 256 layers of equal area. Layer i (1..255)
/// is the rectangle [0, x[i]] x [f(x[i]), f(x[i+1])], f(x) = exp(-x^2 / 2); layer 0 is the
/// base [0, x[1]] x [0, f(x[1])] plus the tail beyond x[1]. Built once, never changed.
struct Ziggurat {
  double x[257];
  double f[257];
};
const Ziggurat& ziggurat();
/// A draw from the tail beyond x[1] or the wedge of `layer`; nullopt-like NaN to retry.
double zigguratSlowPath(int layer, double x, double u1, double u2);
}  // namespace detail

/// Standard normal N(0, 1) from any engine with 64-bit output (std::mt19937_64, SplitMix64).
/// One draw gives the layer (8 bits), the sign (1 bit) and a 53-bit uniform; about 99% of
/// calls return after one comparison.
template <class Engine>
double standardNormal(Engine& engine, const detail::Ziggurat& z = detail::ziggurat()) {
  while (true) {
    const std::uint64_t bits = engine();
    const int layer = static_cast<int>(bits & 0xFF);
    const double sign = (bits & 0x100) ? -1.0 : 1.0;
    const double x = toUnit(bits) * z.x[layer];
    if (x < z.x[layer + 1]) return sign * x;
    const double u1 = toUnit(engine());
    const double u2 = layer == 0 ? toUnit(engine()) : 0.0;
    const double value = detail::zigguratSlowPath(layer, x, u1, u2);
    if (value == value) return sign * value;  // not NaN: accepted
  }
}

/// Seed of a sub-stream (world, trial, ...) that does not depend on thread scheduling.
std::uint64_t mixSeed(std::uint64_t base, std::uint64_t a, std::uint64_t b = 0);

/// A Gaussian noise source on SplitMix64.
class FastNoise {
 public:
  explicit FastNoise(std::uint64_t seed) : engine_(seed), table_(&detail::ziggurat()) {}
  double normal() { return standardNormal(engine_, *table_); }

 private:
  SplitMix64 engine_;
  const detail::Ziggurat* table_;  // looked up once: the hot loop skips the static's guard
};

class Rng {
 public:
  explicit Rng(std::uint64_t seed) : engine_(seed) {}

  /// Uniform double in [0, 1) with 53 random bits.
  double uniform01();
  /// Uniform integer in [0, n) without modulo bias; n must be > 0.
  std::uint64_t below(std::uint64_t n);
  /// Standard normal N(0, 1) by Marsaglia and Tsang's ziggurat (256 layers).
  double normal();

 private:
  std::mt19937_64 engine_;
};

}  // namespace barn::core
