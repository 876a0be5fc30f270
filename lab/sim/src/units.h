// Seconds, the scenario's unit, to the scheduler's nanoseconds (rounded to
// the nearest): one definition for lab/sim's sources, which compile as one
// unit on the host (cmake/SyrofHelpers.cmake).
#pragma once

#include <cmath>
#include <cstdint>

namespace syrof::lab::sim {

inline int64_t Nanoseconds(double seconds) { return std::llround(seconds * 1e9); }

}  // namespace syrof::lab::sim
