#include "syrof/estimation/estimation_error.h"

namespace syrof::estimation {

const char* ToString(EstimationError error) {
  switch (error) {
    case EstimationError::kOk: return "Ok";
    case EstimationError::kRejectedByGate: return "RejectedByGate";
    case EstimationError::kInvalidMeasurement: return "InvalidMeasurement";
    case EstimationError::kNumericalFailure: return "NumericalFailure";
    case EstimationError::kDegenerateGeometry: return "DegenerateGeometry";
    case EstimationError::kTooFewAnchors: return "TooFewAnchors";
    case EstimationError::kNoConvergence: return "NoConvergence";
    case EstimationError::kInconsistentRanges: return "InconsistentRanges";
    case EstimationError::kNotInitialized: return "NotInitialized";
  }
  return "?";
}

}  // namespace syrof::estimation
