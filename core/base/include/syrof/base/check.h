// Always-on invariant checks for core code.
//
// SYROF_CHECK is for conditions that can only fail through a bug in SyROF
// itself (a broken invariant), never for bad input or caller mistakes, which
// are reported through error values. It stays enabled in release builds and
// on the robot: continuing with a broken invariant is worse than stopping.
#pragma once

namespace syrof::base {

/// Reports a failed check and stops the program; never returns. On the host
/// it prints to stderr and aborts; on bare metal it prints through newlib
/// (semihosting under qemu) and exits with a non-zero status.
[[noreturn]] void check_failed(const char* expression, const char* file, int line);

}  // namespace syrof::base

#define SYROF_CHECK(condition)                                          \
  do {                                                                  \
    if (!(condition)) {                                                 \
      ::syrof::base::check_failed(#condition, __FILE__, __LINE__);      \
    }                                                                   \
  } while (false)
