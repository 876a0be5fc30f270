// Why a sensor driver produced no reading.
#pragma once

#include <cstdint>

namespace syrof::firmware::drivers {

/// Errors of the sensor drivers (MPU-9250, PMW3901, DWM1000 ranging). A
/// driver that fails a bus transfer keeps the bus's own status for the log
/// (last_bus_status()).
enum class [[nodiscard]] DriverError : uint8_t {
  kOk = 0,
  kBus,                ///< a bus transfer failed (see the driver's last_bus_status())
  kWrongDevice,        ///< the identity register does not hold the expected value
  kBadConfig,          ///< the configuration is invalid (an axis map that is no signed permutation)
  kNotStarted,         ///< Read() before a successful Start()
  kLowQuality,         ///< flow: the sensor saw too little texture or light; the deltas are not used
  kBadTimestamp,       ///< a reading's time is not after the previous one, or too far after it
  kIntervalOutOfRange, ///< UWB: a DS-TWR interval is not in 1 .. kMaxIntervalTicks
  kRangeOutOfBounds,   ///< UWB: the computed range is outside the sweep's limits
};

/// The enumerator's name without the k ("LowQuality"); "?" for an unknown value.
const char* ToString(DriverError error);

}  // namespace syrof::firmware::drivers
