#include "syrof/firmware/drivers/pmw3901.h"

#include <limits>

namespace syrof::firmware::drivers {
namespace pmw3901 {

MotionBurst ParseMotionBurst(std::span<const uint8_t, kBurstBytes> burst) {
  MotionBurst parsed{};
  parsed.motion = burst[0];
  parsed.observation = burst[1];
  parsed.delta_x = static_cast<int16_t>(static_cast<uint16_t>(burst[2] | (burst[3] << 8)));
  parsed.delta_y = static_cast<int16_t>(static_cast<uint16_t>(burst[4] | (burst[5] << 8)));
  parsed.squal = burst[6];
  parsed.raw_data_sum = burst[7];
  parsed.max_raw_data = burst[8];
  parsed.min_raw_data = burst[9];
  parsed.shutter = static_cast<uint16_t>((burst[10] << 8) | burst[11]);
  return parsed;
}

}  // namespace pmw3901

bool Pmw3901BurstUsable(const pmw3901::MotionBurst& burst, const Pmw3901Config& config) {
  const auto shutter_upper = static_cast<uint8_t>(burst.shutter >> 8);
  return !(burst.squal < config.min_squal && shutter_upper >= config.dark_shutter_upper);
}

base::Result<estimation::FlowReading, DriverError> DecodePmw3901Burst(
    std::span<const uint8_t, pmw3901::kBurstBytes> burst, const Pmw3901Config& config, int64_t timestamp_ns,
    uint32_t interval_ns) {
  const pmw3901::MotionBurst parsed = pmw3901::ParseMotionBurst(burst);
  if (!Pmw3901BurstUsable(parsed, config)) return DriverError::kLowQuality;
  const int32_t sensor[2] = {parsed.delta_x, parsed.delta_y};
  int16_t body[2] = {0, 0};
  for (size_t axis = 0; axis < 2; ++axis) {
    const AxisSource source = config.body_from_sensor[axis];
    const int32_t value = source.sign * sensor[source.axis];
    body[axis] = static_cast<int16_t>(value > std::numeric_limits<int16_t>::max() ? std::numeric_limits<int16_t>::max()
                                                                                  : value);
  }
  estimation::FlowReading reading{};
  reading.timestamp_ns = timestamp_ns;
  reading.interval_ns = interval_ns;
  reading.delta_x_px = body[0];
  reading.delta_y_px = body[1];
  return reading;
}

DriverError Pmw3901::Check(BusStatus status) {
  last_bus_status_ = status;
  return status == BusStatus::kOk ? DriverError::kOk : DriverError::kBus;
}

DriverError Pmw3901::WriteRegister(uint8_t reg, uint8_t value) {
  const uint8_t bytes[2] = {static_cast<uint8_t>(reg | pmw3901::kWriteBit), value};
  bus_.Select();
  const BusStatus status = bus_.Transfer(bytes, {});
  bus_.Deselect();
  return Check(status);
}

DriverError Pmw3901::ReadRegister(uint8_t reg, uint8_t& value) {
  const uint8_t address = static_cast<uint8_t>(reg & ~pmw3901::kWriteBit);
  bus_.Select();
  BusStatus status = bus_.Transfer({&address, 1}, {});
  if (status == BusStatus::kOk) {
    delay_.WaitUs(pmw3901::kReadWaitUs);
    status = bus_.Transfer({}, {&value, 1});
  }
  bus_.Deselect();
  return Check(status);
}

DriverError Pmw3901::Start(int64_t now_ns) {
  started_ = false;
  if (!IsSignedPermutation(config_.body_from_sensor)) return DriverError::kBadConfig;
  if (WriteRegister(pmw3901::kPowerUpReset, pmw3901::kPowerUpResetValue) != DriverError::kOk) return DriverError::kBus;
  delay_.WaitUs(pmw3901::kResetWaitUs);
  uint8_t product = 0;
  uint8_t inverse = 0;
  if (ReadRegister(pmw3901::kProductId, product) != DriverError::kOk ||
      ReadRegister(pmw3901::kInverseProductId, inverse) != DriverError::kOk) {
    return DriverError::kBus;
  }
  if (product != pmw3901::kProductIdValue || inverse != pmw3901::kInverseProductIdValue) {
    return DriverError::kWrongDevice;
  }
  // The datasheet's power-up step: read Motion and the deltas once, whatever they hold.
  for (uint8_t reg = pmw3901::kMotion; reg <= pmw3901::kDeltaYHigh; ++reg) {
    uint8_t ignored = 0;
    if (ReadRegister(reg, ignored) != DriverError::kOk) return DriverError::kBus;
  }
  for (const RegisterWrite& step : config_.tuning) {
    if (WriteRegister(step.reg, step.value) != DriverError::kOk) return DriverError::kBus;
    if (step.wait_us > 0) delay_.WaitUs(step.wait_us);
  }
  last_read_ns_ = now_ns;
  started_ = true;
  return DriverError::kOk;
}

base::Result<estimation::FlowReading, DriverError> Pmw3901::Read(int64_t now_ns) {
  if (!started_) return DriverError::kNotStarted;
  if (now_ns <= last_read_ns_) return DriverError::kBadTimestamp;
  const uint8_t address = pmw3901::kMotionBurst;
  std::array<uint8_t, pmw3901::kBurstBytes> burst{};
  bus_.Select();
  BusStatus status = bus_.Transfer({&address, 1}, {});
  if (status == BusStatus::kOk) {
    delay_.WaitUs(pmw3901::kReadWaitUs);
    status = bus_.Transfer({}, burst);
  }
  bus_.Deselect();
  if (Check(status) != DriverError::kOk) return DriverError::kBus;
  const int64_t interval_ns = now_ns - last_read_ns_;
  last_read_ns_ = now_ns;
  if (interval_ns > std::numeric_limits<uint32_t>::max()) return DriverError::kBadTimestamp;
  return DecodePmw3901Burst(burst, config_, now_ns, static_cast<uint32_t>(interval_ns));
}

}  // namespace syrof::firmware::drivers
