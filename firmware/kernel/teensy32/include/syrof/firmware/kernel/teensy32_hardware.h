// The kernel's hardware on the Teensy 3.2 (MK20DX256VLH7, Cortex-M4 without
// FPU), written from the K20 reference manual (K20P64M72SF1RM: the NVIC
// interrupt map, chapter 38 "Periodic Interrupt Timer") and the Armv7-M
// architecture manual. Not run here: qemu has no K20 machine. The image test
// checks its vectors; the host tests check its time arithmetic
// (tests/firmware/kernel/teensy32_timing_test.cpp).
//
//   | what                              | IRQ                 | NVIC priority        |
//   |-----------------------------------|---------------------|----------------------|
//   | faults                            | -                   | 0                    |
//   | SysTick (the board's BusyDelay)   | -                   | 1 (never masked)     |
//   | UART0/UART2 status (the board)    | 45, 49              | 2 (no kernel call)   |
//   | PIT channel 0: releases (OnTimer) | 68                  | 4 (= kernel mask)    |
//   | task level L (0..9)               | DMA channel L's: L  | 14 - L               |
//
// The image uses no DMA, so the ten DMA channel interrupts (0-9) are the
// levels' software interrupts: nothing but the kernel pends them. PIT
// channel 1 runs free at the 36 MHz bus clock as the clock (27.8 ns a
// tick, wrapping every 119 s; widened to 64 bits on every read, and the
// alarm is never set more than 1.86 s ahead, so it is read often enough).
// PIT channel 0 is the alarm: loaded, started, and stopped in its interrupt.
//
// The board's vector table (firmware/boards/teensy32/src/startup.cpp)
// names these entries after their sources, dma_channel0_handler ..
// dma_channel9_handler and pit0_handler, as weak symbols that default to
// the unexpected-interrupt handler; linking this hardware defines them.
#pragma once

#include <array>
#include <cstdint>

#include "syrof/firmware/kernel/hardware.h"

namespace syrof::firmware::kernel {

class NvicPort;

namespace teensy32 {

/// The interrupts the kernel takes on the MK20DX256.
inline constexpr std::array<uint8_t, kLevelCount> kLevelIrq = {0, 1, 2, 3, 4, 5, 6, 7, 8, 9};  // DMA channels
inline constexpr uint8_t kTimerIrq = 68;  ///< PIT channel 0
inline constexpr uint8_t kTimerPriority = 4;
inline constexpr uint32_t kKernelMask = uint32_t{kTimerPriority} << 4;
constexpr uint8_t LevelPriority(uint8_t level) { return static_cast<uint8_t>(14 - level); }

/// The PIT counts the bus clock.
inline constexpr int64_t kPitClockHz = 36'000'000;
/// The longest alarm, in PIT ticks (1.86 s): the clock is read at least this
/// often, far inside its 119 s wrap, and the tick count fits 32 bits.
inline constexpr uint32_t kLongestAlarmTicks = 1u << 26;

/// Nanoseconds of `ticks` PIT ticks, rounded down (exact to the nanosecond:
/// 9 ticks are 250 ns).
constexpr int64_t NsFromTicks(uint64_t ticks) {
  return static_cast<int64_t>((ticks / 9) * 250 + (ticks % 9) * 250 / 9);
}

/// PIT ticks an alarm `ahead_ns` (> 0) from now must count so that it never
/// fires early: rounded up, at least 1, at most kLongestAlarmTicks.
constexpr uint32_t AlarmTicks(int64_t ahead_ns) {
  constexpr int64_t kLongestNs = (int64_t{kLongestAlarmTicks} * 250 + 8) / 9;
  if (ahead_ns >= kLongestNs) return kLongestAlarmTicks;
  const int64_t ticks = (ahead_ns * 9 + 249) / 250;
  return ticks < 1 ? 1u : static_cast<uint32_t>(ticks);
}

}  // namespace teensy32

class Teensy32Hardware final : public KernelHardware {
 public:
  /// Gates and starts the PIT (channel 1 free-running, channel 0 idle), sets
  /// the levels' and the timer's priorities and enables them. The clock
  /// starts at 0 here. One instance per program; the board has set the clock
  /// to 72 MHz before main.
  Teensy32Hardware();

  /// Sends the interrupts to `port` (a later Attach replaces it).
  void Attach(NvicPort& port);

  void PendLevel(uint8_t level) override;
  uint32_t MaskKernel() override;
  void RestoreMask(uint32_t previous) override;
  int64_t now_ns() override;
  void SetAlarm(int64_t at_ns) override;

 private:
  uint64_t ticks_high_ = 0;  ///< wraps of PIT channel 1 counted so far, times 2^32
  uint32_t last_low_ = 0;
};

}  // namespace syrof::firmware::kernel
