// Seeded standard normal numbers for the simulated sensors, the same on every
// platform (std::normal_distribution's algorithm differs between standard
// libraries). The lab draws a dozen per IMU sample for every robot, so the
// method is Marsaglia and Tsang's ziggurat over SplitMix64: one 64-bit draw
// and a multiplication for about 99% of the numbers; the rest fall in a
// wedge (one exponential) or in the tail beyond 3.44 (two logarithms).
#pragma once

#include <cstdint>

#include "syrof/base/split_mix64.h"

namespace syrof::lab::sensors {

class GaussianSource {
 public:
  explicit GaussianSource(uint64_t seed) : engine_(seed) {}

  /// A standard normal number (mean 0, variance 1).
  double Next();

  /// Uniform in [0, 1), on a grid of 2^-53.
  double Uniform() { return static_cast<double>(engine_.Next() >> 11) * 0x1.0p-53; }

 private:
  base::SplitMix64 engine_;
};

}  // namespace syrof::lab::sensors
