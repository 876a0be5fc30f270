// The thin bus interface the drivers talk through: I2C, SPI, a UART's
// transmit side and a short wait. A board implements these over its
// peripherals (the Teensy 3.2's I2C0, SPI0 and UART1; docs/firmware.md,
// "Drivers"); host tests implement them with fakes that play a sensor's
// registers, so the drivers' sequences and decoding are tested without
// hardware.
//
// Contract shared by every method:
//   - Bounded: a call returns after at most the transfer's bytes plus the
//     board's timeout; it never waits for an event without one.
//   - No allocation; spans are borrowed for the call only.
//   - Errors are values (BusStatus); a driver passes them up unchanged.
#pragma once

#include <cstddef>
#include <cstdint>
#include <span>

namespace syrof::firmware::drivers {

/// How a bus transfer ended.
enum class [[nodiscard]] BusStatus : uint8_t {
  kOk = 0,
  kNack,     ///< I2C: the device did not acknowledge its address or a byte
  kTimeout,  ///< the peripheral did not finish within the board's timeout
  kError,    ///< any other bus fault (arbitration lost, overrun)
};

/// The enumerator's name without the k ("Nack"); "?" for an unknown value.
const char* ToString(BusStatus status);

/// An I2C master. Addresses are 7-bit.
class I2cBus {
 public:
  /// Writes `data` to the device at `address` in one transaction (START,
  /// address+W, data, STOP). For a register write `data` is the register
  /// number followed by its value(s).
  virtual BusStatus Write(uint8_t address, std::span<const uint8_t> data) = 0;

  /// Writes `command` then, after a repeated START, reads `response.size()`
  /// bytes (START, address+W, command, RESTART, address+R, response, STOP):
  /// a register read when `command` is the register number.
  virtual BusStatus WriteRead(uint8_t address, std::span<const uint8_t> command,
                              std::span<uint8_t> response) = 0;

 protected:
  ~I2cBus() = default;
};

/// An SPI master with one device's chip select. Select() asserts it,
/// Deselect() releases it; Transfer() clocks `out` while reading as many
/// bytes into `in` (the two are the same length; `in` may be empty to
/// discard what comes back, `out` empty to clock zeros).
class SpiBus {
 public:
  virtual void Select() = 0;
  virtual void Deselect() = 0;
  virtual BusStatus Transfer(std::span<const uint8_t> out, std::span<uint8_t> in) = 0;

 protected:
  ~SpiBus() = default;
};

/// A UART's transmit side. Write() never blocks: it queues what fits in the
/// board's transmit buffer and returns how many bytes it took (a caller that
/// must send a whole frame checks Free() first).
class UartTx {
 public:
  virtual size_t Free() const = 0;
  virtual size_t Write(std::span<const uint8_t> bytes) = 0;

 protected:
  ~UartTx() = default;
};

/// A busy wait, for the few delays a start-up sequence or a sensor's
/// register timing needs (microseconds to milliseconds, never in a loop
/// without a bound).
class Delay {
 public:
  virtual void WaitUs(uint32_t microseconds) = 0;

 protected:
  ~Delay() = default;
};

/// One step of a start-up sequence kept as data: write `value` to register
/// `reg`, then wait `wait_us` microseconds before the next step.
struct RegisterWrite {
  uint8_t reg;
  uint8_t value;
  uint32_t wait_us;

  friend bool operator==(const RegisterWrite&, const RegisterWrite&) = default;
};

}  // namespace syrof::firmware::drivers
