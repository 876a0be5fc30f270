#include "syrof/wire/fixed_point.h"

#include <algorithm>
#include <cmath>
#include <limits>

#include "syrof/wire/beacon.h"

namespace syrof::wire {
namespace {

constexpr float kMilliPerUnit = 1000.0f;
constexpr float kTwoPi = 6.28318530718f;

// Rounds to nearest (ties away from zero) and saturates to int16; NaN is 0.
int16_t round_saturated(float value) {
  if (std::isnan(value)) return 0;
  if (value >= static_cast<float>(std::numeric_limits<int16_t>::max())) {
    return std::numeric_limits<int16_t>::max();
  }
  if (value <= static_cast<float>(std::numeric_limits<int16_t>::min())) {
    return std::numeric_limits<int16_t>::min();
  }
  return static_cast<int16_t>(std::lround(value));
}

}  // namespace

int16_t ToMillimetres(float metres) { return round_saturated(metres * kMilliPerUnit); }

int16_t ToMillimetresPerSecond(float metres_per_second) {
  return round_saturated(metres_per_second * kMilliPerUnit);
}

int16_t ToMilliradians(float radians) {
  if (!std::isfinite(radians)) return 0;
  // remainder() is exact, so wrapping adds no error of its own, and its
  // result lies within float's pi, which rounds to 3142 mrad. The clamp states
  // the bound the decoder enforces instead of leaning on that argument.
  const int16_t milliradians = round_saturated(std::remainder(radians, kTwoPi) * kMilliPerUnit);
  return std::clamp(milliradians, kMinHeadingMilliradians, kMaxHeadingMilliradians);
}

float ToMetres(int16_t millimetres) { return static_cast<float>(millimetres) / kMilliPerUnit; }

float ToMetresPerSecond(int16_t millimetres_per_second) {
  return static_cast<float>(millimetres_per_second) / kMilliPerUnit;
}

float ToRadians(int16_t milliradians) { return static_cast<float>(milliradians) / kMilliPerUnit; }

}  // namespace syrof::wire
