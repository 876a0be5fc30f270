// The PMW3901 optical-flow sensor over SPI: registers, the motion burst, and
// its decoding into estimation::FlowReading (the topic the lab's simulated
// flow sensor publishes; core/estimation/messages.h).
//
//   Pmw3901 flow(spi, delay, Pmw3901Config{});
//   if (flow.Start(now_ns) != DriverError::kOk) ...       // once, at start-up
//   auto reading = flow.Read(now_ns);                      // at 50 Hz
//   if (reading.ok()) publish(reading.value());            // kLowQuality: nothing to publish
//
// Facts from PixArt's PMW3901MB-TXQT datasheet (rev 1.00): SPI mode 3 up to
// 2 MHz; bit 7 of the address byte is 1 for a write; 35 us between the
// address and the data of a read or a motion burst. The datasheet also lists
// a long "performance optimisation" register sequence to write after reset;
// it is the sensor's calibration, not this driver's logic, so the board
// passes it in (Pmw3901Config::tuning) and it is checked only on hardware.
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
namespace pmw3901 {

inline constexpr uint8_t kProductId = 0x00;         ///< reads kProductIdValue
inline constexpr uint8_t kMotion = 0x02;            ///< bit 7: motion since the last read
inline constexpr uint8_t kDeltaXLow = 0x03;         ///< Delta_X_L .. Delta_Y_H are 0x03 .. 0x06
inline constexpr uint8_t kDeltaYHigh = 0x06;
inline constexpr uint8_t kMotionBurst = 0x16;       ///< reading it streams kBurstBytes bytes
inline constexpr uint8_t kPowerUpReset = 0x3A;      ///< write kPowerUpResetValue to reset
inline constexpr uint8_t kInverseProductId = 0x5F;  ///< reads kInverseProductIdValue

inline constexpr uint8_t kProductIdValue = 0x49;
inline constexpr uint8_t kInverseProductIdValue = 0xB6;
inline constexpr uint8_t kPowerUpResetValue = 0x5A;
inline constexpr uint8_t kWriteBit = 0x80;
inline constexpr uint8_t kMotionOccurred = 0x80;

/// Address-to-data wait of a read and of a motion burst, and the wait after a reset.
inline constexpr uint32_t kReadWaitUs = 35;
inline constexpr uint32_t kResetWaitUs = 5'000;

/// The motion burst: Motion, Observation, Delta_X_L, Delta_X_H, Delta_Y_L,
/// Delta_Y_H, SQUAL, RawData_Sum, Maximum_RawData, Minimum_RawData,
/// Shutter_Upper, Shutter_Lower.
inline constexpr size_t kBurstBytes = 12;

/// The burst's fields. Deltas are the sensor's counts since the last burst
/// (little-endian int16 in the burst), in its own axes.
struct MotionBurst {
  uint8_t motion;
  uint8_t observation;
  int16_t delta_x;
  int16_t delta_y;
  uint8_t squal;          ///< surface quality: about the number of features seen
  uint8_t raw_data_sum;
  uint8_t max_raw_data;
  uint8_t min_raw_data;
  uint16_t shutter;       ///< Shutter_Upper << 8 | Shutter_Lower: exposure, longer in the dark
};

MotionBurst ParseMotionBurst(std::span<const uint8_t, kBurstBytes> burst);

}  // namespace pmw3901

/// The driver's configuration.
struct Pmw3901Config {
  /// Body x (forward) and y (left) from the sensor's x and y. The default
  /// (identity) assumes the sensor mounted so that pushing the robot forward
  /// gives positive Delta_X; check it on the robot (docs/firmware.md).
  std::array<AxisSource, 2> body_from_sensor{{{0, 1}, {1, 1}}};
  /// The datasheet's rule: a burst with SQUAL below min_squal AND
  /// Shutter_Upper at or above dark_shutter_upper is not to be trusted.
  uint8_t min_squal = 0x19;
  uint8_t dark_shutter_upper = 0x1F;
  /// Written after the reset (the datasheet's performance-optimisation
  /// sequence); must outlive the driver.
  std::span<const RegisterWrite> tuning{};
};

/// Whether a burst passes the quality gate.
bool Pmw3901BurstUsable(const pmw3901::MotionBurst& burst, const Pmw3901Config& config);

/// A burst mapped to the body frame, covering `interval_ns` (> 0) up to
/// `timestamp_ns`. kLowQuality when the gate rejects it. A body delta that
/// would be -(-32768) saturates at 32767.
base::Result<estimation::FlowReading, DriverError> DecodePmw3901Burst(
    std::span<const uint8_t, pmw3901::kBurstBytes> burst, const Pmw3901Config& config, int64_t timestamp_ns,
    uint32_t interval_ns);

/// The PMW3901 on its SPI chip select.
class Pmw3901 {
 public:
  /// `bus`, `delay` and config.tuning must outlive the driver.
  Pmw3901(SpiBus& bus, Delay& delay, const Pmw3901Config& config) : bus_(bus), delay_(delay), config_(config) {}

  /// Resets the sensor, checks both identity registers, clears the motion
  /// registers and writes the tuning; the first interval starts at `now_ns`.
  /// Errors: kBadConfig, kWrongDevice, kBus.
  DriverError Start(int64_t now_ns);

  /// Reads a motion burst: the image motion since the previous Read() (or
  /// Start()). The sensor clears its counts on every burst, so a rejected
  /// burst's motion is lost and the next interval starts at `now_ns` anyway.
  /// Errors: kNotStarted, kBus, kLowQuality, kBadTimestamp (`now_ns` not
  /// after the previous read, or more than 4.29 s after it).
  base::Result<estimation::FlowReading, DriverError> Read(int64_t now_ns);

  BusStatus last_bus_status() const { return last_bus_status_; }

 private:
  DriverError WriteRegister(uint8_t reg, uint8_t value);
  DriverError ReadRegister(uint8_t reg, uint8_t& value);
  DriverError Check(BusStatus status);

  SpiBus& bus_;
  Delay& delay_;
  Pmw3901Config config_;
  bool started_ = false;
  int64_t last_read_ns_ = 0;
  BusStatus last_bus_status_ = BusStatus::kOk;
};

}  // namespace syrof::firmware::drivers
