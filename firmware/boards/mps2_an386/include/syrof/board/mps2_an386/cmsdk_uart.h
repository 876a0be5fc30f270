// The mps2-an386's UARTs (Arm CMSDK APB UART) behind firmware/drivers' bus
// interface, so firmware images under qemu talk to other processes through
// `-chardev socket,id=radio,path=SOCK -serial ...` (toolchain-facts).
//
//   CmsdkUart radio(kCmsdkUart1);          // qemu's second -serial
//   radio.Start();
//   radio.Write(bytes);                    // queued; Poll() or the TX interrupt sends
//   radio.Poll();                          // moves bytes between the ring and the UART
//   size_t n = radio.Read(buffer);         // what has arrived
//
// The UART holds one byte each way, so both directions go through rings
// here. Without interrupts (the test images' vector table is in flash and
// sends every external interrupt to a fatal handler) Poll() does the
// moving; an image that routes the UART's RX and TX interrupts (the
// kernel's RAM vector table) calls OnInterrupt() from them instead. Under
// qemu the baud divider only needs to be valid (>= 16); bytes move at
// emulation speed.
#pragma once

#include <cstddef>
#include <cstdint>
#include <span>

#include "syrof/firmware/drivers/bus.h"

namespace syrof::board::mps2_an386 {

/// Base addresses of the CMSDK UARTs on mps2-an386 (qemu 7.2's map).
inline constexpr uintptr_t kCmsdkUart0 = 0x40004000;
inline constexpr uintptr_t kCmsdkUart1 = 0x40005000;
inline constexpr uintptr_t kCmsdkUart2 = 0x40006000;

/// UARTn's receive interrupt is 2n, its transmit interrupt 2n + 1 (n = 0..2).
constexpr int CmsdkUartRxIrq(uintptr_t base) { return static_cast<int>((base - kCmsdkUart0) / 0x1000) * 2; }

class CmsdkUart final : public firmware::drivers::UartTx {
 public:
  explicit CmsdkUart(uintptr_t base) : base_(base) {}
  /// Enables transmitter and receiver (and their interrupts when
  /// `interrupts`); the divider is the smallest valid one.
  void Start(bool interrupts = false);
  size_t Free() const override;
  /// Queues what fits in the transmit ring; never blocks.
  size_t Write(std::span<const uint8_t> bytes) override;
  /// Takes up to `out.size()` received bytes, oldest first.
  size_t Read(std::span<uint8_t> out);
  /// Moves one pending byte each way if the UART is ready; returns true if
  /// it moved any. Call it in a loop (or from the interrupts).
  bool Poll();
  void OnInterrupt() { while (Poll()) {} }
  /// 0x00 bytes received so far (wrapping): the radio and sensor links end
  /// every frame with one, so a handler can wake its task once a frame
  /// rather than once a byte.
  uint32_t zeros_received() const { return zeros_received_; }
  /// Bytes lost because the receive ring was full or the UART overran.
  uint32_t dropped() const { return dropped_; }
  bool transmit_idle() const { return tx_head_ == tx_tail_; }

 private:
  static constexpr uint32_t kRing = 256;  // a power of two
  uintptr_t base_;
  uint8_t tx_[kRing];
  uint8_t rx_[kRing];
  volatile uint32_t tx_head_ = 0, tx_tail_ = 0, rx_head_ = 0, rx_tail_ = 0;
  uint32_t dropped_ = 0;
  volatile uint32_t zeros_received_ = 0;
};

/// A CMSDK APB timer (timer0 at 0x40000000, timer1 at 0x40001000): a 32-bit
/// down-counter at the 25 MHz system clock, reloading. `count_cycles()`
/// counts up without a gap across reloads when read at least once per
/// reload period (172 s at the full 32-bit reload). The firmware kernel
/// owns timer0 and timer1 in its images; use this one elsewhere.
class CmsdkTimer {
 public:
  static constexpr uintptr_t kTimer0 = 0x40000000;
  static constexpr uintptr_t kTimer1 = 0x40001000;
  static constexpr uint32_t kClockHz = 25'000'000;

  explicit CmsdkTimer(uintptr_t base) : base_(base) {}
  /// Starts counting down from `reload` (interrupt on reaching 0 if asked).
  void Start(uint32_t reload = 0xFFFFFFFFu, bool interrupt = false);
  void Stop();
  uint32_t value() const;
  /// Cycles since Start, widened to 64 bits across reloads.
  uint64_t count_cycles();
  /// Clears the interrupt; returns whether it was pending.
  bool ClearInterrupt();

 private:
  uintptr_t base_;
  uint32_t reload_ = 0;
  uint32_t last_value_ = 0;
  uint64_t elapsed_ = 0;
};

}  // namespace syrof::board::mps2_an386
