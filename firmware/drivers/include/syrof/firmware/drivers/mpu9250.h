// The MPU-9250 IMU over I2C: register map, start-up sequence, and the decoding
// of one 14-byte sample burst into estimation::ImuReading (the topic the lab's
// simulated IMU publishes; core/estimation/messages.h).
//
//   Mpu9250 imu(i2c, delay, Mpu9250Config{});
//   if (imu.Start() != DriverError::kOk) ...            // once, at start-up
//   auto reading = imu.Read(now_ns);                     // at 100 Hz (the data-ready pin)
//
// Facts from InvenSense's MPU-9250 register map (RM-MPU-9250A-00 rev 1.6) and
// product specification (PS-MPU-9250A-01 rev 1.1). The magnetometer (the
// AK8963 behind the auxiliary bus) is not used: the estimator has no
// magnetometer model.
#pragma once

#include <array>
#include <cstddef>
#include <cstdint>
#include <span>

#include "syrof/base/result.h"
#include "syrof/estimation/messages.h"
#include "syrof/firmware/drivers/axis_map.h"
#include "syrof/firmware/drivers/bus.h"
#include "syrof/firmware/drivers/driver_error.h"

namespace syrof::firmware::drivers {
namespace mpu9250 {

/// 7-bit I2C address with AD0 low (0x69 with AD0 high).
inline constexpr uint8_t kAddress = 0x68;

/// Registers the driver uses.
inline constexpr uint8_t kSampleRateDivider = 0x19;  ///< SMPLRT_DIV: rate = 1 kHz / (1 + value) with the DLPF on
inline constexpr uint8_t kConfig = 0x1A;             ///< CONFIG: DLPF_CFG in bits 2:0
inline constexpr uint8_t kGyroConfig = 0x1B;         ///< GYRO_CONFIG: GYRO_FS_SEL in bits 4:3
inline constexpr uint8_t kAccelConfig = 0x1C;        ///< ACCEL_CONFIG: ACCEL_FS_SEL in bits 4:3
inline constexpr uint8_t kAccelConfig2 = 0x1D;       ///< ACCEL_CONFIG 2: A_DLPF_CFG in bits 2:0
inline constexpr uint8_t kIntPinConfig = 0x37;       ///< INT_PIN_CFG
inline constexpr uint8_t kIntEnable = 0x38;          ///< INT_ENABLE: RAW_RDY_EN is bit 0
inline constexpr uint8_t kIntStatus = 0x3A;          ///< INT_STATUS
inline constexpr uint8_t kAccelXoutHigh = 0x3B;      ///< first of the 14-byte burst
inline constexpr uint8_t kPowerManagement1 = 0x6B;   ///< PWR_MGMT_1: H_RESET bit 7, CLKSEL bits 2:0
inline constexpr uint8_t kPowerManagement2 = 0x6C;   ///< PWR_MGMT_2: axis disables
inline constexpr uint8_t kWhoAmI = 0x75;             ///< WHO_AM_I

/// WHO_AM_I of an MPU-9250.
inline constexpr uint8_t kWhoAmIValue = 0x71;

/// The burst from ACCEL_XOUT_H: accel x, y, z, temperature, gyro x, y, z,
/// each a big-endian two's-complement int16.
inline constexpr size_t kBurstBytes = 14;

/// Accelerometer full scale (ACCEL_FS_SEL).
enum class AccelRange : uint8_t { k2G = 0, k4G = 1, k8G = 2, k16G = 3 };
/// Gyroscope full scale (GYRO_FS_SEL).
enum class GyroRange : uint8_t { k250Dps = 0, k500Dps = 1, k1000Dps = 2, k2000Dps = 3 };

/// Sensitivity: 16384 LSB/g at ±2 g, halving with each range step.
float AccelLsbPerG(AccelRange range);
/// Sensitivity, the datasheet's figures: 131, 65.5, 32.8 and 16.4 LSB/(deg/s)
/// at ±250, ±500, ±1000 and ±2000 deg/s.
float GyroLsbPerDps(GyroRange range);

/// The chip's counts, in register order.
struct RawSample {
  int16_t accel[3];
  int16_t temperature;
  int16_t gyro[3];
};

/// Reads the 14 bytes of a burst.
RawSample ParseBurst(std::span<const uint8_t, kBurstBytes> burst);

/// Die temperature from TEMP_OUT: raw / 333.87 + 21 degC (room-temperature offset 0).
float TemperatureC(int16_t raw);

}  // namespace mpu9250

/// The driver's configuration.
struct Mpu9250Config {
  uint8_t address = mpu9250::kAddress;
  mpu9250::AccelRange accel_range = mpu9250::AccelRange::k4G;
  mpu9250::GyroRange gyro_range = mpu9250::GyroRange::k500Dps;
  /// 1 kHz / (1 + divider): 9 gives the 100 Hz of registry::kImuPeriodNs.
  uint8_t sample_rate_divider = 9;
  /// How the chip sits on the robot: body axis i (x forward, y left, z up)
  /// is chip axis body_from_chip[i].axis times its sign. The default is the
  /// chip flat, component side up, its x arrow pointing forward.
  std::array<AxisSource, 3> body_from_chip{{{0, 1}, {1, 1}, {2, 1}}};
};

/// Steps of the start-up sequence, in order.
inline constexpr size_t kMpu9250StartSteps = 10;

/// The start-up sequence for `config`, as data: reset (and wait 100 ms),
/// clock from the gyro's PLL, all axes on, both low-pass filters at about
/// 41 Hz (the bandwidth the lab's ImuModel assumes), the sample-rate
/// divider, both full-scale ranges, and the data-ready interrupt (cleared by
/// any read).
std::array<RegisterWrite, kMpu9250StartSteps> Mpu9250StartSequence(const Mpu9250Config& config);

/// A burst in the configured ranges, mapped to the body frame: the
/// ImuReading the lab's simulated IMU publishes.
estimation::ImuReading DecodeMpu9250Burst(std::span<const uint8_t, mpu9250::kBurstBytes> burst,
                                          const Mpu9250Config& config, int64_t timestamp_ns);

/// The MPU-9250 on an I2C bus.
class Mpu9250 {
 public:
  /// `bus` and `delay` must outlive the driver.
  Mpu9250(I2cBus& bus, Delay& delay, const Mpu9250Config& config) : bus_(bus), delay_(delay), config_(config) {}

  /// Checks the configuration and WHO_AM_I, then runs the start-up sequence.
  /// Takes about 110 ms (the reset's wait). Errors: kBadConfig, kWrongDevice, kBus.
  DriverError Start();

  /// Reads one sample burst and decodes it, stamped `timestamp_ns` (the
  /// port clock when the data-ready interrupt fired). Errors: kNotStarted, kBus.
  base::Result<estimation::ImuReading, DriverError> Read(int64_t timestamp_ns);

  BusStatus last_bus_status() const { return last_bus_status_; }

 private:
  DriverError Check(BusStatus status);

  I2cBus& bus_;
  Delay& delay_;
  Mpu9250Config config_;
  bool started_ = false;
  BusStatus last_bus_status_ = BusStatus::kOk;
};

}  // namespace syrof::firmware::drivers
