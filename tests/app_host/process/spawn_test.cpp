// Spawn of a plain Command, and Child's wait, kill and reap.
#include "syrof/process/spawn.h"

#include <gtest/gtest.h>
#include <fcntl.h>
#include <poll.h>
#include <sched.h>
#include <signal.h>
#include <sys/stat.h>
#include <sys/syscall.h>
#include <sys/wait.h>
#include <unistd.h>

#include <cerrno>
#include <chrono>
#include <fstream>
#include <functional>
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

// The state letter of process `pid` in /proc (R, S, T, Z...).
char StateOf(pid_t pid) {
  std::ifstream stat("/proc/" + std::to_string(pid) + "/stat");
  std::string line;
  std::getline(stat, line);
  const size_t close = line.rfind(')');
  return close == std::string::npos || close + 2 >= line.size() ? '?' : line[close + 2];
}

TEST(SpawnTest, SearchesThePathOnlyWhenAsked) {
  Command command;
  command.argv = {"sh", "-c", "exit 4"};
  command.inherit_environment = true;  // PATH
  const Child unsearched = Spawn(command);
  EXPECT_FALSE(unsearched.started());
  EXPECT_EQ(unsearched.start_error(), ENOENT);
  command.search_path = true;
  Child searched = Spawn(command);
  ASSERT_TRUE(searched.started()) << strerror(searched.start_error());
  EXPECT_EQ(searched.Reap().code, 4);
}

// posix_spawn, and fork and exec (die_with_parent), say why a program did
// not start, and leave no child behind.
TEST(SpawnTest, AProgramThatCannotBeExecutedIsAStartErrorOnBothWaysOfStarting) {
  // Executable, but neither a binary nor a script with a #! line.
  const std::string not_a_program = "/tmp/syrof_spawn_not_a_program_" + std::to_string(getpid());
  std::ofstream(not_a_program) << "not a program\n";
  ASSERT_EQ(chmod(not_a_program.c_str(), 0755), 0);
  for (const bool forked : {false, true}) {
    Command command;
    command.argv = {"/nonexistent/syrof-no-such-program"};
    command.die_with_parent = forked;
    const Child missing = Spawn(command);
    EXPECT_FALSE(missing.started()) << forked;
    EXPECT_EQ(missing.start_error(), ENOENT) << forked;
    command.argv = {not_a_program};
    const Child not_executable = Spawn(command);
    EXPECT_FALSE(not_executable.started()) << forked;
    EXPECT_EQ(not_executable.start_error(), ENOEXEC) << forked;
    EXPECT_EQ(waitpid(-1, nullptr, WNOHANG), -1) << forked;  // nothing left to reap
    EXPECT_EQ(errno, ECHILD) << forked;
  }
  unlink(not_a_program.c_str());
}

TEST(SpawnTest, ForkAndExecTakeTheCommandAsPosixSpawnDoes) {
  Pipe output;
  Command command;
  command.argv = {"/bin/sh", "-c", "echo \"$1 $GREETING $(pwd)\"; cat; echo to-errors >&2", "sh", "first"};
  command.environment = {"GREETING=hello"};
  command.working_directory = "/usr";
  command.descriptors = {{1, output.write_end.get()}, {2, output.write_end.get()}};
  command.die_with_parent = true;
  Child child = Spawn(command);
  ASSERT_TRUE(child.started()) << strerror(child.start_error());
  EXPECT_EQ(output.ReadAll(), "first hello /usr\nto-errors\n");  // cat: standard input is /dev/null
  EXPECT_EQ(child.Reap().code, 0);
}

// Starts a process that starts a child with `start`, then kills that process
// with SIGKILL: whether the child died with it (it is not ours to reap, so
// its pidfd says when it ended).
bool DiesWithItsStarter(const std::function<Child()>& start) {
  Pipe pid_pipe;
  const pid_t starter = fork();
  if (starter == 0) {
    Child child = start();
    const pid_t pid = child.pid();
    (void)WriteAll(pid_pipe.write_end.get(), &pid, sizeof pid);
    for (;;) pause();
  }
  pid_pipe.write_end.Reset();
  pid_t pid = -1;
  EXPECT_EQ(read(pid_pipe.read_end.get(), &pid, sizeof pid), static_cast<ssize_t>(sizeof pid));
  const Fd pidfd(static_cast<int>(syscall(SYS_pidfd_open, pid, 0)));
  EXPECT_TRUE(pidfd.valid());
  kill(starter, SIGKILL);
  waitpid(starter, nullptr, 0);
  pollfd ended{pidfd.get(), POLLIN, 0};
  const bool died = poll(&ended, 1, 10'000) == 1;
  if (!died) kill(pid, SIGKILL);
  return died;
}

TEST(SpawnTest, AChildDiesWithItsStarterWhenAsked) {
  for (const bool die : {false, true}) {
    const bool died = DiesWithItsStarter([die] {
      Command command;
      command.argv = {"/bin/sleep", "30"};
      command.die_with_parent = die;
      return Spawn(command);
    });
    EXPECT_EQ(died, die);
  }
}

TEST(SpawnTest, RunsUnderSchedFifoWhenAsked) {
  for (const bool forked : {false, true}) {
    Command command;
    command.argv = {"/bin/sleep", "30"};
    command.fifo_priority = 3;
    command.die_with_parent = forked;
    Child child = Spawn(command);
    if (!child.started() && child.start_error() == EPERM) GTEST_SKIP() << "SCHED_FIFO needs CAP_SYS_NICE";
    ASSERT_TRUE(child.started()) << strerror(child.start_error());
    EXPECT_EQ(sched_getscheduler(child.pid()), SCHED_FIFO) << forked;
    sched_param parameters{};
    EXPECT_EQ(sched_getparam(child.pid(), &parameters), 0);
    EXPECT_EQ(parameters.sched_priority, 3) << forked;
    child.Kill();
  }
}

TEST(SpawnTest, EntersTheNetworkNamespaceGiven) {
  // Not a namespace: the start fails, saying so.
  const Fd not_a_namespace(open("/dev/null", O_RDONLY | O_CLOEXEC));
  Command refused;
  refused.argv = {"/bin/true"};
  refused.network_namespace = not_a_namespace.get();
  const Child not_started = Spawn(refused);
  EXPECT_FALSE(not_started.started());
  EXPECT_EQ(not_started.start_error(), EINVAL);

  if (geteuid() != 0) GTEST_SKIP() << "making and entering a network namespace needs root";
  // A process in a network namespace of its own holds it.
  Command holder;
  holder.argv = {"/usr/bin/unshare", "--net", "/bin/sleep", "30"};
  Child held = Spawn(holder);
  ASSERT_TRUE(held.started()) << strerror(held.start_error());
  auto namespace_of = [](const std::string& pid) {
    char target[64] = {};
    const ssize_t length = readlink(("/proc/" + pid + "/ns/net").c_str(), target, sizeof target - 1);
    return std::string(target, length > 0 ? static_cast<size_t>(length) : 0);
  };
  const std::string ours = namespace_of("self");
  std::string theirs = ours;
  for (int tries = 0; tries < 1000 && theirs == ours; ++tries) {  // until unshare has run
    usleep(10'000);
    theirs = namespace_of(std::to_string(held.pid()));
  }
  ASSERT_NE(theirs, ours);
  const Fd net(open(("/proc/" + std::to_string(held.pid()) + "/ns/net").c_str(), O_RDONLY | O_CLOEXEC));
  ASSERT_TRUE(net.valid());
  Pipe output;
  Command command;
  command.argv = {"/bin/readlink", "/proc/self/ns/net"};
  command.network_namespace = net.get();
  command.descriptors = {{1, output.write_end.get()}};
  Child child = Spawn(command);
  ASSERT_TRUE(child.started()) << strerror(child.start_error());
  EXPECT_EQ(output.ReadAll(), theirs + "\n");
  EXPECT_EQ(child.Reap().code, 0);
}

TEST(ChildTest, SignalStopsAndContinuesTheChild) {
  Command command;
  command.argv = {"/bin/sleep", "30"};
  Child child = Spawn(command);
  ASSERT_TRUE(child.started());
  child.Signal(SIGSTOP);
  char state = '?';
  for (int tries = 0; tries < 1000 && (state = StateOf(child.pid())) != 'T'; ++tries) usleep(10'000);
  EXPECT_EQ(state, 'T');
  child.Signal(SIGCONT);
  for (int tries = 0; tries < 1000 && (state = StateOf(child.pid())) == 'T'; ++tries) usleep(10'000);
  EXPECT_NE(state, 'T');
  child.Kill();
  EXPECT_EQ(child.Reap().signal, SIGKILL);
}

TEST(ChildTest, TheStatusCarriesTheChildsCpuTime) {
  Child idle = Spawn(Shell("exit 0"));
  Child busy = Spawn(Shell("i=0; while [ $i -lt 300000 ]; do i=$((i+1)); done"));
  ASSERT_TRUE(idle.started());
  ASSERT_TRUE(busy.started());
  const double idle_seconds = idle.Reap().cpu_seconds;
  const double busy_seconds = busy.Reap().cpu_seconds;
  EXPECT_GT(busy_seconds, 0.0);
  EXPECT_GT(busy_seconds, idle_seconds);
}

TEST(ForkHelperTest, RunsTheBodyInACopyOfTheCallerAndExitsWithItsValue) {
  Pipe output;
  const int fd = output.write_end.get();
  Child helper = ForkHelper([fd] {
    static const char kText[] = "from the helper";
    return WriteAll(fd, kText, sizeof kText - 1) ? 6 : 1;
  });
  ASSERT_TRUE(helper.started()) << strerror(helper.start_error());
  EXPECT_EQ(output.ReadAll(), "from the helper");
  EXPECT_EQ(helper.Reap().code, 6);
}

TEST(ForkHelperTest, TheHelperDiesWithItsStarter) {
  EXPECT_TRUE(DiesWithItsStarter([] {
    return ForkHelper([] {
      for (;;) pause();
      return 0;
    });
  }));
}

}  // namespace
}  // namespace syrof::process

namespace syrof::process {
namespace {

// A child's copy made with CLONE_PARENT is this process's child: Adopt
// holds it as a Child (waited for, with its status); a pid that is not a
// child of this process is refused.
TEST(AdoptTest, HoldsACopyAChildMadeWithCloneParent) {
  int report[2];
  ASSERT_EQ(pipe(report), 0);
  Child helper = ForkHelper([&] {
    const long pid = syscall(SYS_clone, CLONE_PARENT, 0, nullptr, nullptr, 0);
    if (pid == 0) {
      const timespec pause{0, 50'000'000};
      nanosleep(&pause, nullptr);
      _exit(7);
    }
    const pid_t made = static_cast<pid_t>(pid);
    return write(report[1], &made, sizeof(made)) == static_cast<ssize_t>(sizeof(made)) ? 0 : 1;
  });
  ASSERT_TRUE(helper.started());
  pid_t copy = -1;
  ASSERT_EQ(read(report[0], &copy, sizeof(copy)), static_cast<ssize_t>(sizeof(copy)));
  close(report[0]);
  close(report[1]);
  ASSERT_GT(copy, 0);
  EXPECT_EQ(helper.Reap().code, 0);

  Child adopted = Adopt(copy);
  ASSERT_TRUE(adopted.started());
  EXPECT_GE(adopted.pidfd(), 0);
  const std::optional<ExitStatus> status = adopted.Wait(std::chrono::seconds(5));
  ASSERT_TRUE(status.has_value());
  EXPECT_TRUE(status->exited());
  EXPECT_EQ(status->code, 7);

  const Child not_ours = Adopt(1);
  EXPECT_FALSE(not_ours.started());
  EXPECT_EQ(not_ours.start_error(), ECHILD);
}

}  // namespace
}  // namespace syrof::process
