#include "syrof/firmware/drivers/sensor_frames.h"

#include <cmath>

namespace syrof::firmware::drivers {

static_assert(kLinkAnchors == static_cast<size_t>(estimation::kMaxAnchors), "a kUwb frame carries every anchor");

ImuPayload ToPayload(const estimation::ImuReading& reading) {
  ImuPayload payload;
  for (size_t i = 0; i < 3; ++i) {
    payload.accel_g[i] = reading.accel_g[i];
    payload.gyro_dps[i] = reading.gyro_dps[i];
  }
  return payload;
}

FlowPayload ToPayload(const estimation::FlowReading& reading) {
  FlowPayload payload;
  payload.interval_ns = reading.interval_ns == 0 ? 1 : reading.interval_ns;
  payload.delta_x_px = reading.delta_x_px;
  payload.delta_y_px = reading.delta_y_px;
  return payload;
}

UwbPayload ToPayload(const estimation::UwbReading& reading) {
  UwbPayload payload;
  payload.sweep = static_cast<uint8_t>(reading.sweep & 0xFF);
  for (size_t i = 0; i < kLinkAnchors; ++i) {
    if ((reading.valid_mask & (1u << i)) == 0) continue;
    const float range_m = reading.range_m[i];
    if (!std::isfinite(range_m) || range_m < 0 || range_m > 65.535f) continue;
    payload.range_mm[i] = static_cast<uint16_t>(std::lround(range_m * 1000.0f));
    payload.valid_mask = static_cast<uint8_t>(payload.valid_mask | (1u << i));
  }
  return payload;
}

DrivePayload ToPayload(const motion::DriveCommand& command) {
  DrivePayload payload;
  payload.kind = static_cast<uint8_t>(command.kind);
  const float values[] = {command.vx_mps, command.vy_mps, command.yaw_rate_radps, command.left_mps,
                          command.right_mps};
  for (const float value : values) {
    if (!std::isfinite(value)) return payload;
  }
  payload.vx_mps = command.vx_mps;
  payload.vy_mps = command.vy_mps;
  payload.yaw_rate_radps = command.yaw_rate_radps;
  payload.left_mps = command.left_mps;
  payload.right_mps = command.right_mps;
  return payload;
}

estimation::ImuReading ToReading(const ImuPayload& payload, int64_t timestamp_ns) {
  estimation::ImuReading reading{};
  reading.timestamp_ns = timestamp_ns;
  for (size_t i = 0; i < 3; ++i) {
    reading.accel_g[i] = payload.accel_g[i];
    reading.gyro_dps[i] = payload.gyro_dps[i];
  }
  return reading;
}

estimation::FlowReading ToReading(const FlowPayload& payload, int64_t timestamp_ns) {
  estimation::FlowReading reading{};
  reading.timestamp_ns = timestamp_ns;
  reading.interval_ns = payload.interval_ns;
  reading.delta_x_px = payload.delta_x_px;
  reading.delta_y_px = payload.delta_y_px;
  return reading;
}

estimation::UwbReading ToReading(const UwbPayload& payload, int64_t timestamp_ns) {
  estimation::UwbReading reading{};
  reading.timestamp_ns = timestamp_ns;
  reading.valid_mask = payload.valid_mask;
  reading.sweep = payload.sweep;
  for (size_t i = 0; i < kLinkAnchors; ++i) {
    if ((payload.valid_mask & (1u << i)) != 0) reading.range_m[i] = static_cast<float>(payload.range_mm[i]) * 1e-3f;
  }
  return reading;
}

motion::DriveCommand ToCommand(const DrivePayload& payload, int64_t timestamp_ns) {
  motion::DriveCommand command;
  command.timestamp_ns = timestamp_ns;
  command.kind = static_cast<motion::DriveKind>(payload.kind);
  command.vx_mps = payload.vx_mps;
  command.vy_mps = payload.vy_mps;
  command.yaw_rate_radps = payload.yaw_rate_radps;
  command.left_mps = payload.left_mps;
  command.right_mps = payload.right_mps;
  return command;
}

}  // namespace syrof::firmware::drivers
