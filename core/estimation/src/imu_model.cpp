#include "syrof/estimation/imu_model.h"

#include <cmath>

namespace syrof::estimation {

template <typename Scalar>
base::Result<ImuSample<Scalar>, EstimationError> ConvertImuReading(const ImuReading& reading) {
  ImuSample<Scalar> sample;
  for (int axis = 0; axis < 3; ++axis) {
    if (!std::isfinite(reading.accel_g[axis]) || !std::isfinite(reading.gyro_dps[axis])) {
      return EstimationError::kInvalidMeasurement;
    }
    sample.accel_mps2[axis] = MetresPerSecondSquaredFromG(static_cast<Scalar>(reading.accel_g[axis]));
    sample.rate_radps[axis] = RadiansPerSecondFromDegrees(static_cast<Scalar>(reading.gyro_dps[axis]));
  }
  return sample;
}

template <typename Scalar>
ImuInput<Scalar> PlanarImuInput(const ImuSample<Scalar>& sample) {
  return ImuInput<Scalar>{sample.accel_mps2[0], sample.accel_mps2[1], sample.rate_radps[2]};
}

template base::Result<ImuSample<float>, EstimationError> ConvertImuReading<float>(const ImuReading&);
template base::Result<ImuSample<double>, EstimationError> ConvertImuReading<double>(const ImuReading&);
template ImuInput<float> PlanarImuInput<float>(const ImuSample<float>&);
template ImuInput<double> PlanarImuInput<double>(const ImuSample<double>&);

}  // namespace syrof::estimation
