// A small deterministic random generator for the scene generator: splitmix64 with our own
// uniform and normal transforms, so the same seed gives the same scene with every standard library.
#pragma once

#include <cmath>
#include <cstdint>

namespace ellipsekit::scenes {

// splitmix64's output function: a bijective 64-bit mixer.
inline std::uint64_t Mix64(std::uint64_t z) {
  z = (z ^ (z >> 30)) * 0xBF58476D1CE4E5B9ull;
  z = (z ^ (z >> 27)) * 0x94D049BB133111EBull;
  return z ^ (z >> 31);
}

class Rng {
 public:
  explicit Rng(std::uint64_t seed) : state_(seed) {}

  std::uint64_t Next() {
    state_ += 0x9E3779B97F4A7C15ull;
    return Mix64(state_);
  }
  // [0, 1), 53 random bits.
  double Uniform() { return static_cast<double>(Next() >> 11) * (1.0 / 9007199254740992.0); }
  double Uniform(double lo, double hi) { return lo + (hi - lo) * Uniform(); }
  // Integer in [lo, hi] (inclusive); the modulo bias is below 2^-32 for the small ranges used here.
  int Int(int lo, int hi) {
    if (hi <= lo) return lo;
    const std::uint64_t span = static_cast<std::uint64_t>(hi - lo) + 1;
    return lo + static_cast<int>(Next() % span);
  }
  bool Chance(double p) { return Uniform() < p; }
  // Standard normal by Box-Muller (both outputs used).
  double Normal() {
    if (has_spare_) {
      has_spare_ = false;
      return spare_;
    }
    double u1 = Uniform();
    if (u1 < 1e-300) u1 = 1e-300;
    const double u2 = Uniform();
    const double r = std::sqrt(-2.0 * std::log(u1));
    const double ang = 6.283185307179586476925 * u2;
    spare_ = r * std::sin(ang);
    has_spare_ = true;
    return r * std::cos(ang);
  }

 private:
  std::uint64_t state_;
  double spare_ = 0;
  bool has_spare_ = false;
};

}  // namespace ellipsekit::scenes
