// Fd (one owner closes the descriptor) and WriteAll (every byte, or false).
#include "syrof/process/fd.h"

#include <gtest/gtest.h>
#include <fcntl.h>
#include <signal.h>
#include <sys/wait.h>
#include <unistd.h>

#include <string>
#include <utility>
#include <vector>

namespace syrof::process {
namespace {

bool IsOpen(int fd) { return fcntl(fd, F_GETFD) != -1; }

TEST(FdTest, ClosesItsDescriptorWhenItGoes) {
  int raw = -1;
  {
    Fd fd(open("/dev/null", O_RDONLY | O_CLOEXEC));
    ASSERT_TRUE(fd.valid());
    raw = fd.get();
    EXPECT_TRUE(IsOpen(raw));
  }
  EXPECT_FALSE(IsOpen(raw));
}

TEST(FdTest, AMoveHandsOverTheDescriptorAndOnlyTheNewOwnerClosesIt) {
  Fd first(open("/dev/null", O_RDONLY | O_CLOEXEC));
  const int raw = first.get();
  Fd second(std::move(first));
  EXPECT_FALSE(first.valid());  // NOLINT(bugprone-use-after-move): the contract under test
  EXPECT_EQ(second.get(), raw);
  first.Reset();  // closes nothing
  EXPECT_TRUE(IsOpen(raw));
  Fd third;
  third = std::move(second);
  EXPECT_EQ(third.get(), raw);
  EXPECT_TRUE(IsOpen(raw));
  third.Reset();
  EXPECT_FALSE(IsOpen(raw));
}

TEST(FdTest, AssigningOverAnOwnerClosesWhatItHeld) {
  Fd held(open("/dev/null", O_RDONLY | O_CLOEXEC));
  const int old_raw = held.get();
  Fd other(open("/dev/zero", O_RDONLY | O_CLOEXEC));
  const int new_raw = other.get();
  held = std::move(other);
  EXPECT_FALSE(IsOpen(old_raw));
  EXPECT_EQ(held.get(), new_raw);
}

TEST(FdTest, ReleaseGivesTheDescriptorUpWithoutClosingIt) {
  Fd fd(open("/dev/null", O_RDONLY | O_CLOEXEC));
  const int raw = fd.Release();
  EXPECT_FALSE(fd.valid());
  EXPECT_TRUE(IsOpen(raw));
  close(raw);
}

TEST(WriteAllTest, WritesEveryByteThroughAPipeSmallerThanTheBuffer) {
  int ends[2];
  ASSERT_EQ(pipe2(ends, O_CLOEXEC), 0);
  Fd read_end(ends[0]);
  Fd write_end(ends[1]);
  // More than a pipe holds (64 KiB): WriteAll must go on after partial writes.
  std::vector<char> data(1 << 20);
  for (size_t i = 0; i < data.size(); ++i) data[i] = static_cast<char>(i * 7 + 3);
  std::string received;
  pid_t reader = fork();
  ASSERT_GE(reader, 0);
  if (reader == 0) {
    write_end.Reset();
    char buffer[4096];
    size_t total = 0;
    uint32_t sum = 0;
    for (ssize_t got; (got = read(read_end.get(), buffer, sizeof buffer)) > 0;) {
      for (ssize_t i = 0; i < got; ++i) sum = sum * 31 + static_cast<unsigned char>(buffer[i]);
      total += static_cast<size_t>(got);
    }
    _exit(total == (1u << 20) ? static_cast<int>(sum % 200) : 255);
  }
  read_end.Reset();
  EXPECT_TRUE(WriteAll(write_end.get(), data.data(), data.size()));
  write_end.Reset();
  int status = 0;
  ASSERT_EQ(waitpid(reader, &status, 0), reader);
  uint32_t sum = 0;
  for (char c : data) sum = sum * 31 + static_cast<unsigned char>(c);
  ASSERT_TRUE(WIFEXITED(status));
  EXPECT_EQ(WEXITSTATUS(status), static_cast<int>(sum % 200));
}

TEST(WriteAllTest, IsFalseWhenTheReaderIsGone) {
  int ends[2];
  ASSERT_EQ(pipe2(ends, O_CLOEXEC), 0);
  Fd write_end(ends[1]);
  close(ends[0]);
  struct sigaction ignore {};
  ignore.sa_handler = SIG_IGN;
  struct sigaction previous {};
  sigaction(SIGPIPE, &ignore, &previous);
  const char text[] = "lost";
  EXPECT_FALSE(WriteAll(write_end.get(), text, sizeof text));
  sigaction(SIGPIPE, &previous, nullptr);
}

}  // namespace
}  // namespace syrof::process
