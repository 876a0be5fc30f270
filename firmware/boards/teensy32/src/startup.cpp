// Reset and exception vectors, the flash configuration field, and the
// clock bring-up of the Teensy 3.2 (MK20DX256VLH7), written from the K20
// reference manual. This file does what crt0 would: memory, clock,
// constructors, main.

#include <cstddef>
#include <cstdint>
#include <cstdio>
#include <cstring>

#include "registers.h"
#include "syrof/board/teensy32/board.h"
#include "syrof/board/teensy32/clock_config.h"

extern "C" {

// Defined by the linker script (teensy32.ld).
extern uint32_t __stack_top;
extern uint32_t __data_start;
extern uint32_t __data_end;
extern const uint32_t __data_load;
extern uint32_t __bss_start__;
extern uint32_t __bss_end__;

void __libc_init_array();
void _init() {}
void _fini() {}

[[noreturn]] void reset_handler();
[[noreturn]] void fault_handler();
[[noreturn]] void unexpected_interrupt_handler();
void systick_handler();
void uart0_status_handler();
void uart2_status_handler();

// The kernel's interrupts (firmware/kernel/teensy32: the ten DMA channels'
// interrupts are its levels, the image uses no DMA; PIT channel 0 is its
// alarm), named after their sources. Weak: an image without the kernel
// keeps them on unrouted_interrupt_handler, which stops in the fault handler.
void unrouted_interrupt_handler();
#define SYROF_WEAK_HANDLER(name) void name() __attribute__((weak, alias("unrouted_interrupt_handler")));
SYROF_WEAK_HANDLER(dma_channel0_handler)
SYROF_WEAK_HANDLER(dma_channel1_handler)
SYROF_WEAK_HANDLER(dma_channel2_handler)
SYROF_WEAK_HANDLER(dma_channel3_handler)
SYROF_WEAK_HANDLER(dma_channel4_handler)
SYROF_WEAK_HANDLER(dma_channel5_handler)
SYROF_WEAK_HANDLER(dma_channel6_handler)
SYROF_WEAK_HANDLER(dma_channel7_handler)
SYROF_WEAK_HANDLER(dma_channel8_handler)
SYROF_WEAK_HANDLER(dma_channel9_handler)
SYROF_WEAK_HANDLER(pit0_handler)
#undef SYROF_WEAK_HANDLER

}  // extern "C"

// The program's main(); C++ forbids calling main by name.
int program_main() asm("main");

namespace {

using Handler = void (*)();
using namespace syrof::board::teensy32;

// 16 system exceptions (the first entry is the initial stack pointer) and
// the MK20DX256's 95 interrupts: 111 words.
constexpr int kVectorCount = 111;

struct VectorTable {
  void* initial_stack_pointer;
  Handler handlers[kVectorCount - 1];
};

constexpr VectorTable MakeVectorTable() {
  VectorTable table{&__stack_top, {}};
  for (Handler& handler : table.handlers) handler = unexpected_interrupt_handler;
  table.handlers[0] = reset_handler;  // 1: Reset
  for (int exception = 2; exception <= 6; ++exception) {
    table.handlers[exception - 1] = fault_handler;  // NMI, HardFault, MemManage, BusFault, UsageFault
  }
  table.handlers[15 - 1] = systick_handler;
  table.handlers[16 + reg::kIrqUart0Status - 1] = uart0_status_handler;
  table.handlers[16 + reg::kIrqUart2Status - 1] = uart2_status_handler;
  constexpr Handler kDmaChannelHandlers[] = {dma_channel0_handler, dma_channel1_handler, dma_channel2_handler,
                                             dma_channel3_handler, dma_channel4_handler, dma_channel5_handler,
                                             dma_channel6_handler, dma_channel7_handler, dma_channel8_handler,
                                             dma_channel9_handler};
  for (int channel = 0; channel < 10; ++channel) {
    table.handlers[16 + reg::kIrqDmaChannel0 + channel - 1] = kDmaChannelHandlers[channel];
  }
  table.handlers[16 + reg::kIrqPit0 - 1] = pit0_handler;
  return table;
}

// The flash configuration field (0x400-0x40F), read by the chip at reset:
// backdoor key, program-flash protection (none), FSEC 0xDE (unsecured,
// mass erase allowed: a wrong value can lock the chip for good), FOPT 0xF9,
// EEPROM and data-flash protection off.
struct FlashConfiguration {
  uint8_t bytes[16];
};
constexpr FlashConfiguration kFlashConfiguration{{0xFF, 0xFF, 0xFF, 0xFF, 0xFF, 0xFF, 0xFF, 0xFF,  // backdoor key
                                                  0xFF, 0xFF, 0xFF, 0xFF,                          // FPROT3..0
                                                  0xDE, 0xF9, 0xFF, 0xFF}};  // FSEC, FOPT, FEPROT, FDPROT
static_assert(sizeof(FlashConfiguration) == 16);

constexpr uint32_t kSysTickHz = 1000;
constexpr uint32_t kSysTickReload = SysTickReload(kCoreHz, kSysTickHz);
static_assert(kSysTickReload < (1u << 24), "SysTick's reload register has 24 bits");

volatile uint32_t systick_count = 0;

// Waits until (S & mask) == value, bounded; a crystal that never starts
// leaves the chip on its internal clock, which fault_handler reports.
bool WaitMcg(uint8_t mask, uint8_t value) {
  for (uint32_t spin = 0; spin < 2'000'000; ++spin) {
    if ((reg::R8(reg::kMcgS) & mask) == value) return true;
  }
  return false;
}

bool clock_ok = false;

// FEI (reset: the FLL from the slow internal reference, about 21 MHz) ->
// FBE (the crystal drives the system directly) -> PBE (the PLL runs and
// locks, still bypassed) -> PEE (the PLL drives the system at 72 MHz).
bool StartClock() {
  // The 16 MHz crystal with 10 pF of internal load.
  reg::R8(reg::kOsc0Cr) = reg::kOscSc8p | reg::kOscSc2p;
  // FEI -> FBE.
  reg::R8(reg::kMcgC2) = kMcgSettings.c2;
  reg::R8(reg::kMcgC1) = kMcgSettings.c1_fbe;
  if (!WaitMcg(reg::kMcgSOscInit, reg::kMcgSOscInit)) return false;
  if (!WaitMcg(reg::kMcgSIrefst, 0)) return false;
  if (!WaitMcg(reg::kMcgSClkstMask, reg::kMcgSClkstExternal)) return false;
  // FBE -> PBE: the PLL from 2 MHz x 36.
  reg::R8(reg::kMcgC5) = kMcgSettings.c5;
  reg::R8(reg::kMcgC6) = kMcgSettings.c6;
  if (!WaitMcg(reg::kMcgSPllst, reg::kMcgSPllst)) return false;
  if (!WaitMcg(reg::kMcgSLock, reg::kMcgSLock)) return false;
  // The dividers before the clock speeds up: core 72, bus 36, flash 24 MHz.
  reg::R32(reg::kSimClkdiv1) = kMcgSettings.clkdiv1;
  // PBE -> PEE.
  reg::R8(reg::kMcgC1) = kMcgSettings.c1_pee;
  return WaitMcg(reg::kMcgSClkstMask, reg::kMcgSClkstPll);
}

void StartSysTick() {
  reg::R32(reg::kSystRvr) = kSysTickReload;
  reg::R32(reg::kSystCvr) = 0;
  // SysTick at priority 1 (0x10), above the kernel (timer 4, levels 5-14):
  // BusyDelay's clock keeps counting inside a task. It never calls the
  // kernel, whose own clock is the PIT (firmware/kernel/teensy32).
  reg::R32(reg::kScbShpr3) = (reg::R32(reg::kScbShpr3) & 0x00FFFFFFu) | (0x10u << 24);
  reg::R32(reg::kSystCsr) = 0x7;  // ENABLE, TICKINT, CLKSOURCE = core clock
}

}  // namespace

extern "C" [[gnu::section(".vectors"), gnu::used]] const VectorTable vector_table = MakeVectorTable();
extern "C" [[gnu::section(".flashconfig"), gnu::used]] const FlashConfiguration flash_configuration =
    kFlashConfiguration;

// No stack frame work before the watchdog: the unlock must come within 256
// bus cycles of reset, and its two keys within 20 bus cycles of each other.
extern "C" [[gnu::naked]] void reset_handler() {
  asm volatile(
      "ldr r0, =0x4005200E \n"  // WDOG_UNLOCK
      "ldr r1, =0xC520 \n"
      "strh r1, [r0] \n"
      "ldr r1, =0xD928 \n"
      "strh r1, [r0] \n"
      "ldr r0, =0x40052000 \n"  // WDOG_STCTRLH
      "movs r1, #0x10 \n"       // ALLOWUPDATE, WDOGEN clear: disabled
      "strh r1, [r0] \n"
      "b reset_continue \n");
}

static_assert(reg::kWdogUnlock == 0x4005200E && reg::kWdogStctrlh == 0x40052000);
static_assert(reg::kWdogUnlockKey1 == 0xC520 && reg::kWdogUnlockKey2 == 0xD928 && reg::kWdogAllowUpdate == 0x10);

extern "C" [[noreturn, gnu::used]] void reset_continue() {
  const size_t data_bytes =
      static_cast<size_t>(reinterpret_cast<char*>(&__data_end) - reinterpret_cast<char*>(&__data_start));
  std::memcpy(&__data_start, &__data_load, data_bytes);
  const size_t bss_bytes =
      static_cast<size_t>(reinterpret_cast<char*>(&__bss_end__) - reinterpret_cast<char*>(&__bss_start__));
  std::memset(&__bss_start__, 0, bss_bytes);

  clock_ok = StartClock();
  StartSysTick();
  __libc_init_array();
  if (!clock_ok) {
    // Still on the FLL (about 21 MHz): the console's baud rate is wrong, so
    // this is for a debugger; the program does not run at the wrong speed.
    fault_handler();
  }
  program_main();
  // main returned: nothing is left to run.
  for (;;) asm volatile("wfi");
}

extern "C" void systick_handler() { systick_count = systick_count + 1; }

int64_t syrof::board::teensy32::now_ns() {
  uint32_t ticks;
  uint32_t value;
  // A tick may land between the two reads; read again until the count is
  // the same on both sides of the current value. Called with SysTick masked
  // (inside its handler or a higher one) the reading can be a tick early.
  do {
    ticks = systick_count;
    value = reg::R32(reg::kSystCvr);
  } while (ticks != systick_count);
  const uint32_t elapsed_cycles = kSysTickReload - value;
  return static_cast<int64_t>(ticks) * (1'000'000'000 / kSysTickHz) +
         static_cast<int64_t>(elapsed_cycles) * 1'000'000'000 / kCoreHz;
}

void syrof::board::teensy32::BusyDelay::WaitUs(uint32_t microseconds) {
  const int64_t until_ns = now_ns() + static_cast<int64_t>(microseconds) * 1000;
  while (now_ns() < until_ns) {
  }
}

extern "C" void fault_handler() {
  // Interrupts off and spin, so nothing else runs: a debugger finds the
  // exception number in IPSR. (No bkpt: without a debugger attached it
  // would escalate to a lockup.)
  asm volatile("cpsid i");
  for (;;) {
  }
}

extern "C" void unexpected_interrupt_handler() { fault_handler(); }
// Not [[noreturn]], so the kernel's handlers (which return) may replace its
// weak aliases with the same declaration.
extern "C" void unrouted_interrupt_handler() { fault_handler(); }
