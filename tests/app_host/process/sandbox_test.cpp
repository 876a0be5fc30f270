// Spawn in a Sandbox: the uid, the namespaces, the limits, the closed
// descriptors, and that nothing the program starts outlives it. As root the
// child runs as uid 65534; otherwise in a user namespace mapping the
// caller's own ids (both are how the grader's build runs).
#include <gtest/gtest.h>
#include <fcntl.h>
#include <poll.h>
#include <signal.h>
#include <unistd.h>

#include <cerrno>
#include <chrono>
#include <string>

#include "syrof/process/confine.h"
#include "syrof/process/fd.h"
#include "syrof/process/landlock.h"
#include "syrof/process/spawn.h"

namespace syrof::process {
namespace {

struct Ran {
  std::string output;
  ExitStatus status;
  SandboxReport report;
};

Ran RunSandboxed(const std::string& script, const Sandbox& sandbox) {
  int ends[2];
  if (pipe2(ends, O_CLOEXEC) != 0) return {};
  Fd read_end(ends[0]);
  Fd write_end(ends[1]);
  Command command;
  command.argv = {"/bin/sh", "-c", script};
  command.environment = {"PATH=/usr/bin:/bin"};
  command.descriptors = {{1, write_end.get()}, {2, write_end.get()}};
  Child child = Spawn(command, sandbox);
  write_end.Reset();
  Ran ran;
  if (!child.started()) return ran;
  char buffer[4096];
  for (ssize_t got; (got = read(read_end.get(), buffer, sizeof buffer)) != 0;) {
    if (got < 0 && errno == EINTR) continue;
    if (got < 0) break;
    ran.output.append(buffer, static_cast<size_t>(got));
  }
  ran.status = child.Reap();
  ran.report = child.sandbox();
  return ran;
}

Sandbox Default() {
  Sandbox sandbox;
  sandbox.drop_to_nobody = geteuid() == 0;
  return sandbox;
}

TEST(SandboxTest, RunsAsNobodyWhenStartedByRootElseAsItsCaller) {
  const Ran ran = RunSandboxed("id -u; id -g; id -G", Default());
  EXPECT_EQ(ran.report.failure, SandboxFailure::kNone);
  const std::string expected = geteuid() == 0 ? "65534\n65534\n65534\n"
                                              : std::to_string(geteuid()) + "\n" + std::to_string(getegid()) + "\n";
  if (geteuid() == 0) {
    EXPECT_EQ(ran.output, expected);
  } else {
    EXPECT_EQ(ran.output.substr(0, expected.size()), expected);
  }
  EXPECT_EQ(ran.status.code, 0);
}

TEST(SandboxTest, TheProgramHasNoNetworkAndItsOwnPidNamespaceWhereTheKernelAllows) {
  char own[64] = {};
  ASSERT_GT(readlink("/proc/self/ns/net", own, sizeof own - 1), 0);
  const Ran ran = RunSandboxed("readlink /proc/self/ns/net; echo $$", Default());
  if (ran.report.isolation == Isolation::kNone) GTEST_SKIP() << "namespaces refused: " << strerror(ran.report.isolation_errno);
  const size_t newline = ran.output.find('\n');
  EXPECT_NE(ran.output.substr(0, newline), own);
  if (ran.report.isolation == Isolation::kFull) {
    EXPECT_EQ(ran.output.substr(newline + 1), "2\n");  // pid 1 is the namespace's init
  }
}

TEST(SandboxTest, TheProgramsOwnSignalIsReportedThroughTheNamespacesInit) {
  const Ran ran = RunSandboxed("kill -SEGV $$", Default());
  EXPECT_TRUE(ran.status.signaled());
  EXPECT_EQ(ran.status.signal, SIGSEGV);
  const Ran exits = RunSandboxed("exit 9", Default());
  EXPECT_TRUE(exits.status.exited());
  EXPECT_EQ(exits.status.code, 9);
}

TEST(SandboxTest, LimitsAndNoNewPrivilegesApply) {
  Sandbox sandbox = Default();
  sandbox.limits = {{RLIMIT_NOFILE, 32}, {RLIMIT_CORE, 0}};
  const Ran ran = RunSandboxed("ulimit -n; ulimit -c; grep NoNewPrivs /proc/self/status", sandbox);
  EXPECT_EQ(ran.output, "32\n0\nNoNewPrivs:\t1\n");
}

TEST(SandboxTest, OnlyTheRedirectedDescriptorsReachTheProgram) {
  // Open without close-on-exec, as a careless library might.
  const Fd stray(open("/dev/null", O_RDONLY));
  ASSERT_TRUE(stray.valid());
  const Ran ran = RunSandboxed("ls /proc/self/fd", Default());
  // ls's own listing of the folder is the one descriptor above 2.
  EXPECT_EQ(ran.output, "0\n1\n2\n3\n");
}

TEST(SandboxTest, ALandlockRulesetConfinesTheProgram) {
  if (LandlockAbi() == 0) GTEST_SKIP() << "no Landlock on this kernel";
  FileRuleset rules;
  ASSERT_TRUE(rules.Create()) << rules.error();
  for (const char* folder : {"/usr", "/bin", "/lib", "/lib64", "/etc/ld.so.cache"}) {
    ASSERT_TRUE(rules.Allow(folder, FileRuleset::Access::kReadExecute)) << rules.error();
  }
  ASSERT_TRUE(rules.Allow("/dev/null", FileRuleset::Access::kReadWrite)) << rules.error();
  Sandbox sandbox = Default();
  sandbox.files = &rules;
  const Ran ran = RunSandboxed("cat /etc/hostname >/dev/null 2>&1 && echo read || echo refused", sandbox);
  EXPECT_EQ(ran.report.failure, SandboxFailure::kNone);
  EXPECT_EQ(ran.output, "refused\n");
}

TEST(SandboxTest, NothingTheProgramStartsOutlivesIt) {
  int ends[2];
  ASSERT_EQ(pipe2(ends, O_CLOEXEC), 0);
  Fd read_end(ends[0]);
  Fd write_end(ends[1]);
  Command command;
  // A daemon in a session of its own (out of the process group) holds the
  // output open.
  command.argv = {"/bin/sh", "-c", "setsid sleep 300 & exit 0"};
  command.environment = {"PATH=/usr/bin:/bin"};
  command.descriptors = {{1, write_end.get()}};
  Child child = Spawn(command, Default());
  ASSERT_TRUE(child.started());
  write_end.Reset();
  EXPECT_EQ(child.Reap().code, 0);
  if (child.sandbox().isolation != Isolation::kFull) GTEST_SKIP() << "no PID namespace here";
  // The namespace's init ended with the program: the kernel killed the
  // daemon, so the output reaches its end.
  pollfd ready{read_end.get(), POLLIN, 0};
  ASSERT_EQ(poll(&ready, 1, 60'000), 1);
  char byte;
  EXPECT_EQ(read(read_end.get(), &byte, 1), 0);
}

TEST(ConfineTest, CallerIdMapsAreTheOneLineMapsOfTheEffectiveIds) {
  const CallerIdMaps maps = CallerIdMaps::OfCaller();
  EXPECT_EQ(std::string(maps.uid_map), std::to_string(geteuid()) + " " + std::to_string(geteuid()) + " 1\n");
  EXPECT_EQ(std::string(maps.gid_map), std::to_string(getegid()) + " " + std::to_string(getegid()) + " 1\n");
}

}  // namespace
}  // namespace syrof::process
