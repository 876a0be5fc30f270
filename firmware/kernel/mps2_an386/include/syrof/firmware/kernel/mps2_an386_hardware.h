// The kernel's hardware on qemu's mps2-an386 (Cortex-M4): the NVIC pends the
// levels, BASEPRI masks the kernel, CMSDK APB timer1 runs free as the clock
// and timer0 raises the alarm.
//
// Priorities (NVIC values use the top 4 bits, `value << 4`, so the 4-bit
// MK20DX256 and qemu's 8-bit NVIC behave alike; lower value = more urgent):
//
//   | what                          | IRQ              | NVIC priority       |
//   |-------------------------------|------------------|---------------------|
//   | faults, SysTick (cycle count) | -                | 0 (never masked)    |
//   | device interrupts above kernel| any              | 1-3 (no kernel call)|
//   | timer0: releases (OnTimer)    | 8                | 4 (= kernel mask)   |
//   | task level L (0..9)           | kLevelIrq[L]     | 14 - L              |
//
// Lock() and every kernel call set BASEPRI to 4 << 4: the timer and all levels
// wait. An interrupt that calls Notify must have priority 4..15.
#pragma once

#include <array>
#include <cstdint>

#include "syrof/firmware/kernel/hardware.h"
#include "syrof/firmware/kernel/nvic_port.h"

namespace syrof::firmware::kernel {

/// Spare external interrupts of mps2-an386 (no device drives them), one per
/// level.
inline constexpr std::array<uint8_t, kLevelCount> kLevelIrq = {6, 7, 14, 15, 16, 17, 23, 25, 26, 27};
inline constexpr uint8_t kTimerIrq = 8;  ///< CMSDK timer0
inline constexpr uint8_t kTimerPriority = 4;
/// BASEPRI while the kernel is masked.
inline constexpr uint32_t kKernelMask = uint32_t{kTimerPriority} << 4;
/// NVIC priority value (unshifted) of a level.
constexpr uint8_t LevelPriority(uint8_t level) { return static_cast<uint8_t>(14 - level); }

class Mps2An386Hardware final : public KernelHardware {
 public:
  /// The clock: timer1 counts the 25 MHz APB clock, 40 ns a tick.
  static constexpr int64_t kNanosecondsPerTick = 40;

  /// Takes over timer0, timer1 and the level IRQs, and moves the vector table
  /// to RAM (VTOR) with the kernel's handlers in it, keeping every other
  /// entry. The clock starts at 0 here. One instance per program.
  Mps2An386Hardware();

  /// Routes a device's interrupt `irq` (not a level's or the timer's) to
  /// `handler` at NVIC priority `priority` (1..15, unshifted) and enables it.
  /// A handler at 1-3 runs above the kernel and must not call it; at 4-15 it
  /// may call Notify (section comment above).
  void RouteInterrupt(uint8_t irq, uint8_t priority, void (*handler)());

  /// Sends the interrupts to `port` (a later Attach replaces it).
  void Attach(NvicPort& port);

  void PendLevel(uint8_t level) override;
  uint32_t MaskKernel() override;
  void RestoreMask(uint32_t previous) override;
  int64_t now_ns() override;
  void SetAlarm(int64_t at_ns) override;

 private:
  uint64_t ticks_high_ = 0;  ///< wraps of timer1 counted so far, times 2^32
  uint32_t last_low_ = 0;
};

}  // namespace syrof::firmware::kernel
