#include "barn/core/rng.hpp"

#include <cassert>
#include <cmath>
#include <limits>

namespace barn::core {

std::uint64_t mixSeed(std::uint64_t base, std::uint64_t a, std::uint64_t b) {
  return splitMix64(splitMix64(splitMix64(base) ^ a) ^ b);
}

double Rng::uniform01() {
  // The top 53 bits fill a double's mantissa exactly: k / 2^53, k in [0, 2^53).
  return toUnit(engine_());
}

std::uint64_t Rng::below(std::uint64_t n) {
  assert(n > 0);
  // Reject the incomplete last block of 2^64 so every residue is equally likely.
  const std::uint64_t limit = UINT64_MAX - (UINT64_MAX % n + 1) % n;
  std::uint64_t x = engine_();
  while (x > limit) x = engine_();
  return x % n;
}

namespace {

constexpr double kR = 3.6541528853610088;   // start of the tail
constexpr double kArea = 4.92867323399e-3;  // area of each layer

double gaussianDensity(double x) { return std::exp(-0.5 * x * x); }

detail::Ziggurat makeZiggurat() {
  detail::Ziggurat z;
  z.x[0] = kArea / gaussianDensity(kR);
  z.x[1] = kR;
  for (int i = 2; i < 256; ++i) z.x[i] = std::sqrt(-2.0 * std::log(kArea / z.x[i - 1] + gaussianDensity(z.x[i - 1])));
  z.x[256] = 0.0;
  for (int i = 0; i < 257; ++i) z.f[i] = gaussianDensity(z.x[i]);
  return z;
}

}  // namespace

const detail::Ziggurat& detail::ziggurat() {
  static const Ziggurat table = makeZiggurat();
  return table;
}

double detail::zigguratSlowPath(int layer, double x, double u1, double u2) {
  constexpr double kRetry = std::numeric_limits<double>::quiet_NaN();
  if (layer == 0) {
    // Tail beyond kR (Marsaglia 1964): accept kR + a when 2b >= a^2.
    const double a = -std::log(1.0 - u1) / kR;
    const double b = -std::log(1.0 - u2);
    return b + b >= a * a ? kR + a : kRetry;
  }
  // Wedge between the rectangle and the curve.
  const Ziggurat& z = ziggurat();
  const double y = z.f[layer] + u1 * (z.f[layer + 1] - z.f[layer]);
  return y < gaussianDensity(x) ? x : kRetry;
}

double Rng::normal() { return standardNormal(engine_); }

}  // namespace barn::core
