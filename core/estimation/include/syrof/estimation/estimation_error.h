// Why an estimation step did not use a reading or could not compute a result.
#pragma once

#include <cstdint>

namespace syrof::estimation {

/// Errors of the filter, the measurement models and multilateration. A
/// rejected reading leaves the filter exactly as it was.
enum class [[nodiscard]] EstimationError : uint8_t {
  kOk = 0,
  kRejectedByGate,       ///< the innovation is outside the gate (an outlier); not fused
  kInvalidMeasurement,   ///< a reading or its variance is not finite or out of range
  kNumericalFailure,     ///< the innovation variance is not positive and finite
  kDegenerateGeometry,   ///< the anchors (or the robot's place among them) determine no unique answer
  kTooFewAnchors,        ///< fewer valid ranges than unknowns
  kNoConvergence,        ///< Gauss-Newton did not settle within its iteration limit
  kInconsistentRanges,   ///< the ranges do not fit one position, even without any one of them
  kNotInitialized,       ///< the filter has no state yet
};

/// The enumerator's name without the k ("RejectedByGate"); "?" for an unknown value.
const char* ToString(EstimationError error);

}  // namespace syrof::estimation
