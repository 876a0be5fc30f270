#include "syrof/bridge/link_input.h"

#include <gtest/gtest.h>
#include <poll.h>
#include <pty.h>
#include <sys/socket.h>
#include <sys/un.h>
#include <unistd.h>

#include <cstring>
#include <string>
#include <thread>
#include <vector>

namespace syrof::bridge {
namespace {

// Reads until `count` bytes came or 2 s passed (a bound on a broken test, not a timing assertion).
std::vector<uint8_t> ReadSome(int fd, size_t count) {
  std::vector<uint8_t> bytes;
  while (bytes.size() < count) {
    pollfd entry{fd, POLLIN, 0};
    if (poll(&entry, 1, 2000) != 1) break;
    uint8_t buffer[256];
    const ssize_t got = read(fd, buffer, sizeof buffer);
    if (got <= 0) break;
    bytes.insert(bytes.end(), buffer, buffer + got);
  }
  return bytes;
}

TEST(LinkInputTest, ASerialDeviceIsRawEveryByteValuePassesUnchanged) {
  int controller = -1, device = -1;
  char name[256] = {};
  ASSERT_EQ(openpty(&controller, &device, name, nullptr, nullptr), 0);
  const LinkOrError link = OpenSerial(name, 1'000'000);
  ASSERT_TRUE(link.ok()) << link.error->ToString();

  // A line-mode terminal would eat ^C, ^S/^Q and ^D, turn CR into LF and
  // hold everything until a newline; a frame uses every byte value.
  std::vector<uint8_t> all(256);
  for (int i = 0; i < 256; ++i) all[i] = static_cast<uint8_t>(i);
  ASSERT_EQ(write(controller, all.data(), all.size()), 256);
  EXPECT_EQ(ReadSome(link.fd, all.size()), all);
  CloseLink(link.fd);
  close(device);
  close(controller);
}

TEST(LinkInputTest, ANonSerialFileOrAnUnknownRateIsRefusedByName) {
  const LinkOrError not_a_tty = OpenSerial("/dev/null", 115200);
  ASSERT_FALSE(not_a_tty.ok());
  EXPECT_NE(not_a_tty.error->ToString().find("/dev/null"), std::string::npos);
  const LinkOrError missing = OpenSerial("/nonexistent/ttyACM9", 115200);
  ASSERT_FALSE(missing.ok());
  EXPECT_NE(missing.error->ToString().find("/nonexistent/ttyACM9: cannot open"), std::string::npos);
  EXPECT_FALSE(OpenSerial("/dev/null", 12345).ok());
  EXPECT_FALSE(IsSupportedBaud(12345));
  EXPECT_TRUE(IsSupportedBaud(1'000'000));
}

TEST(LinkInputTest, ASocketIsConnectedOnceItsServerListens) {
  const std::string path = "/tmp/syrof-bridge-test-" + std::to_string(getpid()) + ".sock";
  unlink(path.c_str());
  // The server starts listening a little after the bridge starts trying.
  std::thread server([&] {
    std::this_thread::sleep_for(std::chrono::milliseconds(150));
    const int listener = socket(AF_UNIX, SOCK_STREAM, 0);
    sockaddr_un address{};
    address.sun_family = AF_UNIX;
    std::memcpy(address.sun_path, path.c_str(), path.size() + 1);
    ASSERT_EQ(bind(listener, reinterpret_cast<sockaddr*>(&address), sizeof address), 0);
    ASSERT_EQ(listen(listener, 1), 0);
    const int client = accept(listener, nullptr, nullptr);
    const uint8_t bytes[] = {0x00, 0x05, 0x00};
    ASSERT_EQ(write(client, bytes, sizeof bytes), 3);
    close(client);
    close(listener);
  });
  const LinkOrError link = ConnectSocket(path, 5000);
  ASSERT_TRUE(link.ok()) << link.error->ToString();
  EXPECT_EQ(ReadSome(link.fd, 3), (std::vector<uint8_t>{0x00, 0x05, 0x00}));
  server.join();
  CloseLink(link.fd);
  unlink(path.c_str());

  const LinkOrError nobody = ConnectSocket(path, 0);
  ASSERT_FALSE(nobody.ok());
  EXPECT_NE(nobody.error->ToString().find("cannot connect"), std::string::npos);
}

}  // namespace
}  // namespace syrof::bridge
