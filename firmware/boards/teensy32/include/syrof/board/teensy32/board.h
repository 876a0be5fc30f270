// The Teensy 3.2 board (MK20DX256VLH7): what runs before main and the
// register-level peripherals behind firmware/drivers' bus interface.
//
// Before main (startup.cpp): the watchdog is unlocked and disabled in the
// reset handler's first instructions, .data copied and .bss zeroed, the
// clock switched from the internal FLL to the crystal's PLL at 72 MHz
// (clock_config.h), SysTick started at 1 kHz, and constructors run.
//
//   syrof::board::teensy32::Uart& console = ConsoleUart();  // UART2, 115200 8N1, printf goes here
//   Uart& radio = RadioUart();                               // UART0, 1 Mbaud 8N1, the nRF51822
//   radio.Start(1'000'000, on_byte);                         // on_byte runs in the receive interrupt
//   I2c0& i2c = I2cBus0();     i2c.Start(400'000);           // MPU-9250
//   Spi0Device flow(kFlowChipSelect, 2'000'000, SpiMode::k3);  // PMW3901
//
// Every transfer is bounded: a peripheral that does not answer within
// kBusSpinLimit polls gives BusStatus::kTimeout. Pin map: pins.h.
#pragma once

#include <cstddef>
#include <cstdint>
#include <span>

#include "syrof/board/teensy32/pins.h"
#include "syrof/firmware/drivers/bus.h"

namespace syrof::board::teensy32 {

/// How many status polls a bus transfer waits for one byte before it gives
/// up with kTimeout (about 1 ms at 72 MHz; an I2C byte at 375 kHz takes 24 us).
inline constexpr uint32_t kBusSpinLimit = 20'000;

/// Nanoseconds since SysTick started (before main), from the tick count and
/// SysTick's current value; monotonic, resolution one core cycle (13.9 ns).
int64_t now_ns();

/// firmware/drivers' Delay over now_ns().
class BusyDelay final : public firmware::drivers::Delay {
 public:
  void WaitUs(uint32_t microseconds) override;
};

/// A UART: transmit through a ring buffer emptied by the transmit interrupt,
/// receive byte by byte into a callback run in the receive interrupt.
class Uart final : public firmware::drivers::UartTx {
 public:
  /// Called in the receive interrupt for each byte; keep it short.
  using ReceiveFn = void (*)(uint8_t byte, void* context);

  Uart(uintptr_t base, uint32_t clock_hz, int irq, PinIndex rx, PinIndex tx, uint32_t clock_gate);
  /// Gates the clock, muxes the pins, sets 8N1 at `baud` and enables the
  /// interrupt. Returns false when `baud` cannot be reached within 2%.
  bool Start(uint32_t baud, ReceiveFn on_byte = nullptr, void* context = nullptr);
  size_t Free() const override;
  size_t Write(std::span<const uint8_t> bytes) override;
  /// Waits (bounded by the buffer's bytes at the baud rate) until all is sent.
  void Flush();
  bool started() const { return baud_ != 0; }
  uint32_t overruns() const { return overruns_; }
  /// The interrupt's body; the vector table calls it.
  void OnInterrupt();

 private:
  static constexpr size_t kTxCapacity = 256;  // a power of two
  uintptr_t base_;
  uint32_t clock_hz_;
  int irq_;
  PinIndex rx_, tx_;
  uint32_t clock_gate_;
  ReceiveFn on_byte_ = nullptr;
  void* context_ = nullptr;
  uint8_t tx_buffer_[kTxCapacity];
  volatile uint32_t tx_head_ = 0;  // written by Write
  volatile uint32_t tx_tail_ = 0;  // written by the interrupt
  uint32_t overruns_ = 0;
  uint32_t baud_ = 0;
};

/// UART0 on pins 0 and 1 (system clock): the nRF51822 radio link.
Uart& RadioUart();
/// UART2 on pins 7 and 8 (bus clock): the debug console; newlib's stdout.
Uart& ConsoleUart();

/// I2C0 as a polled master on pins 18 and 19.
class I2c0 final : public firmware::drivers::I2cBus {
 public:
  /// Gates the clock, muxes the pins (open drain, pull-ups), sets the
  /// fastest SCL not above `scl_hz`. Returns the SCL frequency reached.
  uint32_t Start(uint32_t scl_hz);
  firmware::drivers::BusStatus Write(uint8_t address, std::span<const uint8_t> data) override;
  firmware::drivers::BusStatus WriteRead(uint8_t address, std::span<const uint8_t> command,
                                         std::span<uint8_t> response) override;

 private:
  firmware::drivers::BusStatus SendByte(uint8_t byte);
  firmware::drivers::BusStatus WaitByteDone();
  void Stop();
};
I2c0& I2cBus0();

enum class SpiMode : uint8_t { k0, k1, k2, k3 };  ///< CPOL << 1 | CPHA

/// One device on SPI0 (pins 11, 12, 13) with its own GPIO chip select and
/// its own clock and mode, set at each Select(): the PMW3901 (mode 3) and
/// the DWM1000 (mode 0) share the bus.
class Spi0Device final : public firmware::drivers::SpiBus {
 public:
  Spi0Device(PinIndex chip_select, uint32_t max_sck_hz, SpiMode mode);
  /// Gates SPI0, muxes its pins (once for all devices) and this chip select
  /// (high, idle).
  void Start();
  /// A new clock limit (the DWM1000 speeds up once its PLL has locked).
  void SetMaxClock(uint32_t max_sck_hz);
  void Select() override;
  void Deselect() override;
  firmware::drivers::BusStatus Transfer(std::span<const uint8_t> out, std::span<uint8_t> in) override;
  uint32_t sck_hz() const { return sck_hz_; }

 private:
  PinIndex chip_select_;
  SpiMode mode_;
  uint32_t ctar_ = 0;
  uint32_t sck_hz_ = 0;
};

/// Drives a GPIO output pin (muxes it as GPIO output on first use).
void GpioConfigureOutput(PinIndex pin, bool high);
void GpioWrite(PinIndex pin, bool high);

}  // namespace syrof::board::teensy32
