// Conversions between estimated quantities (SI units, float) and the beacon's
// fixed-point fields.
//
// To the wire: multiply by 1000, round to nearest with ties away from zero,
// and saturate to int16 (so positions and velocities are limited to
// +-32.767 m and +-32.767 m/s; anything beyond reads as the bound). NaN
// becomes 0. Every step is exact IEEE arithmetic, so x86-64 and the
// soft-float Cortex-M4 give the same integers.
#pragma once

#include <cstdint>

namespace syrof::wire {

/// Metres to millimetres, rounded and saturated to -32768 .. 32767; NaN gives 0.
int16_t ToMillimetres(float metres);

/// Metres per second to millimetres per second, rounded and saturated to
/// -32768 .. 32767; NaN gives 0.
int16_t ToMillimetresPerSecond(float metres_per_second);

/// An angle in radians to a heading in milliradians: wrapped into [-pi, pi]
/// first, then rounded, so the result is in -3142 .. 3142 (both ends mean
/// pi). NaN and infinities give 0.
int16_t ToMilliradians(float radians);

/// Millimetres to metres.
float ToMetres(int16_t millimetres);

/// Millimetres per second to metres per second.
float ToMetresPerSecond(int16_t millimetres_per_second);

/// Milliradians to radians.
float ToRadians(int16_t milliradians);

}  // namespace syrof::wire
