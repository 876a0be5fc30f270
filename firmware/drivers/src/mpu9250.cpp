#include "syrof/firmware/drivers/mpu9250.h"

namespace syrof::firmware::drivers {
namespace mpu9250 {

float AccelLsbPerG(AccelRange range) { return 16384.0f / static_cast<float>(1u << static_cast<unsigned>(range)); }

float GyroLsbPerDps(GyroRange range) {
  constexpr float kSensitivity[] = {131.0f, 65.5f, 32.8f, 16.4f};
  return kSensitivity[static_cast<unsigned>(range) & 3u];
}

namespace {
int16_t BigEndian(std::span<const uint8_t, kBurstBytes> burst, size_t at) {
  return static_cast<int16_t>(static_cast<uint16_t>((burst[at] << 8) | burst[at + 1]));
}
}  // namespace

RawSample ParseBurst(std::span<const uint8_t, kBurstBytes> burst) {
  RawSample sample{};
  for (size_t axis = 0; axis < 3; ++axis) {
    sample.accel[axis] = BigEndian(burst, 2 * axis);
    sample.gyro[axis] = BigEndian(burst, 8 + 2 * axis);
  }
  sample.temperature = BigEndian(burst, 6);
  return sample;
}

float TemperatureC(int16_t raw) { return static_cast<float>(raw) / 333.87f + 21.0f; }

}  // namespace mpu9250

namespace {
// PWR_MGMT_1 values, CONFIG and ACCEL_CONFIG 2's filter setting, INT_PIN_CFG's INT_ANYRD_2CLEAR.
constexpr uint8_t kHardReset = 0x80;
constexpr uint8_t kClockAutoPll = 0x01;
constexpr uint8_t kLowPass41Hz = 0x03;
constexpr uint8_t kClearOnAnyRead = 0x10;
constexpr uint8_t kRawDataReady = 0x01;
constexpr uint32_t kResetWaitUs = 100'000;
constexpr uint32_t kClockWaitUs = 10'000;
}  // namespace

std::array<RegisterWrite, kMpu9250StartSteps> Mpu9250StartSequence(const Mpu9250Config& config) {
  using namespace mpu9250;
  return {{
      {kPowerManagement1, kHardReset, kResetWaitUs},
      {kPowerManagement1, kClockAutoPll, kClockWaitUs},
      {kPowerManagement2, 0x00, 0},
      {kConfig, kLowPass41Hz, 0},
      {kSampleRateDivider, config.sample_rate_divider, 0},
      {kGyroConfig, static_cast<uint8_t>(static_cast<uint8_t>(config.gyro_range) << 3), 0},
      {kAccelConfig, static_cast<uint8_t>(static_cast<uint8_t>(config.accel_range) << 3), 0},
      {kAccelConfig2, kLowPass41Hz, 0},
      {kIntPinConfig, kClearOnAnyRead, 0},
      {kIntEnable, kRawDataReady, 0},  // last, once the ranges are set
  }};
}

estimation::ImuReading DecodeMpu9250Burst(std::span<const uint8_t, mpu9250::kBurstBytes> burst,
                                          const Mpu9250Config& config, int64_t timestamp_ns) {
  const mpu9250::RawSample raw = mpu9250::ParseBurst(burst);
  const float accel_lsb = mpu9250::AccelLsbPerG(config.accel_range);
  const float gyro_lsb = mpu9250::GyroLsbPerDps(config.gyro_range);
  estimation::ImuReading reading{};
  reading.timestamp_ns = timestamp_ns;
  for (size_t body = 0; body < 3; ++body) {
    const AxisSource source = config.body_from_chip[body];
    const auto sign = static_cast<float>(source.sign);
    reading.accel_g[body] = sign * (static_cast<float>(raw.accel[source.axis]) / accel_lsb);
    reading.gyro_dps[body] = sign * (static_cast<float>(raw.gyro[source.axis]) / gyro_lsb);
  }
  return reading;
}

DriverError Mpu9250::Check(BusStatus status) {
  last_bus_status_ = status;
  return status == BusStatus::kOk ? DriverError::kOk : DriverError::kBus;
}

DriverError Mpu9250::Start() {
  started_ = false;
  if (!IsSignedPermutation(config_.body_from_chip)) return DriverError::kBadConfig;
  const uint8_t who_am_i_register = mpu9250::kWhoAmI;
  uint8_t who_am_i = 0;
  if (Check(bus_.WriteRead(config_.address, {&who_am_i_register, 1}, {&who_am_i, 1})) != DriverError::kOk) {
    return DriverError::kBus;
  }
  if (who_am_i != mpu9250::kWhoAmIValue) return DriverError::kWrongDevice;
  for (const RegisterWrite& step : Mpu9250StartSequence(config_)) {
    const uint8_t bytes[2] = {step.reg, step.value};
    if (Check(bus_.Write(config_.address, bytes)) != DriverError::kOk) return DriverError::kBus;
    if (step.wait_us > 0) delay_.WaitUs(step.wait_us);
  }
  started_ = true;
  return DriverError::kOk;
}

base::Result<estimation::ImuReading, DriverError> Mpu9250::Read(int64_t timestamp_ns) {
  if (!started_) return DriverError::kNotStarted;
  const uint8_t first = mpu9250::kAccelXoutHigh;
  std::array<uint8_t, mpu9250::kBurstBytes> burst{};
  if (Check(bus_.WriteRead(config_.address, {&first, 1}, burst)) != DriverError::kOk) return DriverError::kBus;
  return DecodeMpu9250Burst(burst, config_, timestamp_ns);
}

}  // namespace syrof::firmware::drivers
