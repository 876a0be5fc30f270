// Reset and exception vectors for qemu's mps2-an386 (Cortex-M4).
//
// The image is linked with newlib's rdimon (semihosting) syscalls but without
// its start files, so this file does what crt0 would: set up memory, open the
// semihosting console, run constructors, call main and hand its return value
// to exit(), which qemu turns into its own exit status.
//
// The FPU stays disabled (CPACR untouched): a floating-point instruction that
// slipped into a soft-float build traps instead of silently running, so code
// that passes here runs on the FPU-less Teensy 3.2 too.

#include <cstdint>
#include <cstdlib>
#include <cstring>

#include "semihosting.h"

extern "C" {

// Defined by the linker script.
extern std::uint32_t __stack_top;
extern std::uint32_t __data_start;
extern std::uint32_t __data_end;
extern const std::uint32_t __data_load;
extern std::uint32_t __bss_start__;
extern std::uint32_t __bss_end__;
extern std::uint32_t __heap_end;
// rdimon's _sbrk refuses to grow the heap past this address (or the current
// stack pointer); it is an rdimon variable that its crt0 would have set.
extern void* __heap_limit;

// From newlib. initialise_monitor_handles opens the semihosting stdin, stdout
// and stderr (without it printf prints nothing); __libc_init_array runs the
// constructors in .preinit_array and .init_array.
void initialise_monitor_handles();
void __libc_init_array();

// __libc_init_array and exit() call these; the C++ runtime needs nothing from
// them because constructors and destructors go through the init/fini arrays.
void _init() {}
void _fini() {}

[[noreturn]] void reset_handler();
[[noreturn]] void fault_handler();
[[noreturn]] void unexpected_interrupt_handler();
void systick_handler();  // in cycles.cpp

}  // extern "C"

// The program's main(). C++ forbids calling main from within the program, so
// the reset handler reaches it through this alias of the same symbol.
int program_main(int argc, char** argv) asm("main");

namespace {

using Handler = void (*)();

// 16 system exceptions plus the 32 external interrupts qemu's mps2-an386
// wires to its NVIC. Nothing here enables an external interrupt; the entries
// only make a stray one stop the program with a message instead of jumping
// into code.
constexpr int kSystemExceptions = 16;
constexpr int kExternalInterrupts = 32;

struct VectorTable {
  void* initial_stack_pointer;
  Handler handlers[kSystemExceptions - 1 + kExternalInterrupts];
};

constexpr VectorTable make_vector_table() {
  VectorTable table{&__stack_top, {}};
  for (Handler& handler : table.handlers) handler = unexpected_interrupt_handler;
  table.handlers[0] = reset_handler;   // 1: Reset
  table.handlers[1] = fault_handler;   // 2: NMI
  table.handlers[2] = fault_handler;   // 3: HardFault
  table.handlers[3] = fault_handler;   // 4: MemManage
  table.handlers[4] = fault_handler;   // 5: BusFault
  table.handlers[5] = fault_handler;   // 6: UsageFault
  table.handlers[14] = systick_handler;  // 15: SysTick
  return table;
}

}  // namespace

// Placed first in CODE by the linker script; the core reads the initial stack
// pointer and the reset vector from address 0.
extern "C" [[gnu::section(".vectors"), gnu::used]] const VectorTable vector_table = make_vector_table();

extern "C" void reset_handler() {
  const std::size_t data_bytes =
      static_cast<std::size_t>(reinterpret_cast<char*>(&__data_end) - reinterpret_cast<char*>(&__data_start));
  std::memcpy(&__data_start, &__data_load, data_bytes);
  const std::size_t bss_bytes =
      static_cast<std::size_t>(reinterpret_cast<char*>(&__bss_end__) - reinterpret_cast<char*>(&__bss_start__));
  std::memset(&__bss_start__, 0, bss_bytes);
  __heap_limit = &__heap_end;

  initialise_monitor_handles();
  __libc_init_array();

  // The command line comes from qemu (`-append "..."`), so a test image takes
  // options such as --gtest_filter when run by hand.
  syrof::board::CommandLine& command_line = syrof::board::semihosting_command_line();
  std::exit(program_main(command_line.argc, command_line.argv));
}

extern "C" void fault_handler() {
  std::uint32_t exception_number;
  asm volatile("mrs %0, ipsr" : "=r"(exception_number));
  syrof::board::semihosting_fatal("mps2-an386: fault exception", exception_number);
}

extern "C" void unexpected_interrupt_handler() {
  std::uint32_t exception_number;
  asm volatile("mrs %0, ipsr" : "=r"(exception_number));
  syrof::board::semihosting_fatal("mps2-an386: unexpected interrupt", exception_number);
}
