// How a sensor's axes are mounted on the robot: each body axis (x forward,
// y left, z up) is one of the sensor's axes, possibly reversed.
#pragma once

#include <cstddef>
#include <cstdint>
#include <span>

namespace syrof::firmware::drivers {

/// Where one body axis comes from: sensor axis `axis` (0 x, 1 y, 2 z) times
/// `sign` (+1 or -1).
struct AxisSource {
  uint8_t axis = 0;
  int8_t sign = 1;
};

/// Whether `map` is a signed permutation: every sign is +1 or -1 and each
/// sensor axis below map.size() is used exactly once.
bool IsSignedPermutation(std::span<const AxisSource> map);

}  // namespace syrof::firmware::drivers
