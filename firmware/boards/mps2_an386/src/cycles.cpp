#include "syrof/board/cycles.h"

namespace syrof::board {
namespace {

// SysTick registers (Armv7-M Architecture Reference Manual, B3.3).
struct SysTickRegisters {
  volatile std::uint32_t control;            // SYST_CSR
  volatile std::uint32_t reload;             // SYST_RVR
  volatile std::uint32_t current;            // SYST_CVR
  volatile const std::uint32_t calibration;  // SYST_CALIB
};
SysTickRegisters& systick() { return *reinterpret_cast<SysTickRegisters*>(0xE000E010u); }

// Interrupt Control and State Register; PENDSTSET reads 1 while the SysTick
// interrupt is pending (Armv7-M ARM, B3.2.4).
volatile const std::uint32_t& interrupt_control_state() {
  return *reinterpret_cast<volatile const std::uint32_t*>(0xE000ED04u);
}
constexpr std::uint32_t kSysTickPending = 1u << 26;

constexpr std::uint32_t kEnable = 1u << 0;
constexpr std::uint32_t kTickInterrupt = 1u << 1;
constexpr std::uint32_t kProcessorClock = 1u << 2;
constexpr std::uint32_t kReload = 0x00FFFFFFu;  // the full 24 bits
constexpr std::uint64_t kTicksPerPeriod = std::uint64_t{kReload} + 1;

// How many times the counter has reached zero since the start; incremented by
// the SysTick interrupt, which the core raises on the step from 1 to 0.
volatile std::uint32_t zero_count = 0;

}  // namespace

void cycle_counter_start() {
  systick().control = 0;
  systick().reload = kReload;
  systick().current = 0;  // any write clears the counter and COUNTFLAG
  zero_count = 0;
  systick().control = kEnable | kTickInterrupt | kProcessorClock;
  // The counter holds 0 until the first tick loads kReload; start counting
  // from there so that 0 always means the end of a period.
  while (systick().current == 0) {
  }
}

std::uint64_t cycle_counter_read() {
  if ((systick().control & kEnable) == 0) return 0;
  std::uint32_t zeros;
  std::uint32_t current;
  bool zero_pending;
  do {
    zeros = zero_count;
    current = systick().current;
    zero_pending = (interrupt_control_state() & kSysTickPending) != 0;
  } while (zero_count != zeros);  // the interrupt ran in between: read again

  // Each period runs kReload, ..., 1, 0; the interrupt counts the step to 0.
  // A counter at 0 is the last tick of its period, not the first of the next:
  // once the interrupt has counted it, that period is not complete yet.
  std::uint32_t periods_completed = zeros;
  if (current == 0 && !zero_pending) periods_completed = zeros - 1;
  const std::uint64_t ticks = periods_completed * kTicksPerPeriod + (kReload - current);
  return ticks * kCycleCounterResolution;
}

}  // namespace syrof::board

extern "C" void systick_handler() { syrof::board::zero_count = syrof::board::zero_count + 1; }
