// The optical-flow measurement model (paper, section "Implementation",
// Flow Breakout).
//
// The paper's geometry: a downward camera at height h whose field of view
// spans the viewing angle theta = 25 degrees, tilted by the mounting angle
// alpha. The ray at the far edge of the view meets the floor at angle
//   beta = (pi - theta) / 2 - alpha
// from the floor, at horizontal distance a + x = h cot(beta) from the point
// below the sensor. The image has 30 pixels per axis, so one pixel of image
// motion is
//   x = (h cot(beta) - a) / 30   metres of floor.
// The paper names a only in a figure that did not survive; here a is the
// (signed) distance to the near edge of the view, a = h tan(alpha - theta/2),
// which makes h cot(beta) - a the length of floor the 30 pixels span; with
// alpha = 0 this is 2 h tan(theta/2), the textbook footprint. The same scale
// serves both image axes, as in the paper.
//
// A reading's pixel deltas over its interval then give the velocity of the
// robot in its body frame, which the filter predicts from its state as
//   v_body = R(heading)^T (vx, vy).
// The sensor is assumed to sit on the rotation axis, so turning in place
// produces no flow.
#pragma once

#include <Eigen/Core>

#include "syrof/base/result.h"
#include "syrof/estimation/ekf.h"
#include "syrof/estimation/estimation_error.h"
#include "syrof/estimation/messages.h"
#include "syrof/estimation/state.h"

namespace syrof::estimation {

/// The paper's flow sensor geometry.
template <typename Scalar>
struct FlowGeometry {
  Scalar viewing_angle_rad = static_cast<Scalar>(25) * kPi<Scalar> / 180;  ///< theta, the effective viewing angle
  Scalar pixels = 30;                                                       ///< pixels per image axis
  Scalar height_m = static_cast<Scalar>(0.10);                              ///< h, sensor above the floor
  Scalar mounting_angle_rad = 0;                                            ///< alpha, tilt of the sensor's axis
};

/// beta = (pi - theta) / 2 - alpha.
template <typename Scalar>
Scalar FlowBeta(const FlowGeometry<Scalar>& geometry);

/// a + x = h cot(beta): the floor distance to the far edge of the view.
template <typename Scalar>
Scalar FlowFarEdgeDistance(const FlowGeometry<Scalar>& geometry);

/// a = h tan(alpha - theta / 2): the signed floor distance to the near edge.
template <typename Scalar>
Scalar FlowNearEdgeDistance(const FlowGeometry<Scalar>& geometry);

/// The paper's normalization (h cot(beta) - a) / 30: metres of floor per pixel.
template <typename Scalar>
Scalar FlowMetresPerPixel(const FlowGeometry<Scalar>& geometry);

/// A flow reading as a velocity measurement in the body frame.
template <typename Scalar>
struct BodyVelocity {
  Scalar forward_mps = 0;  ///< along body x
  Scalar left_mps = 0;     ///< along body y
  Scalar sigma_mps = 0;    ///< standard deviation of each component
};

/// Converts a reading: pixels times metres per pixel (FlowMetresPerPixel,
/// computed once per geometry) over the interval. `sigma_px` is the pixel
/// noise of one reading. kInvalidMeasurement for a zero interval or a
/// non-positive or non-finite scale or sigma.
template <typename Scalar>
base::Result<BodyVelocity<Scalar>, EstimationError> FlowToBodyVelocity(const FlowReading& reading,
                                                                      Scalar metres_per_pixel, Scalar sigma_px);

/// The same from the geometry; kInvalidMeasurement also for a geometry whose
/// far ray does not reach the floor ahead (beta outside (0, pi/2]).
template <typename Scalar>
base::Result<BodyVelocity<Scalar>, EstimationError> FlowToBodyVelocity(const FlowReading& reading,
                                                                      const FlowGeometry<Scalar>& geometry,
                                                                      Scalar sigma_px);

/// h(x): the body-frame velocity (forward, left) the state predicts.
template <typename Scalar>
Vector2<Scalar> PredictBodyVelocity(const StateVector<Scalar>& state);

/// d h / d state, dense (rows: forward, left).
template <typename Scalar>
Eigen::Matrix<Scalar, 2, kStateSize> BodyVelocityJacobian(const StateVector<Scalar>& state);

/// Fuses both components as two scalar updates, forward then left, gated at
/// gate_sigma each (<= 0: no gate). Both are linearized at the state before
/// the first: the second's innovation is z - h(x0) - H (x1 - x0), which
/// makes the pair exactly the EKF's joint two-dimensional update (and needs
/// one sine and cosine, not two). Returns kOk if both were fused, else the
/// first error.
///
/// Below `heading_min_speed_mps` (the prior's speed) the readings say
/// nothing about the heading, and the filter is not told they do: H's heading
/// entries are dropped and what they would have carried (speed^2 times the
/// heading's variance) is added to R. Linearized at a near-zero velocity
/// estimate, the full H turns velocity noise into heading "corrections" with
/// ever smaller variance: a robot at rest ended 0.6 rad off its heading,
/// claiming 0.05 (docs/estimation.md, "At rest"). 0 keeps the full H always.
template <typename Scalar>
EstimationError FuseBodyVelocity(Ekf<Scalar>& filter, const BodyVelocity<Scalar>& velocity, Scalar gate_sigma,
                                 Scalar heading_min_speed_mps = 0);

}  // namespace syrof::estimation
