#include "core/random.h"

#include <cmath>
#include <vector>

namespace aerograsp {
namespace {

std::uint64_t SplitMix64(std::uint64_t* x) {
  std::uint64_t z = (*x += 0x9E3779B97F4A7C15ull);
  z = (z ^ (z >> 30)) * 0xBF58476D1CE4E5B9ull;
  z = (z ^ (z >> 27)) * 0x94D049BB133111EBull;
  return z ^ (z >> 31);
}

constexpr int kTableBits = 16;  // FastNormal in random.h takes 16 bits per sample

/// Box-Muller samples of a fixed generator, shifted and scaled so that the
/// table's mean is exactly 0 and its variance exactly 1.
const std::vector<float>& NormalTable() {
  static const std::vector<float> table = [] {
    // Box-Muller on splitmix64 uniforms in (0, 1].
    std::uint64_t state = 0x5EEDull;
    auto uniform = [&state] {
      return (static_cast<double>(SplitMix64(&state) >> 11) + 1.0) * 0x1.0p-53;
    };
    std::vector<double> values(1u << kTableBits);
    double sum = 0.0;
    for (std::size_t i = 0; i < values.size(); i += 2) {
      const double r = std::sqrt(-2.0 * std::log(uniform())), a = 2.0 * M_PI * uniform();
      values[i] = r * std::cos(a);
      values[i + 1] = r * std::sin(a);
      sum += values[i] + values[i + 1];
    }
    const double mean = sum / values.size();
    double sq = 0.0;
    for (double& v : values) {
      v -= mean;
      sq += v * v;
    }
    const double scale = 1.0 / std::sqrt(sq / values.size());
    std::vector<float> out(values.size());
    for (std::size_t i = 0; i < values.size(); ++i) out[i] = static_cast<float>(values[i] * scale);
    return out;
  }();
  return table;
}

}  // namespace

FastRandom::FastRandom(std::uint64_t seed) : normal_table_(NormalTable().data()) {
  for (auto& s : s_) s = SplitMix64(&seed);
}

double FastRandom::Normal() {
  if (has_spare_) {
    has_spare_ = false;
    return spare_;
  }
  double u1 = Uniform();
  while (u1 <= 0.0) u1 = Uniform();
  const double u2 = Uniform();
  const double r = std::sqrt(-2.0 * std::log(u1));
  spare_ = r * std::sin(2.0 * M_PI * u2);
  has_spare_ = true;
  return r * std::cos(2.0 * M_PI * u2);
}

}  // namespace aerograsp
