// What the estimator does with one UWB sweep, as pure functions beside the
// math: which ranges are usable, when a sweep may only place the robot by a
// fix, when it is screened as a whole, and when the estimate declares itself
// lost. The estimator's Kalman task (estimator.h) only hands each sweep to
// ApplySweep(); everything here takes its state in and gives it back, so each
// rule has its own test (tests/core/estimation/uwb_screen_test.cpp).
//
// The rules, by the position's largest standard deviation s (EstimatorConfig
// has the thresholds and why):
//   s > fix_above_sigma_m      lost: the sweep's linearized updates could
//                              settle anywhere, so only a consistent fix
//                              (MultilaterateOnPlaneRobust) may place the
//                              robot: the re-fix. A sweep that gives none
//                              places nobody.
//   s > screen_above_sigma_m   uncertain: one range's gate is too wide to
//                              stop an outlier, so the sweep is screened as a
//                              whole (FindInconsistentRange) and its worst
//                              range dropped if it does not fit; the rest go
//                              through their gates.
//   otherwise                  steady: every range through its own gate.
// A sweep whose gate (or screen) rejects two ranges or more is inconsistent;
// max_inconsistent_sweeps in a row inflate the position variance (the
// estimate is lost, and the next consistent sweep gives a fix).
#pragma once

#include <cstddef>
#include <cstdint>
#include <span>

#include "syrof/base/result.h"
#include "syrof/estimation/ekf.h"
#include "syrof/estimation/estimation_error.h"
#include "syrof/estimation/estimator_config.h"
#include "syrof/estimation/messages.h"
#include "syrof/estimation/state.h"

namespace syrof::estimation {

/// The usable ranges of one sweep, packed for the solvers: the ranges whose
/// valid bit is set, to anchors the arena has, in anchor order.
template <typename Scalar>
struct SweepRanges {
  Vector3<Scalar> anchors[kMaxAnchors];
  Scalar ranges_m[kMaxAnchors] = {};
  int anchor_index[kMaxAnchors] = {};  ///< the arena's index of each packed range
  size_t count = 0;

  std::span<const Vector3<Scalar>> anchor_span() const { return {anchors, count}; }
  std::span<const Scalar> range_span() const { return {ranges_m, count}; }
};

/// Gathers the usable ranges of `sweep` against `arena` (the one place that
/// reads valid_mask).
template <typename Scalar>
SweepRanges<Scalar> GatherRanges(const Arena<Scalar>& arena, const UwbReading& sweep);

/// How a sweep may be used (the rules above).
enum class SweepUse : uint8_t {
  kFixOnly = 0,         ///< lost: only a consistent fix may place the robot
  kScreenThenFuse = 1,  ///< uncertain: screen the sweep as a whole, then gate each range
  kFuse = 2,            ///< steady: gate each range
};

/// The rule for a filter with `covariance`: by the larger of the x and y
/// variances against fix_above_sigma_m and screen_above_sigma_m, squared.
template <typename Scalar>
SweepUse ChooseSweepUse(const StateCovariance<Scalar>& covariance, const EstimatorConfig<Scalar>& config);

/// The position the ranges agree on (MultilaterateOnPlaneRobust on the
/// antenna plane, residuals within fix_residual_sigma * range_sigma_m, one
/// nameable outlier tolerated); kInconsistentRanges (or the solver's error)
/// when they do not.
template <typename Scalar>
base::Result<Vector2<Scalar>, EstimationError> FixFromRanges(const SweepRanges<Scalar>& ranges,
                                                             const EstimatorConfig<Scalar>& config);

/// The sweep screen at `state`: the arena index of the range that does not
/// fit (FindInconsistentRange at range_gate_sigma), or -1 when all fit or
/// fewer than four ranges leave nothing to compare.
template <typename Scalar>
int ScreenRanges(const StateVector<Scalar>& state, const SweepRanges<Scalar>& ranges,
                 const EstimatorConfig<Scalar>& config);

/// The consistency count after a sweep whose gate or screen rejected `gated`
/// ranges: one more when gated >= 2, else 0; `relocalize` when it reaches
/// max_inconsistent_sweeps (the count then starts again from 0).
struct ConsistencyUpdate {
  int inconsistent_sweeps = 0;
  bool relocalize = false;
};
ConsistencyUpdate TrackConsistency(int inconsistent_sweeps, int gated, int max_inconsistent_sweeps);

/// The pose a fix gives: its position, the configured heading, and the
/// configured initial standard deviations.
template <typename Scalar>
InitialPose<Scalar> PoseFromFix(const Vector2<Scalar>& position, const EstimatorConfig<Scalar>& config);

/// Restarts `filter` at `pose`, at rest and with zero gyro bias (standard
/// deviations of velocity and bias from `config`). Every (re)start of the
/// filter goes through here: SetInitialPose() and the first fix.
template <typename Scalar>
void StartFilter(Ekf<Scalar>& filter, const InitialPose<Scalar>& pose, const EstimatorConfig<Scalar>& config);

/// Starts `filter` from `sweep` if its ranges give a fix; false (filter
/// unchanged) otherwise. The sweep is then in the state: do not fuse it again.
template <typename Scalar>
bool StartFilterFromSweep(Ekf<Scalar>& filter, const UwbReading& sweep, const EstimatorConfig<Scalar>& config);

/// What ApplySweep() did, for the estimator's counters.
struct SweepOutcome {
  int fused = 0;             ///< ranges fused by the filter's updates
  int rejected = 0;          ///< ranges gated, screened out or invalid
  bool fixed = false;        ///< the re-fix placed the robot
  bool relocalized = false;  ///< the position variance was inflated
};

/// Applies every rule above to one sweep of an initialized filter.
/// `inconsistent_sweeps` is the count TrackConsistency() keeps, in and out.
/// Bounded: at most one robust fix or one screen, and one update per range.
template <typename Scalar>
SweepOutcome ApplySweep(Ekf<Scalar>& filter, int& inconsistent_sweeps, const UwbReading& sweep,
                        const EstimatorConfig<Scalar>& config);

}  // namespace syrof::estimation
