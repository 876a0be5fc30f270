// What the estimator is told at construction (EstimatorConfig) and when given
// a pose (InitialPose): plain parameters, shared by the estimator's tasks
// (estimator.h) and the pure sweep policy they call (uwb_screen.h).
#pragma once

#include <cstdint>

#include "syrof/estimation/arena.h"
#include "syrof/estimation/ekf.h"
#include "syrof/estimation/flow_model.h"
#include "syrof/estimation/zero_rate_model.h"

namespace syrof::estimation {

/// Everything the estimator needs to know, fixed at construction.
template <typename Scalar>
struct EstimatorConfig {
  Arena<Scalar> arena = DefaultArena<Scalar>();
  FlowGeometry<Scalar> flow_geometry{};
  EkfParams<Scalar> filter{};
  Scalar flow_sigma_px = 2;                            ///< pixel noise of one flow reading
  Scalar range_sigma_m = static_cast<Scalar>(0.10);   ///< DWM1000 range noise
  /// Ranges further than this many standard deviations from the prediction
  /// are outliers (3.5: a good range is lost once in 2000).
  Scalar range_gate_sigma = static_cast<Scalar>(3.5);
  Scalar flow_gate_sigma = 5;
  /// Flow readings tell the heading only above this speed (FuseBodyVelocity).
  Scalar flow_heading_min_speed_mps = static_cast<Scalar>(0.1);
  /// Zero-rate updates while the robot does not turn (zero_rate_model.h).
  ZeroRateConfig<Scalar> zero_rate{};
  /// A sweep is inconsistent when the gate rejects two or more of its
  /// ranges. After this many inconsistent sweeps in a row the estimate is
  /// lost (the robot was carried away, or the filter settled on a wrong
  /// solution): the position variance is inflated by
  /// relocalization_variance_m2, so that the next consistent sweep gives a
  /// fix. (Two outliers in one sweep of four happen in 5 % of sweeps even at
  /// a 10 % outlier rate; five such sweeps in a row, once in 2.5 million.)
  int max_inconsistent_sweeps = 5;
  Scalar relocalization_variance_m2 = 1;
  /// While the position's standard deviation exceeds this, sweeps do not go
  /// through the filter's linearized updates (which can settle on a wrong
  /// solution from far away): a sweep places the robot by least squares, with
  /// standard deviation initial_position_sigma_m, if its ranges agree
  /// within fix_residual_sigma range sigmas, or if exactly one subset without
  /// one range does (MultilaterateOnPlaneRobust); otherwise the sweep places
  /// nobody. The first placement follows the same rule.
  Scalar fix_above_sigma_m = static_cast<Scalar>(0.5);
  Scalar fix_residual_sigma = 3;
  /// While the position's standard deviation exceeds this, the gate of one
  /// range is too wide to stop an outlier, so each sweep of four ranges or
  /// more is first screened as a whole (FindInconsistentRange, at
  /// range_gate_sigma) and its worst-fitting range dropped if it does not
  /// fit. Below it (the steady state) the screen is skipped, and costs nothing.
  Scalar screen_above_sigma_m = static_cast<Scalar>(0.1);
  /// Initialization from the first UWB sweep (and later fixes): heading (no
  /// sensor gives an absolute heading at rest) and the standard deviations
  /// it starts with.
  Scalar initial_heading_rad = 0;
  Scalar initial_heading_sigma_rad = static_cast<Scalar>(0.3);
  Scalar initial_position_sigma_m = static_cast<Scalar>(0.3);
  Scalar initial_velocity_sigma_mps = static_cast<Scalar>(0.3);
  Scalar initial_gyro_bias_sigma_radps = static_cast<Scalar>(0.02);
  /// A step longer than this (a paused robot resumed) predicts over this long.
  int64_t max_step_ns = 100'000'000;
  /// kEstimateUwbStale is set when no range was fused for this long.
  int64_t uwb_stale_ns = 1'000'000'000;
};

/// A known starting pose (SetInitialPose).
template <typename Scalar>
struct InitialPose {
  Scalar x_m = 0;
  Scalar y_m = 0;
  Scalar heading_rad = 0;
  Scalar position_sigma_m = static_cast<Scalar>(0.1);
  Scalar heading_sigma_rad = static_cast<Scalar>(0.1);
};

}  // namespace syrof::estimation
