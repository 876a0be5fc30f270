// Spawn of a plain Command, and Child's wait, kill and reap.
#include "syrof/process/spawn.h"

#include <gtest/gtest.h>
#include <fcntl.h>
#include <poll.h>
#include <signal.h>
#include <sys/wait.h>
#include <unistd.h>

#include <cerrno>
#include <chrono>
#include <fstream>
#include <string>

#include "syrof/process/fd.h"

namespace syrof::process {
namespace {

using std::chrono::milliseconds;

struct Pipe {
  Fd read_end;
  Fd write_end;
  Pipe() {
    int ends[2];
    if (pipe2(ends, O_CLOEXEC) == 0) {
      read_end.Reset(ends[0]);
      write_end.Reset(ends[1]);
    }
  }
  // Everything until every writer is gone.
  std::string ReadAll() {
    write_end.Reset();
    std::string text;
    char buffer[4096];
    for (;;) {
      const ssize_t got = read(read_end.get(), buffer, sizeof buffer);
      if (got < 0 && errno == EINTR) continue;
      if (got <= 0) return text;
      text.append(buffer, static_cast<size_t>(got));
    }
  }
};

Command Shell(const std::string& script) {
  Command command;
  command.argv = {"/bin/sh", "-c", script, "sh"};
  return command;
}

TEST(SpawnTest, RunsTheProgramWithItsArgumentsEnvironmentAndDescriptors) {
  Pipe output;
  Command command;
  command.argv = {"/bin/sh", "-c", "echo \"$1 $GREETING\"; echo to-errors >&2; cat", "sh", "first"};
  command.environment = {"GREETING=hello"};
  command.descriptors = {{1, output.write_end.get()}, {2, output.write_end.get()}};
  Child child = Spawn(command);
  ASSERT_TRUE(child.started()) << strerror(child.start_error());
  // cat reads standard input: /dev/null, so it ends at once.
  EXPECT_EQ(output.ReadAll(), "first hello\nto-errors\n");
  const ExitStatus status = child.Reap();
  EXPECT_TRUE(status.exited());
  EXPECT_EQ(status.code, 0);
}

TEST(SpawnTest, ReportsTheExitCodeOrTheSignal) {
  Child exits = Spawn(Shell("exit 7"));
  ASSERT_TRUE(exits.started());
  const ExitStatus exited = exits.Reap();
  EXPECT_TRUE(exited.exited());
  EXPECT_EQ(exited.code, 7);
  EXPECT_EQ(exits.Reap().code, 7);  // the same status again

  Child signaled = Spawn(Shell("kill -TERM $$"));
  ASSERT_TRUE(signaled.started());
  const ExitStatus killed = signaled.Reap();
  EXPECT_TRUE(killed.signaled());
  EXPECT_EQ(killed.signal, SIGTERM);
}

TEST(SpawnTest, AProgramThatCannotBeExecutedIsAStartError) {
  Command command;
  command.argv = {"/nonexistent/syrof-no-such-program"};
  const Child child = Spawn(command);
  EXPECT_FALSE(child.started());
  EXPECT_EQ(child.start_error(), ENOENT);
}

TEST(SpawnTest, RedirectsWhoseSourcesAreAlsoTargetsReachTheRightDescriptors) {
  Pipe first;
  Pipe second;
  // In this process `first` is 41 and `second` 40; the child gets them the
  // other way round. Placed naively, the first dup2 overwrites the second's source.
  ASSERT_EQ(dup3(first.write_end.get(), 41, O_CLOEXEC), 41);
  ASSERT_EQ(dup3(second.write_end.get(), 40, O_CLOEXEC), 40);
  Fd forty_one(41);
  Fd forty(40);
  Command command;
  command.argv = {"/bin/bash", "-c", "echo to-40 >&40; echo to-41 >&41"};
  command.descriptors = {{40, 41}, {41, 40}};
  Child child = Spawn(command);
  ASSERT_TRUE(child.started()) << strerror(child.start_error());
  forty.Reset();
  forty_one.Reset();
  EXPECT_EQ(first.ReadAll(), "to-40\n");
  EXPECT_EQ(second.ReadAll(), "to-41\n");
  EXPECT_EQ(child.Reap().code, 0);
}

TEST(SpawnTest, StartsInTheWorkingDirectoryGiven) {
  Pipe output;
  Command command = Shell("pwd");
  command.working_directory = "/usr";
  command.descriptors = {{1, output.write_end.get()}};
  Child child = Spawn(command);
  ASSERT_TRUE(child.started());
  EXPECT_EQ(output.ReadAll(), "/usr\n");
  EXPECT_EQ(child.Reap().code, 0);
}

TEST(SpawnTest, AddressRandomisationOffWhenAsked) {
  for (const bool off : {false, true}) {
    Pipe output;
    Command command;
    command.argv = {"/bin/cat", "/proc/self/personality"};
    command.no_address_randomization = off;
    command.descriptors = {{1, output.write_end.get()}};
    Child child = Spawn(command);
    ASSERT_TRUE(child.started());
    const unsigned long persona = std::stoul(output.ReadAll(), nullptr, 16);
    EXPECT_EQ((persona & 0x0040000) != 0, off) << persona;  // ADDR_NO_RANDOMIZE
    EXPECT_EQ(child.Reap().code, 0);
  }
}

TEST(ChildTest, WaitGivesUpAfterItsTimeoutAndKillGroupEndsWhatTheChildStarted) {
  Pipe output;
  // The background sleep keeps the output open: EOF comes only once it is
  // gone too.
  Command command = Shell("sleep 30 & sleep 30");
  command.own_process_group = true;
  command.descriptors = {{1, output.write_end.get()}};
  Child child = Spawn(command);
  ASSERT_TRUE(child.started());
  EXPECT_FALSE(child.Wait(milliseconds(20)).has_value());
  EXPECT_FALSE(child.reaped());
  child.KillGroup();
  const std::optional<ExitStatus> status = child.Wait(milliseconds(60'000));
  ASSERT_TRUE(status.has_value());
  EXPECT_TRUE(status->signaled());
  EXPECT_EQ(status->signal, SIGKILL);
  EXPECT_EQ(output.ReadAll(), "");  // returns: no writer is left
}

TEST(ChildTest, KillReachesTheChildAlone) {
  Pipe output;
  Command command = Shell("sleep 30 & echo $!; wait");
  command.own_process_group = true;
  command.descriptors = {{1, output.write_end.get()}};
  Child child = Spawn(command);
  ASSERT_TRUE(child.started());
  output.write_end.Reset();
  char line[32] = {};
  ASSERT_GT(read(output.read_end.get(), line, sizeof line - 1), 0);
  const pid_t background = static_cast<pid_t>(std::stol(line));
  child.Kill();
  EXPECT_EQ(child.Reap().signal, SIGKILL);
  EXPECT_EQ(kill(background, 0), 0);  // still there: only the shell was killed
  kill(background, SIGKILL);
}

TEST(ChildTest, AChildThatGoesKillsAndReapsItsProcess) {
  pid_t pid = -1;
  {
    Command command;
    command.argv = {"/bin/sleep", "30"};  // no shell between: the child is the sleep
    Child child = Spawn(command);
    ASSERT_TRUE(child.started());
    pid = child.pid();
    Child moved = std::move(child);  // the new owner ends it, once
    EXPECT_FALSE(child.started());   // NOLINT(bugprone-use-after-move): the contract under test
    EXPECT_EQ(moved.pid(), pid);
  }
  EXPECT_EQ(waitpid(pid, nullptr, WNOHANG), -1);  // reaped already
  EXPECT_EQ(errno, ECHILD);
  EXPECT_EQ(kill(pid, 0), -1);
}

TEST(ChildTest, TheProcessDescriptorSaysWhenTheChildEnded) {
  Child child = Spawn(Shell("exit 3"));
  ASSERT_TRUE(child.started());
  if (child.pidfd() < 0) GTEST_SKIP() << "no pidfd_open on this kernel";
  pollfd ready{child.pidfd(), POLLIN, 0};
  ASSERT_EQ(poll(&ready, 1, 60'000), 1);
  const std::optional<ExitStatus> status = child.Wait(milliseconds(0));
  ASSERT_TRUE(status.has_value());
  EXPECT_EQ(status->code, 3);
}

}  // namespace
}  // namespace syrof::process
