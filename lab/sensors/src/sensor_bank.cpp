#include "syrof/lab/sensors/sensor_bank.h"

#include <algorithm>
#include <cmath>
#include <limits>
#include <numbers>

#include "syrof/base/check.h"
#include "syrof/base/split_mix64.h"
#include "units.h"

namespace syrof::lab::sensors {
namespace {

constexpr double kDegreesPerRadian = 180.0 / std::numbers::pi;

// Independent seeds for each stream from the one scenario seed.
uint64_t StreamSeed(uint64_t seed, uint64_t stream) {
  return base::SplitMix64Hash(base::SplitMix64Hash(seed) ^ base::SplitMix64Hash(stream));
}

int16_t RoundToPixels(double pixels) {
  const double bounded = std::clamp(pixels, static_cast<double>(std::numeric_limits<int16_t>::min()),
                                    static_cast<double>(std::numeric_limits<int16_t>::max()));
  return static_cast<int16_t>(std::lround(bounded));
}

bool ValidPeriod(int64_t period_ns, int64_t offset_ns) { return period_ns > 0 && offset_ns >= 0; }

bool ValidProbability(double probability) { return probability >= 0 && probability <= 1; }

}  // namespace

SensorBank::SensorBank(const SensorBankConfig& config, uint64_t seed)
    : config_(config),
      flow_metres_per_pixel_(estimation::FlowMetresPerPixel(config.flow.geometry)),
      imu_noise_(StreamSeed(seed, 1)),
      flow_noise_(StreamSeed(seed, 2)),
      uwb_noise_(StreamSeed(seed, 3)),
      imu_{config.imu.period_ns, config.imu.offset_ns},
      flow_{config.flow.period_ns, config.flow.offset_ns},
      uwb_{config.uwb.period_ns, config.uwb.offset_ns},
      last_flow_ns_(config.flow.offset_ns - config.flow.period_ns) {
  SYROF_CHECK(ValidPeriod(config.imu.period_ns, config.imu.offset_ns));
  SYROF_CHECK(ValidPeriod(config.flow.period_ns, config.flow.offset_ns));
  SYROF_CHECK(ValidPeriod(config.uwb.period_ns, config.uwb.offset_ns));
  SYROF_CHECK(config.imu.accel_sigma_mps2 >= 0 && config.imu.gyro_sigma_radps >= 0);
  SYROF_CHECK(config.imu.accel_bias_sigma_mps2 >= 0 && config.imu.gyro_bias_sigma_radps >= 0);
  SYROF_CHECK(config.imu.accel_bias_walk_mps2_per_sqrt_s >= 0 && config.imu.gyro_bias_walk_radps_per_sqrt_s >= 0);
  SYROF_CHECK(config.flow.sigma_px >= 0 && flow_metres_per_pixel_ > 0 && std::isfinite(flow_metres_per_pixel_));
  SYROF_CHECK(config.uwb.sigma_m >= 0 && ValidProbability(config.uwb.outlier_probability) &&
              ValidProbability(config.uwb.dropout_probability));
  SYROF_CHECK(config.uwb.outlier_min_m <= config.uwb.outlier_max_m);
  SYROF_CHECK(config.arena.anchor_count >= 0 && config.arena.anchor_count <= estimation::kMaxAnchors);
  for (int axis = 0; axis < 3; ++axis) {
    imu_bias_.accel_mps2[axis] = config.imu.accel_bias_sigma_mps2 * imu_noise_.Next();
    imu_bias_.gyro_radps[axis] = config.imu.gyro_bias_sigma_radps * imu_noise_.Next();
  }
}

int64_t SensorBank::next_due_ns() const { return std::min({imu_.next_due_ns, flow_.next_due_ns, uwb_.next_due_ns}); }

void SensorBank::set_enabled(SensorKind kind, bool enabled) {
  switch (kind) {
    case SensorKind::kImu: imu_.enabled = enabled; break;
    case SensorKind::kFlow: flow_.enabled = enabled; break;
    case SensorKind::kUwb: uwb_.enabled = enabled; break;
  }
}

bool SensorBank::enabled(SensorKind kind) const {
  switch (kind) {
    case SensorKind::kImu: return imu_.enabled;
    case SensorKind::kFlow: return flow_.enabled;
    case SensorKind::kUwb: return uwb_.enabled;
  }
  return false;
}

bool SensorBank::Due(Schedule& schedule, int64_t now_ns) {
  if (schedule.next_due_ns > now_ns) return false;
  const int64_t behind = (now_ns - schedule.next_due_ns) / schedule.period_ns;
  missed_ += static_cast<uint64_t>(behind);
  schedule.next_due_ns += (behind + 1) * schedule.period_ns;
  return true;
}

void SensorBank::Sample(int64_t now_ns, const TrueState& truth, ReadingSink& sink) {
  if (Due(imu_, now_ns)) EmitImu(now_ns, truth, sink);
  if (Due(flow_, now_ns)) EmitFlow(now_ns, truth, sink);
  if (Due(uwb_, now_ns)) EmitUwb(now_ns, truth, sink);
}

void SensorBank::EmitImu(int64_t now_ns, const TrueState& truth, ReadingSink& sink) {
  const ImuModel& model = config_.imu;
  // The biases walk once per sample period whether or not the sensor reports.
  const double sqrt_period = std::sqrt(static_cast<double>(model.period_ns) / kNanosecondsPerSecond);
  for (int axis = 0; axis < 3; ++axis) {
    imu_bias_.accel_mps2[axis] += model.accel_bias_walk_mps2_per_sqrt_s * sqrt_period * imu_noise_.Next();
    imu_bias_.gyro_radps[axis] += model.gyro_bias_walk_radps_per_sqrt_s * sqrt_period * imu_noise_.Next();
  }
  // Draw the white noise even when disabled, so a switched-off sensor leaves
  // the later readings of this stream unchanged.
  double accel_noise[3];
  double gyro_noise[3];
  for (int axis = 0; axis < 3; ++axis) {
    accel_noise[axis] = model.accel_sigma_mps2 * imu_noise_.Next();
    gyro_noise[axis] = model.gyro_sigma_radps * imu_noise_.Next();
  }
  if (!imu_.enabled) return;

  const double cos_heading = std::cos(truth.heading_rad);
  const double sin_heading = std::sin(truth.heading_rad);
  // Specific force in the body frame: the arena acceleration rotated into the
  // body, plus the floor's push against gravity on z.
  const double specific_force[3] = {cos_heading * truth.ax_mps2 + sin_heading * truth.ay_mps2,
                                    -sin_heading * truth.ax_mps2 + cos_heading * truth.ay_mps2, kStandardGravity};
  const double rate[3] = {0.0, 0.0, truth.yaw_rate_radps};
  estimation::ImuReading reading{};
  reading.timestamp_ns = now_ns;
  for (int axis = 0; axis < 3; ++axis) {
    reading.accel_g[axis] = static_cast<float>(
        (specific_force[axis] + imu_bias_.accel_mps2[axis] + accel_noise[axis]) / kStandardGravity);
    reading.gyro_dps[axis] =
        static_cast<float>((rate[axis] + imu_bias_.gyro_radps[axis] + gyro_noise[axis]) * kDegreesPerRadian);
  }
  sink.OnImu(reading);
}

void SensorBank::EmitFlow(int64_t now_ns, const TrueState& truth, ReadingSink& sink) {
  const double noise_x = config_.flow.sigma_px * flow_noise_.Next();
  const double noise_y = config_.flow.sigma_px * flow_noise_.Next();
  // The sensor accumulates since its last read; after a gap (disabled, or a
  // late call) it reports at most two periods' worth.
  const int64_t interval_ns = std::min(now_ns - last_flow_ns_, 2 * config_.flow.period_ns);
  last_flow_ns_ = now_ns;
  if (!flow_.enabled || interval_ns <= 0) return;

  const double cos_heading = std::cos(truth.heading_rad);
  const double sin_heading = std::sin(truth.heading_rad);
  const double forward_mps = cos_heading * truth.vx_mps + sin_heading * truth.vy_mps;
  const double left_mps = -sin_heading * truth.vx_mps + cos_heading * truth.vy_mps;
  const double interval_s = static_cast<double>(interval_ns) / kNanosecondsPerSecond;
  estimation::FlowReading reading{};
  reading.timestamp_ns = now_ns;
  reading.interval_ns = static_cast<uint32_t>(interval_ns);
  reading.delta_x_px = RoundToPixels(forward_mps * interval_s / flow_metres_per_pixel_ + noise_x);
  reading.delta_y_px = RoundToPixels(left_mps * interval_s / flow_metres_per_pixel_ + noise_y);
  sink.OnFlow(reading);
}

void SensorBank::EmitUwb(int64_t now_ns, const TrueState& truth, ReadingSink& sink) {
  const UwbModel& model = config_.uwb;
  const estimation::Arena<double>& arena = config_.arena;
  estimation::UwbReading reading{};
  reading.timestamp_ns = now_ns;
  reading.sweep = uwb_sweeps_++;
  // Every anchor draws the same four numbers whether or not it reports, so
  // the stream stays aligned across dropouts and disabled periods.
  for (int i = 0; i < arena.anchor_count; ++i) {
    const double noise = model.sigma_m * uwb_noise_.Next();
    const bool outlier = uwb_noise_.Uniform() < model.outlier_probability;
    const double excess = model.outlier_min_m + (model.outlier_max_m - model.outlier_min_m) * uwb_noise_.Uniform();
    const bool dropout = uwb_noise_.Uniform() < model.dropout_probability;
    if (!uwb_.enabled) continue;
    if (dropout) {
      ++uwb_dropouts_;
      continue;
    }
    const double dx = truth.x_m - arena.anchors[i][0];
    const double dy = truth.y_m - arena.anchors[i][1];
    const double dz = arena.tag_height_m - arena.anchors[i][2];
    double range = std::sqrt(dx * dx + dy * dy + dz * dz) + noise;
    if (outlier) {
      range += excess;
      ++uwb_outliers_;
    }
    reading.range_m[i] = static_cast<float>(std::max(range, 0.0));
    reading.valid_mask |= 1u << i;
  }
  if (uwb_.enabled) sink.OnUwb(reading);
}

}  // namespace syrof::lab::sensors
