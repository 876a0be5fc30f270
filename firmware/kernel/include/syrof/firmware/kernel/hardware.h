// What the run-to-completion kernel needs from the chip, and nothing more:
// pend a level's software interrupt, mask the kernel's interrupts, read a
// monotonic clock, and ask for one timer interrupt at an absolute time.
//
// The NVIC port (nvic_port.h) holds all of the dispatch logic and sees the
// chip only through this interface, so the same logic runs on the host over a
// fake (tests/firmware/kernel/fake_hardware.h) and on a Cortex-M4 over the
// NVIC, BASEPRI and a hardware timer (mps2_an386_hardware.h).
#pragma once

#include <cstdint>

namespace syrof::firmware::kernel {

/// Number of task priority levels: os::TaskConfig::priority 0..kLevelCount-1,
/// higher preempts lower. Covers every priority in core/registry/tasks.h.
inline constexpr uint8_t kLevelCount = 10;

/// The interrupts that call back into NvicPort.
///   - level interrupts: RunLevel(level) runs that level's ready tasks;
///   - the timer interrupt: OnTimer() releases periodic tasks.
/// The timer interrupt preempts every level; a level preempts every lower one.
class KernelHardware {
 public:
  /// Makes `level`'s interrupt pending. It runs as soon as nothing of equal
  /// or higher priority is active and the kernel mask is not held; from a
  /// lower level that is at once (preemption). Pending twice before it runs
  /// runs it once.
  virtual void PendLevel(uint8_t level) = 0;

  /// Masks the timer and every level interrupt (BASEPRI) and returns the
  /// mask in force before, for RestoreMask. Nests: an inner
  /// MaskKernel/RestoreMask pair leaves the outer one in force.
  virtual uint32_t MaskKernel() = 0;
  virtual void RestoreMask(uint32_t previous) = 0;

  /// Nanoseconds since the hardware's epoch, monotonic. Called with the
  /// kernel masked (the hardware may extend a narrow counter here).
  virtual int64_t now_ns() = 0;

  /// Requests the timer interrupt once the clock reaches `at_ns` (at once if
  /// it already has), replacing any earlier request; a negative value cancels
  /// it. Called with the kernel masked. The interrupt may come late (qemu
  /// merges timer ticks when its host is slow), never early.
  virtual void SetAlarm(int64_t at_ns) = 0;

 protected:
  ~KernelHardware() = default;
};

}  // namespace syrof::firmware::kernel
