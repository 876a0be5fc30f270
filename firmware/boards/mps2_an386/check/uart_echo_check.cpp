// Two qemu instances of this image, joined by a Unix socket on UART1
// (uart_echo.cmake): "echo N" sends back the first N bytes it receives;
// "ping" sends every byte value 0..255 and checks they come back in order.
// Exit status 0 on success, 1 on a wrong byte, 2 on a timeout. The ping side
// reports on stderr: its stdout is the pipe CMake runs the pair through.
#include <cstdint>
#include <cstdio>
#include <cstdlib>
#include <cstring>

#include "syrof/board/mps2_an386/cmsdk_uart.h"

namespace {

using syrof::board::mps2_an386::CmsdkTimer;
using syrof::board::mps2_an386::CmsdkUart;

// Guest time, so the bound is the same on every host (-icount shift=0).
constexpr uint64_t kTimeoutCycles = uint64_t{2} * CmsdkTimer::kClockHz;  // the exchange takes ~40 ms
// After its last byte the echo side lingers before exiting: qemu may still
// hold bytes for the socket that an exit would throw away.
constexpr uint64_t kLingerCycles = CmsdkTimer::kClockHz / 10;

int Echo(CmsdkUart& uart, CmsdkTimer& timer, int count) {
  int echoed = 0;
  while (echoed < count || !uart.transmit_idle()) {
    uart.Poll();
    uint8_t byte;
    if (echoed < count && uart.Free() > 0 && uart.Read({&byte, 1}) == 1) {
      (void)uart.Write({&byte, 1});
      ++echoed;
    }
    if (timer.count_cycles() > kTimeoutCycles) {
      std::printf("uart echo: timed out after %d of %d bytes\n", echoed, count);
      return 2;
    }
  }
  const uint64_t until = timer.count_cycles() + kLingerCycles;
  while (timer.count_cycles() < until) {
  }
  std::printf("uart echo: sent back %d bytes\n", echoed);
  return 0;
}

int Ping(CmsdkUart& uart, CmsdkTimer& timer) {
  uint8_t sent[256];
  for (int i = 0; i < 256; ++i) sent[i] = static_cast<uint8_t>(i);
  size_t queued = 0;
  size_t received = 0;
  while (received < sizeof sent) {
    queued += uart.Write({sent + queued, sizeof sent - queued});
    uart.Poll();
    uint8_t byte;
    while (uart.Read({&byte, 1}) == 1) {
      if (byte != sent[received]) {
        std::fprintf(stderr, "uart ping: byte %u came back as %u\n", static_cast<unsigned>(received),
                    static_cast<unsigned>(byte));
        return 1;
      }
      ++received;
    }
    if (timer.count_cycles() > kTimeoutCycles) {
      std::fprintf(stderr, "uart ping: timed out with %u of 256 bytes back\n", static_cast<unsigned>(received));
      return 2;
    }
  }
  std::fprintf(stderr, "uart ping: 256 bytes out and back through the socket in %u us of guest time, %u dropped\n",
               static_cast<unsigned>(timer.count_cycles() / (CmsdkTimer::kClockHz / 1'000'000)),
               static_cast<unsigned>(uart.dropped()));
  return uart.dropped() == 0 ? 0 : 1;
}

}  // namespace

int main(int argc, char** argv) {
  CmsdkUart uart(syrof::board::mps2_an386::kCmsdkUart1);
  uart.Start();
  CmsdkTimer timer(CmsdkTimer::kTimer0);
  timer.Start();
  if (argc >= 3 && std::strcmp(argv[1], "echo") == 0) return Echo(uart, timer, std::atoi(argv[2]));
  if (argc >= 2 && std::strcmp(argv[1], "ping") == 0) return Ping(uart, timer);
  std::printf("usage: uart_echo_check echo N | ping\n");
  return 2;
}
