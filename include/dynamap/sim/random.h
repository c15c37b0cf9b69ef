#pragma once
// The simulator's only source of randomness. std::normal_distribution (and every other standard
// distribution) is implementation-defined, so the same seed would give different logs with
// different standard libraries; mt19937_64's raw output is fully specified, and the transforms
// below use only IEEE arithmetic, std::sqrt (exact) and std::log.

#include <cmath>
#include <cstdint>
#include <random>

namespace dynamap::sim {

class Rng {
 public:
  explicit Rng(std::uint64_t seed) : gen_(seed) {}

  /// Uniform in [0, 1), from the top 53 bits of one draw.
  double uniform() { return static_cast<double>(gen_() >> 11) * 0x1.0p-53; }

  /// Standard normal, Marsaglia's polar method; the second value of each pair is kept.
  double gaussian() {
    if (has_spare_) {
      has_spare_ = false;
      return spare_;
    }
    double u = 0, v = 0, s = 0;
    do {
      u = 2 * uniform() - 1;
      v = 2 * uniform() - 1;
      s = u * u + v * v;
    } while (s >= 1 || s == 0);
    const double f = std::sqrt(-2 * std::log(s) / s);
    spare_ = v * f;
    has_spare_ = true;
    return u * f;
  }

  /// A normal draw with standard deviation `std` (0 gives 0, still consuming a draw so the
  /// stream stays aligned whatever the noise settings).
  double gaussian(double std) { return std * gaussian(); }

 private:
  std::mt19937_64 gen_;
  bool has_spare_ = false;
  double spare_ = 0;
};

}  // namespace dynamap::sim
