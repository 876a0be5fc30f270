// One definition for lab/sensors' sources, which compile as one unit on the
// host (cmake/SyrofHelpers.cmake).
#pragma once

namespace syrof::lab::sensors {

inline constexpr double kNanosecondsPerSecond = 1e9;

}  // namespace syrof::lab::sensors
