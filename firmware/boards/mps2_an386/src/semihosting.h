// Raw Arm semihosting calls the board needs outside newlib: the command line
// qemu passes to the image, and a last-resort message and exit for faults,
// where newlib's state can no longer be trusted.
#pragma once

#include <cstdint>

namespace syrof::board {

struct CommandLine {
  int argc;
  char** argv;
};

/// The words of qemu's semihosting command line (the image's path, then
/// whatever `-append` gave), split at spaces; no quoting. Read once, kept in
/// static storage. argv[argc] is null.
CommandLine& semihosting_command_line();

/// Prints `message` and `value` in hex to the host's stderr and stops the
/// emulator with a failure status. Safe to call from an exception handler.
[[noreturn]] void semihosting_fatal(const char* message, std::uint32_t value);

}  // namespace syrof::board
