// The DWM1000 range measurement model, fused directly in the filter: one
// scalar update per anchor.
//
// Anchors are points in 3-D; the robot's antenna moves on the plane
// z = tag_height. The predicted range and its Jacobian are
//   h(x) = |(x - ax, y - ay, tag_height - az)|
//   H    = ((x - ax) / h, (y - ay) / h, 0, 0, 0, 0)
// so each range pulls the position along the line to its anchor, and an
// anchor high above the plane constrains x and y less than one at the
// antenna's height.
#pragma once

#include <Eigen/Core>
#include <span>

#include "syrof/base/result.h"
#include "syrof/estimation/ekf.h"
#include "syrof/estimation/estimation_error.h"
#include "syrof/estimation/state.h"

namespace syrof::estimation {

/// h(x): the range from the antenna at (x, y, tag_height) to `anchor`.
template <typename Scalar>
Scalar PredictRange(const StateVector<Scalar>& state, const Vector3<Scalar>& anchor, Scalar tag_height_m);

/// d h / d state, dense. Zero when the antenna is at the anchor.
template <typename Scalar>
Eigen::Matrix<Scalar, 1, kStateSize> RangeJacobian(const StateVector<Scalar>& state, const Vector3<Scalar>& anchor,
                                                   Scalar tag_height_m);

/// The linearized measurement for Ekf::Update. kInvalidMeasurement for a
/// range that is negative or not finite or sigma <= 0; kDegenerateGeometry
/// when the predicted range is under 1 mm (no direction to pull along).
template <typename Scalar>
base::Result<ScalarMeasurement<Scalar>, EstimationError> RangeMeasurement(const StateVector<Scalar>& state,
                                                                          const Vector3<Scalar>& anchor,
                                                                          Scalar tag_height_m, Scalar range_m,
                                                                          Scalar sigma_m);

/// Linearizes at the filter's state and fuses one range, gated at
/// gate_sigma (<= 0: no gate).
template <typename Scalar>
EstimationError FuseRange(Ekf<Scalar>& filter, const Vector3<Scalar>& anchor, Scalar tag_height_m, Scalar range_m,
                          Scalar sigma_m, Scalar gate_sigma);

/// Fault detection and exclusion for one sweep, as GNSS receivers check
/// their satellites (RAIM): every range is linearized at the state's
/// position, the common position offset that best explains the innovations
/// is fitted by least squares, and each range's residual is standardized by
/// its share of the redundancy, e / (sigma sqrt(1 - leverage)). Returns the
/// index (into `anchors`) of the range with the largest standardized
/// residual if that exceeds `threshold_sigma`, else -1. Needs four ranges or
/// more (two to spare over the two unknowns, to tell which one is wrong);
/// -1 otherwise, and for degenerate geometry. The gate of a single range
/// cannot do this when the position itself is uncertain: its window is then
/// wide enough to let an outlier in.
template <typename Scalar>
int FindInconsistentRange(const StateVector<Scalar>& state, std::span<const Vector3<Scalar>> anchors,
                          std::span<const Scalar> ranges_m, Scalar tag_height_m, Scalar sigma_m,
                          Scalar threshold_sigma);

}  // namespace syrof::estimation
