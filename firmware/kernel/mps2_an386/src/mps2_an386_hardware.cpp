#include "syrof/firmware/kernel/mps2_an386_hardware.h"

#include <cstring>
#include <utility>

#include "../../armv7m/armv7m_nvic.h"
#include "syrof/base/check.h"

namespace syrof::firmware::kernel {
namespace {

volatile uint32_t& vector_table_offset() { return *reinterpret_cast<volatile uint32_t*>(0xE000ED08u); }  // VTOR

// CMSDK APB timer (ARM CoreLink SDK TRM): a 32-bit down-counter that
// interrupts on reaching 0 and reloads.
struct CmsdkTimer {
  volatile uint32_t control;  // bit 0 enable, bit 3 interrupt enable
  volatile uint32_t value;
  volatile uint32_t reload;
  volatile uint32_t interrupt;  // read: status; write 1: clear
};
CmsdkTimer& alarm_timer() { return *reinterpret_cast<CmsdkTimer*>(0x40000000u); }  // timer0, IRQ 8
CmsdkTimer& clock_timer() { return *reinterpret_cast<CmsdkTimer*>(0x40001000u); }  // timer1
constexpr uint32_t kTimerEnable = 1u << 0;
constexpr uint32_t kTimerInterruptEnable = 1u << 3;
// The alarm is never set further ahead than this (2.7 s), so the timer
// interrupt reads the 32-bit clock (and counts its wrap) many times per wrap,
// and the distance in nanoseconds fits 32 bits (no 64-bit division).
constexpr uint32_t kLongestAlarmTicks = 1u << 26;

NvicPort* attached_port = nullptr;

template <uint8_t kLevel>
void LevelHandler() {
  attached_port->RunLevel(kLevel);
}

void TimerHandler() {
  alarm_timer().interrupt = 1;
  attached_port->OnTimer();
}

using Handler = void (*)();
template <size_t... kLevels>
constexpr std::array<Handler, sizeof...(kLevels)> MakeLevelHandlers(std::index_sequence<kLevels...>) {
  return {&LevelHandler<static_cast<uint8_t>(kLevels)>...};
}
constexpr std::array<Handler, kLevelCount> kLevelHandlers = MakeLevelHandlers(std::make_index_sequence<kLevelCount>{});

// 16 system exceptions and 32 external interrupts; VTOR needs the table
// aligned to its size rounded up to a power of two.
constexpr int kSystemExceptions = 16;
constexpr int kVectors = kSystemExceptions + 32;
alignas(256) uint32_t ram_vectors[kVectors];

}  // namespace

Mps2An386Hardware::Mps2An386Hardware() {
  SYROF_CHECK(armv7m::PriorityGrouping() <= 3u);
  const uint32_t saved = MaskKernel();
  const uintptr_t current_table = vector_table_offset();
  if (current_table != reinterpret_cast<uintptr_t>(ram_vectors)) {  // a second instance keeps the table
    std::memcpy(ram_vectors, reinterpret_cast<const void*>(current_table), sizeof(ram_vectors));
  }
  for (uint8_t level = 0; level < kLevelCount; ++level) {
    ram_vectors[kSystemExceptions + kLevelIrq[level]] = reinterpret_cast<uint32_t>(kLevelHandlers[level]);
  }
  ram_vectors[kSystemExceptions + kTimerIrq] = reinterpret_cast<uint32_t>(&TimerHandler);
  vector_table_offset() = reinterpret_cast<uint32_t>(ram_vectors);
  asm volatile("dsb\n isb" ::: "memory");

  clock_timer().control = 0;
  clock_timer().reload = 0xFFFFFFFFu;
  clock_timer().value = 0xFFFFFFFFu;
  clock_timer().control = kTimerEnable;
  alarm_timer().control = 0;
  alarm_timer().interrupt = 1;

  for (uint8_t level = 0; level < kLevelCount; ++level) armv7m::Enable(kLevelIrq[level], LevelPriority(level));
  armv7m::Enable(kTimerIrq, kTimerPriority);
  RestoreMask(saved);
}

void Mps2An386Hardware::RouteInterrupt(uint8_t irq, uint8_t priority, void (*handler)()) {
  SYROF_CHECK(irq < kVectors - kSystemExceptions && priority >= 1 && priority <= 15);
  for (const uint8_t level_irq : kLevelIrq) SYROF_CHECK(irq != level_irq);
  SYROF_CHECK(irq != kTimerIrq);
  armv7m::Disable(irq);
  ram_vectors[kSystemExceptions + irq] = reinterpret_cast<uint32_t>(handler);
  asm volatile("dsb" ::: "memory");
  armv7m::Enable(irq, priority);
}

void Mps2An386Hardware::Attach(NvicPort& port) {
  const uint32_t saved = MaskKernel();
  attached_port = &port;
  RestoreMask(saved);
}

void Mps2An386Hardware::PendLevel(uint8_t level) { armv7m::Pend(kLevelIrq[level]); }

// basepri_max only ever raises the mask, so nested sections keep the outer
// one (and a caller already above the kernel's priority stays there).
uint32_t Mps2An386Hardware::MaskKernel() { return armv7m::RaiseBasepri(kKernelMask); }

void Mps2An386Hardware::RestoreMask(uint32_t previous) { armv7m::RestoreBasepri(previous); }

int64_t Mps2An386Hardware::now_ns() {
  const uint32_t low = 0xFFFFFFFFu - clock_timer().value;
  if (low < last_low_) ticks_high_ += uint64_t{1} << 32;
  last_low_ = low;
  return static_cast<int64_t>(ticks_high_ + low) * kNanosecondsPerTick;
}

void Mps2An386Hardware::SetAlarm(int64_t at_ns) {
  alarm_timer().control = 0;
  alarm_timer().interrupt = 1;
  armv7m::ClearPending(kTimerIrq);
  if (at_ns < 0) return;
  const int64_t ahead_ns = at_ns - now_ns();
  if (ahead_ns <= 0) {
    armv7m::Pend(kTimerIrq);
    return;
  }
  // Round up: the interrupt must never come before at_ns.
  constexpr int64_t kLongestAlarmNs = int64_t{kLongestAlarmTicks} * kNanosecondsPerTick;
  static_assert(kLongestAlarmNs < (int64_t{1} << 32));
  const uint32_t ticks = ahead_ns >= kLongestAlarmNs
                             ? kLongestAlarmTicks
                             : (static_cast<uint32_t>(ahead_ns) + (kNanosecondsPerTick - 1)) / kNanosecondsPerTick;
  alarm_timer().reload = ticks;
  alarm_timer().value = ticks;
  alarm_timer().control = kTimerEnable | kTimerInterruptEnable;
}

}  // namespace syrof::firmware::kernel
