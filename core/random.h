// A small, fast, seeded random generator whose sequence is the same on every
// platform and standard library (std::normal_distribution is not), for the
// simulator's noise. Not for cryptography.
#pragma once

#include <cstdint>

namespace aerograsp {

class FastRandom {
 public:
  /// Every seed, including 0, gives a distinct, valid state (splitmix64 init).
  explicit FastRandom(std::uint64_t seed);

  /// xoshiro256** output.
  std::uint64_t Next();
  /// Uniform in [0, 1).
  double Uniform() { return static_cast<double>(Next() >> 11) * 0x1.0p-53; }
  /// Uniform in [lo, hi).
  double Uniform(double lo, double hi) { return lo + (hi - lo) * Uniform(); }
  /// Standard normal by Box-Muller (exact, ~20 ns).
  double Normal();
  /// Standard normal from a 65,536-entry table of Box-Muller samples (~2 ns):
  /// exact mean 0 and variance 1 over the table, tails cut at about 4.5 sigma.
  /// For per-pixel image noise.
  float FastNormal();

 private:
  std::uint64_t s_[4];
  double spare_ = 0.0;
  bool has_spare_ = false;
};

}  // namespace aerograsp
