#include "syrof/estimation/uwb_screen.h"

#include "syrof/estimation/multilateration.h"
#include "syrof/estimation/range_model.h"

namespace syrof::estimation {

template <typename Scalar>
SweepRanges<Scalar> GatherRanges(const Arena<Scalar>& arena, const UwbReading& sweep) {
  SweepRanges<Scalar> ranges;
  for (int i = 0; i < arena.anchor_count && i < kMaxAnchors; ++i) {
    if ((sweep.valid_mask & (1u << i)) == 0) continue;
    ranges.anchors[ranges.count] = arena.anchors[i];
    ranges.ranges_m[ranges.count] = static_cast<Scalar>(sweep.range_m[i]);
    ranges.anchor_index[ranges.count] = i;
    ++ranges.count;
  }
  return ranges;
}

template <typename Scalar>
SweepUse ChooseSweepUse(const StateCovariance<Scalar>& covariance, const EstimatorConfig<Scalar>& config) {
  const Scalar largest_variance = covariance(kStateX, kStateX) > covariance(kStateY, kStateY)
                                      ? covariance(kStateX, kStateX)
                                      : covariance(kStateY, kStateY);
  if (largest_variance > config.fix_above_sigma_m * config.fix_above_sigma_m) return SweepUse::kFixOnly;
  if (largest_variance > config.screen_above_sigma_m * config.screen_above_sigma_m) {
    return SweepUse::kScreenThenFuse;
  }
  return SweepUse::kFuse;
}

template <typename Scalar>
base::Result<Vector2<Scalar>, EstimationError> FixFromRanges(const SweepRanges<Scalar>& ranges,
                                                             const EstimatorConfig<Scalar>& config) {
  return MultilaterateOnPlaneRobust<Scalar>(ranges.anchor_span(), ranges.range_span(), config.arena.tag_height_m,
                                            config.fix_residual_sigma * config.range_sigma_m);
}

template <typename Scalar>
int ScreenRanges(const StateVector<Scalar>& state, const SweepRanges<Scalar>& ranges,
                 const EstimatorConfig<Scalar>& config) {
  const int worst = FindInconsistentRange<Scalar>(state, ranges.anchor_span(), ranges.range_span(),
                                                  config.arena.tag_height_m, config.range_sigma_m,
                                                  config.range_gate_sigma);
  return worst >= 0 ? ranges.anchor_index[worst] : -1;
}

ConsistencyUpdate TrackConsistency(int inconsistent_sweeps, int gated, int max_inconsistent_sweeps) {
  // One outlier in a sweep is common (a person walks by an anchor); two or
  // more, sweep after sweep, means the estimate is wrong.
  ConsistencyUpdate update;
  update.inconsistent_sweeps = gated >= 2 ? inconsistent_sweeps + 1 : 0;
  if (update.inconsistent_sweeps >= max_inconsistent_sweeps) {
    update.relocalize = true;
    update.inconsistent_sweeps = 0;
  }
  return update;
}

template <typename Scalar>
InitialPose<Scalar> PoseFromFix(const Vector2<Scalar>& position, const EstimatorConfig<Scalar>& config) {
  InitialPose<Scalar> pose;
  pose.x_m = position[0];
  pose.y_m = position[1];
  pose.heading_rad = config.initial_heading_rad;
  pose.position_sigma_m = config.initial_position_sigma_m;
  pose.heading_sigma_rad = config.initial_heading_sigma_rad;
  return pose;
}

template <typename Scalar>
void StartFilter(Ekf<Scalar>& filter, const InitialPose<Scalar>& pose, const EstimatorConfig<Scalar>& config) {
  StateVector<Scalar> state;
  state << pose.x_m, pose.y_m, 0, 0, pose.heading_rad, 0;
  StateVector<Scalar> sigma;
  sigma << pose.position_sigma_m, pose.position_sigma_m, config.initial_velocity_sigma_mps,
      config.initial_velocity_sigma_mps, pose.heading_sigma_rad, config.initial_gyro_bias_sigma_radps;
  filter.Reset(state, sigma);
}

template <typename Scalar>
bool StartFilterFromSweep(Ekf<Scalar>& filter, const UwbReading& sweep, const EstimatorConfig<Scalar>& config) {
  const auto fix = FixFromRanges(GatherRanges(config.arena, sweep), config);
  if (!fix) return false;
  StartFilter(filter, PoseFromFix(fix.value(), config), config);
  return true;
}

template <typename Scalar>
SweepOutcome ApplySweep(Ekf<Scalar>& filter, int& inconsistent_sweeps, const UwbReading& sweep,
                        const EstimatorConfig<Scalar>& config) {
  SweepOutcome outcome;
  const SweepRanges<Scalar> ranges = GatherRanges(config.arena, sweep);
  const SweepUse use = ChooseSweepUse(filter.covariance(), config);
  if (use == SweepUse::kFixOnly) {
    const auto fix = FixFromRanges(ranges, config);
    if (fix) {
      filter.ResetPosition(fix.value()[0], fix.value()[1], config.initial_position_sigma_m);
      outcome.fixed = true;
      inconsistent_sweeps = 0;
    }
    return outcome;
  }
  const int excluded = use == SweepUse::kScreenThenFuse ? ScreenRanges(filter.state(), ranges, config) : -1;
  int gated = 0;
  for (size_t k = 0; k < ranges.count; ++k) {
    if (ranges.anchor_index[k] == excluded) {
      ++outcome.rejected;
      ++gated;
      continue;
    }
    const EstimationError error = FuseRange(filter, ranges.anchors[k], config.arena.tag_height_m, ranges.ranges_m[k],
                                            config.range_sigma_m, config.range_gate_sigma);
    if (error == EstimationError::kOk) {
      ++outcome.fused;
      continue;
    }
    ++outcome.rejected;
    if (error == EstimationError::kRejectedByGate) ++gated;
  }
  const ConsistencyUpdate update = TrackConsistency(inconsistent_sweeps, gated, config.max_inconsistent_sweeps);
  inconsistent_sweeps = update.inconsistent_sweeps;
  if (update.relocalize) {
    filter.InflatePositionVariance(config.relocalization_variance_m2);
    outcome.relocalized = true;
  }
  return outcome;
}

#define SYROF_INSTANTIATE_UWB_SCREEN(Scalar)                                                                       \
  template SweepRanges<Scalar> GatherRanges(const Arena<Scalar>&, const UwbReading&);                              \
  template SweepUse ChooseSweepUse(const StateCovariance<Scalar>&, const EstimatorConfig<Scalar>&);                \
  template base::Result<Vector2<Scalar>, EstimationError> FixFromRanges(const SweepRanges<Scalar>&,                \
                                                                        const EstimatorConfig<Scalar>&);           \
  template int ScreenRanges(const StateVector<Scalar>&, const SweepRanges<Scalar>&, const EstimatorConfig<Scalar>&); \
  template InitialPose<Scalar> PoseFromFix(const Vector2<Scalar>&, const EstimatorConfig<Scalar>&);                \
  template void StartFilter(Ekf<Scalar>&, const InitialPose<Scalar>&, const EstimatorConfig<Scalar>&);             \
  template bool StartFilterFromSweep(Ekf<Scalar>&, const UwbReading&, const EstimatorConfig<Scalar>&);             \
  template SweepOutcome ApplySweep(Ekf<Scalar>&, int&, const UwbReading&, const EstimatorConfig<Scalar>&);

SYROF_INSTANTIATE_UWB_SCREEN(float)
SYROF_INSTANTIATE_UWB_SCREEN(double)

#undef SYROF_INSTANTIATE_UWB_SCREEN

}  // namespace syrof::estimation
