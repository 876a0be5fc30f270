// SplitMix64: a tiny seeded generator whose output is fixed by its
// definition (unlike the standard distributions, whose algorithms the
// standard leaves open), so a seed gives the same numbers on every compiler,
// on the host and on the Cortex-M4. For tests, benchmarks and seed mixing;
// not for cryptography.
#pragma once

#include <cstdint>

namespace syrof::base {

/// SplitMix64's output for the generator state `value`: a fast, well-mixed
/// hash of 64 bits, also used to derive independent seeds from one seed.
constexpr uint64_t SplitMix64Hash(uint64_t value) {
  uint64_t z = value + 0x9E3779B97F4A7C15ull;
  z = (z ^ (z >> 30)) * 0xBF58476D1CE4E5B9ull;
  z = (z ^ (z >> 27)) * 0x94D049BB133111EBull;
  return z ^ (z >> 31);
}

/// The generator: Next() walks the SplitMix64 sequence from `seed`.
class SplitMix64 {
 public:
  explicit constexpr SplitMix64(uint64_t seed) : state_(seed) {}

  constexpr uint64_t Next() {
    const uint64_t out = SplitMix64Hash(state_);
    state_ += 0x9E3779B97F4A7C15ull;
    return out;
  }

  /// Uniform in [0, bound) for bound > 0 (modulo bias, negligible for small bounds).
  constexpr uint32_t Below(uint32_t bound) { return static_cast<uint32_t>(Next() % bound); }

  /// Uniform in [low, high], low <= high.
  constexpr int32_t Between(int32_t low, int32_t high) {
    return low + static_cast<int32_t>(Below(static_cast<uint32_t>(high - low + 1)));
  }

 private:
  uint64_t state_;
};

}  // namespace syrof::base
