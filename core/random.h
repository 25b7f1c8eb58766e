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

  /// xoshiro256** output. Inline: the image noise calls it once per pixel or so.
  std::uint64_t Next() {
    const std::uint64_t result = Rotl(s_[1] * 5, 7) * 9;
    const std::uint64_t t = s_[1] << 17;
    s_[2] ^= s_[0];
    s_[3] ^= s_[1];
    s_[1] ^= s_[2];
    s_[0] ^= s_[3];
    s_[2] ^= t;
    s_[3] = Rotl(s_[3], 45);
    return result;
  }
  /// Uniform in [0, 1).
  double Uniform() { return static_cast<double>(Next() >> 11) * 0x1.0p-53; }
  /// Uniform in [lo, hi).
  double Uniform(double lo, double hi) { return lo + (hi - lo) * Uniform(); }
  /// Standard normal by Box-Muller (exact, ~20 ns).
  double Normal();
  /// Standard normal from a 65,536-entry table of Box-Muller samples (~1 ns;
  /// one Next() serves four calls):
  /// exact mean 0 and variance 1 over the table, tails cut at about 4.5 sigma.
  /// For per-pixel image noise.
  float FastNormal() {
    if (table_indices_left_ == 0) {
      table_bits_ = Next();
      table_indices_left_ = 4;
    }
    const float value = normal_table_[table_bits_ & 0xFFFF];
    table_bits_ >>= 16;
    --table_indices_left_;
    return value;
  }

 private:
  static std::uint64_t Rotl(std::uint64_t x, int k) { return (x << k) | (x >> (64 - k)); }
  std::uint64_t s_[4];
  const float* normal_table_;     // 65,536 entries, shared by all generators
  std::uint64_t table_bits_ = 0;  // unused 16-bit table indices of the last Next()
  int table_indices_left_ = 0;
  double spare_ = 0.0;
  bool has_spare_ = false;
};

}  // namespace aerograsp
