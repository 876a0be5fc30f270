// Cycle counter for measuring code regions on the emulated Cortex-M4.
//
// Under `-icount shift=0` (as `make test-m4` runs qemu) the emulated core
// executes one instruction per nanosecond of virtual time, independent of the
// host, so the counter reads the same on every run of the same image. qemu
// models no pipeline or memory timing: one counted cycle is one executed
// instruction. It is a deterministic measure of work on the target
// instruction set, not a prediction of Teensy timing (the real core takes
// extra cycles for loads, branches and multi-cycle instructions).
//
// Built on SysTick, extended to 64 bits by counting its wrap-arounds in the
// SysTick interrupt. SysTick runs from the board's 25 MHz processor clock,
// 40 ns of virtual time (40 instructions) per tick, so readings come in steps
// of kCycleCounterResolution: measure regions of many thousand instructions,
// or repeat a short one in a loop.
#pragma once

#include <cstdint>

namespace syrof::board {

/// Granularity of cycle_counter_read(), in cycles (instructions).
inline constexpr std::uint32_t kCycleCounterResolution = 40;

/// Resets the counter to zero and starts it. Takes over SysTick and its
/// interrupt until the program ends; interrupts must stay enabled (PRIMASK
/// clear) for wrap-arounds, every 2^24 ticks, to be counted.
void cycle_counter_start();

/// Cycles (executed instructions under -icount shift=0) since the last
/// cycle_counter_start(), a multiple of kCycleCounterResolution; 0 if the
/// counter was never started. Non-decreasing.
std::uint64_t cycle_counter_read();

}  // namespace syrof::board
