// The system calls newlib needs from the board: stdout to the debug console
// and a fixed heap. Everything else comes from nosys (fails with ENOSYS).
#include <sys/stat.h>

#include <cerrno>
#include <cstddef>
#include <cstdint>
#include <span>

#include "syrof/board/teensy32/board.h"

extern "C" {

extern char __heap_start;
extern char __heap_end;

void* __dso_handle = nullptr;

// The heap is a fixed region of the linker script (counted in the RAM
// budget); running out is an error, never a collision with the stack.
void* _sbrk(ptrdiff_t increment) {
  static char* top = &__heap_start;
  if (increment < 0 || &__heap_end - top < increment) {
    errno = ENOMEM;
    return reinterpret_cast<void*>(-1);
  }
  char* previous = top;
  top += increment;
  return previous;
}

// stdout and stderr: the console UART, '\n' sent as "\r\n". Blocks (bounded
// by the console's rate) when the ring is full, so nothing is lost.
int _write(int file, const char* bytes, int length) {
  if (file != 1 && file != 2) {
    errno = EBADF;
    return -1;
  }
  auto& console = syrof::board::teensy32::ConsoleUart();
  if (!console.started()) return length;  // before main starts it: dropped
  for (int i = 0; i < length; ++i) {
    const uint8_t crlf[2] = {'\r', '\n'};
    const bool newline = bytes[i] == '\n';
    const std::span<const uint8_t> chunk =
        newline ? std::span<const uint8_t>(crlf, 2) : std::span<const uint8_t>(reinterpret_cast<const uint8_t*>(bytes + i), 1);
    size_t sent = 0;
    const int64_t deadline_ns = syrof::board::teensy32::now_ns() + 50'000'000;
    while (sent < chunk.size() && syrof::board::teensy32::now_ns() < deadline_ns) {
      sent += console.Write(chunk.subspan(sent));
    }
  }
  return length;
}

}  // extern "C"
