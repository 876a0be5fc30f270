#include "syrof/bridge/link_input.h"

#include <fcntl.h>
#include <sys/socket.h>
#include <sys/un.h>
#include <termios.h>
#include <unistd.h>

#include <cerrno>
#include <chrono>
#include <cstring>
#include <thread>

namespace syrof::bridge {
namespace {

struct BaudConstant {
  uint32_t baud;
  speed_t constant;
};

constexpr BaudConstant kBauds[] = {
    {9600, B9600},       {19200, B19200},     {38400, B38400},     {57600, B57600},     {115200, B115200},
    {230400, B230400},   {460800, B460800},   {500000, B500000},   {921600, B921600},   {1000000, B1000000},
    {2000000, B2000000}, {3000000, B3000000}, {4000000, B4000000},
};

LinkOrError Failed(const std::string& where, const std::string& what) {
  return LinkOrError{-1, lab::Error{.where = where, .message = what + ": " + std::strerror(errno)}};
}

}  // namespace

bool IsSupportedBaud(uint32_t baud) {
  for (const BaudConstant& entry : kBauds) {
    if (entry.baud == baud) return true;
  }
  return false;
}

LinkOrError OpenSerial(const std::string& device, uint32_t baud) {
  speed_t speed = 0;
  for (const BaudConstant& entry : kBauds) {
    if (entry.baud == baud) speed = entry.constant;
  }
  if (speed == 0) {
    return LinkOrError{-1, lab::Error{.where = "--baud", .message = std::to_string(baud) + " is not a supported rate"}};
  }
  const int fd = open(device.c_str(), O_RDONLY | O_NOCTTY | O_CLOEXEC);
  if (fd < 0) return Failed(device, "cannot open");
  termios settings{};
  if (tcgetattr(fd, &settings) != 0) {
    LinkOrError failed = Failed(device, "not a serial device (tcgetattr)");
    close(fd);
    return failed;
  }
  cfmakeraw(&settings);
  settings.c_cflag |= CLOCAL | CREAD;
  settings.c_cflag &= ~(CSTOPB | PARENB | CRTSCTS);
  settings.c_iflag &= ~(IXON | IXOFF | IXANY);
  // read() returns as soon as a byte is there; the loop polls.
  settings.c_cc[VMIN] = 1;
  settings.c_cc[VTIME] = 0;
  if (cfsetispeed(&settings, speed) != 0 || cfsetospeed(&settings, speed) != 0 ||
      tcsetattr(fd, TCSANOW, &settings) != 0) {
    LinkOrError failed = Failed(device, "cannot set raw mode at " + std::to_string(baud) + " baud");
    close(fd);
    return failed;
  }
  tcflush(fd, TCIFLUSH);  // bytes from before the bridge started belong to no round of its
  return LinkOrError{fd, std::nullopt};
}

LinkOrError ConnectSocket(const std::string& path, int wait_ms) {
  sockaddr_un address{};
  address.sun_family = AF_UNIX;
  if (path.empty() || path.size() >= sizeof address.sun_path) {
    errno = ENAMETOOLONG;
    return Failed(path, "not a usable socket path");
  }
  std::memcpy(address.sun_path, path.c_str(), path.size() + 1);
  const auto give_up = std::chrono::steady_clock::now() + std::chrono::milliseconds(wait_ms);
  for (;;) {
    const int fd = socket(AF_UNIX, SOCK_STREAM | SOCK_CLOEXEC, 0);
    if (fd < 0) return Failed(path, "cannot make a socket");
    if (connect(fd, reinterpret_cast<const sockaddr*>(&address), sizeof address) == 0) return LinkOrError{fd, std::nullopt};
    const int why = errno;
    close(fd);
    errno = why;
    if ((why != ENOENT && why != ECONNREFUSED) || std::chrono::steady_clock::now() >= give_up) {
      return Failed(path, "cannot connect");
    }
    std::this_thread::sleep_for(std::chrono::milliseconds(50));
  }
}

LinkOrError OpenInputFile(const std::string& path) {
  if (path == "-") return LinkOrError{STDIN_FILENO, std::nullopt};
  const int fd = open(path.c_str(), O_RDONLY | O_CLOEXEC);
  if (fd < 0) return Failed(path, "cannot open");
  return LinkOrError{fd, std::nullopt};
}

void CloseLink(int fd) {
  if (fd > STDERR_FILENO) close(fd);
}

}  // namespace syrof::bridge
