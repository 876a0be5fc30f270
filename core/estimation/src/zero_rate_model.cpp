#include "syrof/estimation/zero_rate_model.h"

#include <cmath>

#include "syrof/estimation/state.h"

namespace syrof::estimation {

template <typename Scalar>
bool ZeroRateDetector<Scalar>::Step(const ZeroRateConfig<Scalar>& config, Scalar rate_minus_bias_radps,
                                    int64_t now_ns) {
  if (!config.enabled || !std::isfinite(rate_minus_bias_radps) ||
      std::fabs(rate_minus_bias_radps) >= config.below_radps) {
    quiet_ = false;
    return false;
  }
  if (!quiet_) {
    quiet_ = true;
    quiet_since_ns_ = now_ns;
  }
  return now_ns - quiet_since_ns_ >= config.after_ns;
}

template <typename Scalar>
EstimationError FuseZeroRate(Ekf<Scalar>& filter, Scalar measured_rate_radps, const ZeroRateConfig<Scalar>& config) {
  ScalarMeasurement<Scalar> measurement;
  measurement.variance = config.sigma_radps * config.sigma_radps;
  measurement.count = 1;
  measurement.index[0] = kStateGyroBias;
  measurement.jacobian[0] = 1;
  measurement.innovation = measured_rate_radps - filter.state()[kStateGyroBias];
  return filter.Update(measurement, config.gate_sigma);
}

template class ZeroRateDetector<float>;
template class ZeroRateDetector<double>;
template EstimationError FuseZeroRate<float>(Ekf<float>&, float, const ZeroRateConfig<float>&);
template EstimationError FuseZeroRate<double>(Ekf<double>&, double, const ZeroRateConfig<double>&);

}  // namespace syrof::estimation
