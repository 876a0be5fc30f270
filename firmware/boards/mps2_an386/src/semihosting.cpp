#include "semihosting.h"

namespace syrof::board {
namespace {

// Operation numbers and the exit reason from Arm's semihosting specification.
constexpr std::uint32_t kSysWrite0 = 0x04;
constexpr std::uint32_t kSysGetCmdline = 0x15;
constexpr std::uint32_t kSysExit = 0x18;
constexpr std::uint32_t kAdpStoppedRunTimeError = 0x20023;

std::uint32_t semihosting_call(std::uint32_t operation, const void* argument) {
  std::uint32_t result;
  asm volatile(
      "mov r0, %1\n\t"
      "mov r1, %2\n\t"
      "bkpt 0xab\n\t"
      "mov %0, r0"
      : "=r"(result)
      : "r"(operation), "r"(argument)
      : "r0", "r1", "memory");
  return result;
}

// The robot image's boot line fits (firmware/robot's boot_words.h,
// kMaxBootLineBytes and kMaxBootLineWords: the swarm host checks each
// robot's line against them before it starts qemu).
constexpr int kMaxArguments = 64;
constexpr int kCommandLineBytes = 1024;

}  // namespace

CommandLine& semihosting_command_line() {
  static char text[kCommandLineBytes];
  static char* words[kMaxArguments + 1];
  static CommandLine command_line{0, words};
  static bool read = false;
  if (read) return command_line;
  read = true;

  struct {
    char* buffer;
    std::uint32_t length;
  } block{text, sizeof(text) - 1};
  // qemu refuses a command line longer than the buffer: a run with none of
  // its words would be another run, so it stops here.
  if (semihosting_call(kSysGetCmdline, &block) != 0) {
    semihosting_fatal("mps2-an386: the semihosting command line is longer than its buffer (bytes)",
                      static_cast<std::uint32_t>(kCommandLineBytes - 1));
  }
  text[block.length] = '\0';

  char* cursor = text;
  while (*cursor != '\0' && command_line.argc < kMaxArguments) {
    while (*cursor == ' ') *cursor++ = '\0';
    if (*cursor == '\0') break;
    words[command_line.argc++] = cursor;
    while (*cursor != '\0' && *cursor != ' ') ++cursor;
  }
  while (*cursor == ' ') *cursor++ = '\0';
  if (*cursor != '\0') {
    semihosting_fatal("mps2-an386: the semihosting command line has more words than", kMaxArguments);
  }
  words[command_line.argc] = nullptr;
  return command_line;
}

void semihosting_fatal(const char* message, std::uint32_t value) {
  char line[] = " 0x00000000\n";
  for (int digit = 0; digit < 8; ++digit) {
    line[10 - digit] = "0123456789abcdef"[(value >> (4 * digit)) & 0xF];
  }
  semihosting_call(kSysWrite0, message);
  semihosting_call(kSysWrite0, line);
  // With a reason other than "application exit", qemu exits with status 1.
  semihosting_call(kSysExit, reinterpret_cast<const void*>(kAdpStoppedRunTimeError));
  for (;;) {
  }
}

}  // namespace syrof::board
