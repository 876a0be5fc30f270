#include "syrof/firmware/kernel/teensy32_hardware.h"

#include "../../armv7m/armv7m_nvic.h"
#include "syrof/base/check.h"
#include "syrof/firmware/kernel/nvic_port.h"

namespace syrof::firmware::kernel {
namespace {

using namespace teensy32;

// System integration module: clock gate 6, bit 23 gates the PIT.
volatile uint32_t& sim_scgc6() { return *reinterpret_cast<volatile uint32_t*>(0x4004803Cu); }
constexpr uint32_t kScgc6Pit = 1u << 23;

// Periodic interrupt timer (K20 reference manual, chapter 38): MCR, then a
// block of four registers per channel at 0x100 + 0x10 n. A channel counts
// LDVAL down to 0, sets TIF (interrupting when TIE), reloads LDVAL; clearing
// and setting TEN restarts it from LDVAL.
struct PitChannel {
  volatile uint32_t load_value;     // LDVAL
  volatile uint32_t current_value;  // CVAL
  volatile uint32_t control;        // TCTRL: bit 0 TEN, bit 1 TIE
  volatile uint32_t flag;           // TFLG: bit 0 TIF, write 1 to clear
};
volatile uint32_t& pit_module_control() { return *reinterpret_cast<volatile uint32_t*>(0x40037000u); }  // MCR
PitChannel& alarm_channel() { return *reinterpret_cast<PitChannel*>(0x40037100u); }
PitChannel& clock_channel() { return *reinterpret_cast<PitChannel*>(0x40037110u); }
constexpr uint32_t kTimerEnable = 1u << 0;
constexpr uint32_t kTimerInterruptEnable = 1u << 1;

NvicPort* attached_port = nullptr;

template <uint8_t kLevel>
void RunLevel() {
  attached_port->RunLevel(kLevel);
}

}  // namespace
}  // namespace syrof::firmware::kernel

// The board's vector table calls these by name (weak there, defined here).
#define SYROF_LEVEL_HANDLER(n)                                                                              \
  extern "C" void dma_channel##n##_handler() {                                                              \
    static_assert(syrof::firmware::kernel::teensy32::kLevelIrq[n] == n, "level n is DMA channel n's IRQ"); \
    syrof::firmware::kernel::RunLevel<n>();                                                                 \
  }
SYROF_LEVEL_HANDLER(0)
SYROF_LEVEL_HANDLER(1)
SYROF_LEVEL_HANDLER(2)
SYROF_LEVEL_HANDLER(3)
SYROF_LEVEL_HANDLER(4)
SYROF_LEVEL_HANDLER(5)
SYROF_LEVEL_HANDLER(6)
SYROF_LEVEL_HANDLER(7)
SYROF_LEVEL_HANDLER(8)
SYROF_LEVEL_HANDLER(9)
#undef SYROF_LEVEL_HANDLER
static_assert(syrof::firmware::kernel::kLevelCount == 10, "one handler above per level");

extern "C" void pit0_handler() {
  using namespace syrof::firmware::kernel;
  alarm_channel().control = 0;  // one shot
  alarm_channel().flag = 1;
  attached_port->OnTimer();
}

namespace syrof::firmware::kernel {

Teensy32Hardware::Teensy32Hardware() {
  SYROF_CHECK(armv7m::PriorityGrouping() <= 3u);
  const uint32_t saved = MaskKernel();
  sim_scgc6() = sim_scgc6() | kScgc6Pit;
  pit_module_control() = 0;  // MDIS clear: the module runs; FRZ clear: it runs under a debugger too
  clock_channel().control = 0;
  clock_channel().load_value = 0xFFFFFFFFu;
  clock_channel().control = kTimerEnable;
  alarm_channel().control = 0;
  alarm_channel().flag = 1;
  for (uint8_t level = 0; level < kLevelCount; ++level) armv7m::Enable(kLevelIrq[level], LevelPriority(level));
  armv7m::Enable(kTimerIrq, kTimerPriority);
  RestoreMask(saved);
}

void Teensy32Hardware::Attach(NvicPort& port) {
  const uint32_t saved = MaskKernel();
  attached_port = &port;
  RestoreMask(saved);
}

void Teensy32Hardware::PendLevel(uint8_t level) { armv7m::Pend(kLevelIrq[level]); }

uint32_t Teensy32Hardware::MaskKernel() { return armv7m::RaiseBasepri(kKernelMask); }

void Teensy32Hardware::RestoreMask(uint32_t previous) { armv7m::RestoreBasepri(previous); }

int64_t Teensy32Hardware::now_ns() {
  const uint32_t low = 0xFFFFFFFFu - clock_channel().current_value;
  if (low < last_low_) ticks_high_ += uint64_t{1} << 32;
  last_low_ = low;
  return NsFromTicks(ticks_high_ + low);
}

void Teensy32Hardware::SetAlarm(int64_t at_ns) {
  alarm_channel().control = 0;
  alarm_channel().flag = 1;
  armv7m::ClearPending(kTimerIrq);
  if (at_ns < 0) return;
  const int64_t ahead_ns = at_ns - now_ns();
  if (ahead_ns <= 0) {
    armv7m::Pend(kTimerIrq);
    return;
  }
  // The channel interrupts LDVAL + 1 ticks after it starts.
  alarm_channel().load_value = AlarmTicks(ahead_ns) - 1;
  alarm_channel().control = kTimerEnable | kTimerInterruptEnable;
}

}  // namespace syrof::firmware::kernel
