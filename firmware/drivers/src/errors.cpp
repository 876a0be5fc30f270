#include "syrof/firmware/drivers/bus.h"
#include "syrof/firmware/drivers/driver_error.h"

namespace syrof::firmware::drivers {

const char* ToString(BusStatus status) {
  switch (status) {
    case BusStatus::kOk: return "Ok";
    case BusStatus::kNack: return "Nack";
    case BusStatus::kTimeout: return "Timeout";
    case BusStatus::kError: return "Error";
  }
  return "?";
}

const char* ToString(DriverError error) {
  switch (error) {
    case DriverError::kOk: return "Ok";
    case DriverError::kBus: return "Bus";
    case DriverError::kWrongDevice: return "WrongDevice";
    case DriverError::kBadConfig: return "BadConfig";
    case DriverError::kNotStarted: return "NotStarted";
    case DriverError::kLowQuality: return "LowQuality";
    case DriverError::kBadTimestamp: return "BadTimestamp";
    case DriverError::kIntervalOutOfRange: return "IntervalOutOfRange";
    case DriverError::kRangeOutOfBounds: return "RangeOutOfBounds";
  }
  return "?";
}

}  // namespace syrof::firmware::drivers
