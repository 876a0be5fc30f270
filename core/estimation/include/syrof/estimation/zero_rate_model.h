// Zero-rate updates: while the robot does not turn, its gyro reads its own
// bias, so the bias is measured directly (a ZARU, the stationary update of
// inertial navigation).
//
// Why: at rest nothing else observes the heading or the bias (flow and
// ranges see the heading only through motion), so a bias estimate pulled off
// by earlier updates turns straight into heading drift, 0.01 rad/s and more:
// a robot parked for a minute believed itself 0.5 to 2 rad off its true
// heading, and an omni robot's or a rover's motion follows that wrong heading
// into its neighbours (docs/estimation.md, "Zero-rate updates").
//
// The detector sees only the gyro: the rate less the estimated bias has
// stayed below `below_radps` for `after_ns`. A robot that turns slower than
// that for that long pulls the bias towards its turn rate; `sigma_radps`
// (the measurement's noise) keeps one step's pull small, and a turn at the
// controllers' rates (tenths of a rad/s and more) is never mistaken for rest.
//
//   h(x) = b       (the gyro bias)
//   H    = (0, 0, 0, 0, 0, 1)
//   z    = the step's mean gyro rate (bias included)
#pragma once

#include <cstdint>

#include "syrof/estimation/ekf.h"
#include "syrof/estimation/estimation_error.h"
#include "syrof/base/state_digest.h"

namespace syrof::estimation {

/// When and how firmly a still robot measures its gyro bias.
template <typename Scalar>
struct ZeroRateConfig {
  bool enabled = true;
  Scalar below_radps = static_cast<Scalar>(0.02);   ///< |rate - bias| under this counts as not turning
  int64_t after_ns = 200'000'000;                   ///< ... for this long before the first update
  Scalar sigma_radps = static_cast<Scalar>(0.005);  ///< the update's noise: white gyro noise and slow turns
  Scalar gate_sigma = 5;                            ///< innovations beyond this many sigmas are not fused
};

/// Decides, one Kalman step at a time, whether the robot is still turning.
/// Plain data.
template <typename Scalar>
class ZeroRateDetector {
 public:
  /// One step: `rate_minus_bias_radps` is the step's mean gyro rate less the
  /// filter's bias, `now_ns` the step's time. True when the robot has not
  /// turned for `config.after_ns` (this step included).
  bool Step(const ZeroRateConfig<Scalar>& config, Scalar rate_minus_bias_radps, int64_t now_ns);
  /// Forget the quiet period (no IMU data, a new pose).
  void Reset() { quiet_ = false; }

  /// The quiet period into `digest` (base/state_digest.h).
  void AddToDigest(base::StateDigest& digest) const {
    digest.AddValue(quiet_);
    digest.AddValue(quiet_since_ns_);
  }

 private:
  bool quiet_ = false;
  int64_t quiet_since_ns_ = 0;
};

/// Folds in "the true yaw rate is zero": `measured_rate_radps` is the step's
/// mean gyro rate, bias included. kRejectedByGate when the gyro disagrees
/// with the bias by more than config.gate_sigma standard deviations.
template <typename Scalar>
EstimationError FuseZeroRate(Ekf<Scalar>& filter, Scalar measured_rate_radps, const ZeroRateConfig<Scalar>& config);

extern template class ZeroRateDetector<float>;
extern template class ZeroRateDetector<double>;

}  // namespace syrof::estimation
