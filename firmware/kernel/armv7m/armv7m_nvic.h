// The Armv7-M parts every board's kernel hardware shares (Armv7-M
// Architecture Reference Manual, B3.4 NVIC and B1.4.3 BASEPRI): pending,
// enabling and prioritising external interrupts, and the kernel mask.
// Internal to firmware/kernel; only cross builds include it.
#pragma once

#include <cstdint>

namespace syrof::firmware::kernel::armv7m {

inline volatile uint32_t* const kNvicSetEnable = reinterpret_cast<volatile uint32_t*>(0xE000E100u);    // ISER
inline volatile uint32_t* const kNvicClearEnable = reinterpret_cast<volatile uint32_t*>(0xE000E180u);  // ICER
inline volatile uint32_t* const kNvicSetPending = reinterpret_cast<volatile uint32_t*>(0xE000E200u);   // ISPR
inline volatile uint32_t* const kNvicClearPending = reinterpret_cast<volatile uint32_t*>(0xE000E280u); // ICPR
inline volatile uint8_t* const kNvicPriority = reinterpret_cast<volatile uint8_t*>(0xE000E400u);  // IPR, a byte each

/// Pends `irq` in software. The dsb makes the write reach the NVIC before
/// the next instruction (qemu does not need it, an M4 does).
inline void Pend(unsigned irq) {
  kNvicSetPending[irq >> 5] = 1u << (irq & 31);
  asm volatile("dsb" ::: "memory");
}

inline void ClearPending(unsigned irq) { kNvicClearPending[irq >> 5] = 1u << (irq & 31); }

/// Sets the priority (0..15, in the top 4 bits, which both the MK20DX256's
/// 4-bit and qemu's 8-bit NVIC implement), clears a stale pending bit and
/// enables the interrupt.
inline void Enable(unsigned irq, uint8_t priority) {
  kNvicPriority[irq] = static_cast<uint8_t>(priority << 4);
  ClearPending(irq);
  kNvicSetEnable[irq >> 5] = 1u << (irq & 31);
}

inline void Disable(unsigned irq) {
  kNvicClearEnable[irq >> 5] = 1u << (irq & 31);
  asm volatile("dsb\n isb" ::: "memory");
}

/// Raises BASEPRI to `mask` unless it is already at or above it (basepri_max
/// only raises, so nested sections keep the outer one); returns the previous
/// BASEPRI.
inline uint32_t RaiseBasepri(uint32_t mask) {
  uint32_t previous;
  asm volatile(
      "mrs %0, basepri\n"
      "msr basepri_max, %1"
      : "=&r"(previous)
      : "r"(mask)
      : "memory");
  return previous;
}

inline void RestoreBasepri(uint32_t previous) { asm volatile("msr basepri, %0" ::"r"(previous) : "memory"); }

/// Application Interrupt and Reset Control; bits 10:8 are PRIGROUP. Above 3
/// the NVIC would merge priorities that differ only in the low bits of the
/// top nibble, and with them the kernel's levels.
inline uint32_t PriorityGrouping() { return (*reinterpret_cast<volatile uint32_t*>(0xE000ED0Cu) >> 8) & 7u; }

}  // namespace syrof::firmware::kernel::armv7m
