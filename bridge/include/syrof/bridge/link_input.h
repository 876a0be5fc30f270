// Where the base station's bytes come from: a serial device (the base
// station's radio on USB or a UART), a Unix stream socket (the emulated
// swarm's base station, syrof-firmware-swarm --base-station), or a file or
// stdin (captures, tests, fuzzing). Each gives a file descriptor to read
// from; the bridge's loop polls it.
#pragma once

#include <cstdint>
#include <optional>
#include <string>

#include "syrof/lab/base/error.h"

namespace syrof::bridge {

/// An open input: a descriptor the caller closes (CloseLink), or why not.
struct LinkOrError {
  int fd = -1;
  std::optional<lab::Error> error;
  bool ok() const { return fd >= 0; }
};

/// Baud rates OpenSerial accepts (termios has a constant for each).
bool IsSupportedBaud(uint32_t baud);

/// Opens `device` in raw mode (termios: 8N1, no flow control, no echo, no
/// line editing, no translation of CR/LF, reads return what has arrived) at
/// `baud`. A USB CDC device (ttyACM) ignores the rate. Errors name the
/// device and errno's words.
LinkOrError OpenSerial(const std::string& device, uint32_t baud);

/// Connects to a Unix stream socket at `path`, trying again for
/// `wait_ms` while it is not there yet (the emulated swarm creates it when
/// it starts).
LinkOrError ConnectSocket(const std::string& path, int wait_ms);

/// Opens a file for reading; "-" is stdin.
LinkOrError OpenInputFile(const std::string& path);

/// Closes a descriptor OpenSerial, ConnectSocket or OpenInputFile gave (not stdin).
void CloseLink(int fd);

}  // namespace syrof::bridge
