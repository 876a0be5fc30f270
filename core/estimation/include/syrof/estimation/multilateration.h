// Positions from ranges alone: the paper's closed form for its four-anchor
// layout, and least squares for any layout. The filter fuses ranges one by
// one instead (range_model.h); these serve to initialize it, to check it,
// and to show where the paper's formulas go wrong (docs/estimation.md).
//
// Closed form. For anchors a_i, a_j, subtracting the sphere equations
// |p - a_i|^2 = d_i^2 and |p - a_j|^2 = d_j^2 gives a plane:
//   2 (a_j - a_i) . p = d_i^2 - d_j^2 + |a_j|^2 - |a_i|^2.
// In the layout FourAnchorLayout{L, h} (arena.h), with D_i = d_i^2:
//   pair (0,1):          x + y = (D0 - D1) / (2L) + L
//   pair (2,3):          x - y = (D2 - D3) / (2L)
//   pairs (0,2) + (1,3): z     = (D0 + D1 - D2 - D3) / (4h) + h / 2
// hence
//   x = (D0 - D1 + D2 - D3) / (4L) + L/2
//   y = (D0 - D1 - D2 + D3) / (4L) + L/2
//   z = (D0 + D1 - D2 - D3) / (4h) + h/2.
// These are the paper's perpendicular lines, with the slopes and the x/y
// assignment corrected. With four anchors the plane equations are exactly
// determined, so the closed form solves them for any ranges, noisy or not.
//
// Least squares. The plane equations against anchor 0 give a linear
// least-squares start; Gauss-Newton on the ranges themselves then minimizes
// sum (d_i - |p - a_i|)^2, the maximum-likelihood position for equal range
// noise. Bounded: at most max_iterations steps of O(anchor count).
#pragma once

#include <span>

#include "syrof/base/result.h"
#include "syrof/estimation/arena.h"
#include "syrof/estimation/estimation_error.h"
#include "syrof/estimation/state.h"

namespace syrof::estimation {

/// The closed form above. kDegenerateGeometry if side or height is not
/// positive; kInvalidMeasurement for a negative or non-finite range.
template <typename Scalar>
base::Result<Vector3<Scalar>, EstimationError> ClosedFormPosition(const FourAnchorLayout<Scalar>& layout,
                                                                  const Scalar (&ranges_m)[4]);

/// 3-D least squares from ranges to any anchors (at least 4, not coplanar).
/// kTooFewAnchors, kInvalidMeasurement (sizes differ, a range negative or
/// not finite), kDegenerateGeometry (coplanar anchors), kNoConvergence.
template <typename Scalar>
base::Result<Vector3<Scalar>, EstimationError> Multilaterate(std::span<const Vector3<Scalar>> anchors,
                                                             std::span<const Scalar> ranges_m,
                                                             int max_iterations = 10);

/// Least squares for an antenna on the plane z = height_m: (x, y) from
/// ranges to at least 3 anchors whose floor positions are not collinear.
/// Errors as Multilaterate().
template <typename Scalar>
base::Result<Vector2<Scalar>, EstimationError> MultilaterateOnPlane(std::span<const Vector3<Scalar>> anchors,
                                                                    std::span<const Scalar> ranges_m,
                                                                    Scalar height_m, int max_iterations = 10);

/// MultilaterateOnPlane that survives one outlier: the fix of all ranges if
/// every residual |d_i - |p - a_i|| is within tolerance_m; otherwise, with
/// four ranges or more, the fix of the one subset without a single range
/// that fits within tolerance_m. kInconsistentRanges if nothing fits, or if
/// two subsets fit (the outlier cannot be told). At most kMaxAnchors ranges
/// (kInvalidMeasurement beyond); at most 1 + count least-squares solves (a
/// set that does not converge counts as not fitting).
/// With three ranges to two unknowns an outlier can be seen but not named,
/// and even four cannot always name it: refusing is safer than a wrong fix.
template <typename Scalar>
base::Result<Vector2<Scalar>, EstimationError> MultilaterateOnPlaneRobust(std::span<const Vector3<Scalar>> anchors,
                                                                          std::span<const Scalar> ranges_m,
                                                                          Scalar height_m, Scalar tolerance_m);

}  // namespace syrof::estimation
