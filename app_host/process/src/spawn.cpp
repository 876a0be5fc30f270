#include "syrof/process/spawn.h"

#include <fcntl.h>
#include <linux/seccomp.h>
#include <poll.h>
#include <sched.h>
#include <signal.h>
#include <spawn.h>
#include <sys/personality.h>
#include <sys/prctl.h>
#include <sys/syscall.h>
#include <sys/wait.h>
#include <unistd.h>

#include <algorithm>
#include <cerrno>
#include <cstring>

#include "syrof/process/confine.h"
#include "syrof/process/landlock.h"

extern char** environ;

namespace syrof::process {
namespace {

// The C arrays exec takes, made before the child starts (no allocation
// after fork).
struct ExecArrays {
  std::vector<char*> argv;
  std::vector<char*> environment;
  explicit ExecArrays(const Command& command) {
    for (const std::string& argument : command.argv) argv.push_back(const_cast<char*>(argument.c_str()));
    argv.push_back(nullptr);
    for (const std::string& entry : command.environment) environment.push_back(const_cast<char*>(entry.c_str()));
    environment.push_back(nullptr);
  }
  char* const* env() const { return environment.data(); }
};

// The redirects with every source moved above the highest target, so that
// placing one never overwrites another's source. The copies made here are
// close-on-exec and closed when the object goes.
class LiftedRedirects {
 public:
  explicit LiftedRedirects(const std::vector<Redirect>& redirects) : redirects_(redirects) {
    for (const Redirect& redirect : redirects_) highest_ = std::max(highest_, redirect.child);
    for (Redirect& redirect : redirects_) {
      if (redirect.parent > highest_) continue;
      const int lifted = fcntl(redirect.parent, F_DUPFD_CLOEXEC, highest_ + 1);
      if (lifted < 0) continue;  // dup2 then reports the problem in the child
      copies_.emplace_back(lifted);
      for (Redirect& same : redirects_) {
        if (&same != &redirect && same.parent == redirect.parent) same.parent = lifted;
      }
      redirect.parent = lifted;
    }
  }
  const std::vector<Redirect>& redirects() const { return redirects_; }
  int highest() const { return highest_; }
  bool names_stdin() const {
    return std::any_of(redirects_.begin(), redirects_.end(), [](const Redirect& r) { return r.child == 0; });
  }

 private:
  std::vector<Redirect> redirects_;
  std::vector<Fd> copies_;
  int highest_ = 2;
};

ExitStatus FromSiginfo(const siginfo_t& info) {
  ExitStatus status;
  if (info.si_code == CLD_EXITED) {
    status.how = ExitStatus::How::kExited;
    status.code = info.si_status;
  } else {
    status.how = ExitStatus::How::kSignaled;
    status.signal = info.si_status;
  }
  return status;
}

int64_t MillisecondsLeft(std::chrono::steady_clock::time_point deadline) {
  return std::chrono::duration_cast<std::chrono::milliseconds>(deadline - std::chrono::steady_clock::now()).count();
}

// A sandboxed child's report pipe carries this once before exec and, from
// a PID namespace's init, the program's wait status after it ends.
struct ReportFrame {
  int isolation = static_cast<int>(Isolation::kNone);
  int isolation_errno = 0;
  int failure = static_cast<int>(SandboxFailure::kNone);
  int failure_errno = 0;
};

constexpr int kNamespaces = CLONE_NEWNET | CLONE_NEWPID | CLONE_NEWIPC | CLONE_NEWUTS;

}  // namespace

ExitStatus ExitStatus::FromWaitStatus(int status) {
  ExitStatus result;
  if (WIFEXITED(status)) {
    result.how = How::kExited;
    result.code = WEXITSTATUS(status);
  } else if (WIFSIGNALED(status)) {
    result.how = How::kSignaled;
    result.signal = WTERMSIG(status);
  }
  return result;
}

Child::~Child() {
  if (started() && !reaped_) {
    KillGroup();
    (void)Reap();
  }
}

Child::Child(Child&& other) noexcept
    : pid_(other.pid_),
      start_error_(other.start_error_),
      own_group_(other.own_group_),
      reaped_(other.reaped_),
      status_(other.status_),
      pidfd_(std::move(other.pidfd_)),
      report_pipe_(std::move(other.report_pipe_)),
      report_(other.report_) {
  other.pid_ = -1;
}

Child& Child::operator=(Child&& other) noexcept {
  if (this == &other) return *this;
  if (started() && !reaped_) {
    KillGroup();
    (void)Reap();
  }
  pid_ = other.pid_;
  start_error_ = other.start_error_;
  own_group_ = other.own_group_;
  reaped_ = other.reaped_;
  status_ = other.status_;
  pidfd_ = std::move(other.pidfd_);
  report_pipe_ = std::move(other.report_pipe_);
  report_ = other.report_;
  other.pid_ = -1;
  return *this;
}

void Child::Finish(ExitStatus status) {
  reaped_ = true;
  status_ = status;
  pidfd_.Reset();
  // The program's own status from the namespace's init: a signal that
  // ended the program is named as such (the init itself always exits).
  int program_status = 0;
  if (report_pipe_.valid() && report_.isolation == Isolation::kFull &&
      read(report_pipe_.get(), &program_status, sizeof program_status) ==
          static_cast<ssize_t>(sizeof program_status)) {
    status_ = ExitStatus::FromWaitStatus(program_status);
  }
  report_pipe_.Reset();
}

std::optional<ExitStatus> Child::Wait(std::chrono::milliseconds timeout) {
  if (!started()) return ExitStatus{};
  if (reaped_) return status_;
  const auto deadline = std::chrono::steady_clock::now() + timeout;
  for (;;) {
    siginfo_t info{};
    if (waitid(P_PID, static_cast<id_t>(pid_), &info, WEXITED | WNOHANG) != 0) {
      if (errno == EINTR) continue;
      Finish(ExitStatus{});  // not ours to wait for any more
      return status_;
    }
    if (info.si_pid != 0) {
      Finish(FromSiginfo(info));
      return status_;
    }
    const int64_t left = MillisecondsLeft(deadline);
    if (left <= 0) return std::nullopt;
    if (pidfd_.valid()) {
      pollfd ready{pidfd_.get(), POLLIN, 0};
      (void)poll(&ready, 1, static_cast<int>(std::min<int64_t>(left, 1000)));
    } else {
      const timespec pause{0, 1'000'000};
      nanosleep(&pause, nullptr);
    }
  }
}

ExitStatus Child::Reap() {
  if (!started()) return ExitStatus{};
  if (reaped_) return status_;
  siginfo_t info{};
  int waited;
  do {
    info = siginfo_t{};
    waited = waitid(P_PID, static_cast<id_t>(pid_), &info, WEXITED);
  } while (waited != 0 && errno == EINTR);
  Finish(waited == 0 ? FromSiginfo(info) : ExitStatus{});
  return status_;
}

void Child::Kill() {
  if (started() && !reaped_) kill(pid_, SIGKILL);
}

void Child::KillGroup() {
  if (!started()) return;
  if (own_group_) {
    // Also after the child is reaped: its group lives on while anything it
    // left in it does (and its number is not reused meanwhile).
    kill(-pid_, SIGKILL);
  } else if (!reaped_) {
    kill(pid_, SIGKILL);
  }
}

Child Spawn(const Command& command) {
  Child child;
  if (command.argv.empty()) {
    child.start_error_ = EINVAL;
    return child;
  }
  const ExecArrays arrays(command);
  const LiftedRedirects lifted(command.descriptors);
  posix_spawn_file_actions_t actions;
  posix_spawn_file_actions_init(&actions);
  if (!lifted.names_stdin()) posix_spawn_file_actions_addopen(&actions, 0, "/dev/null", O_RDONLY, 0);
  for (const Redirect& redirect : lifted.redirects()) {
    posix_spawn_file_actions_adddup2(&actions, redirect.parent, redirect.child);
  }
  if (!command.working_directory.empty()) {
    posix_spawn_file_actions_addchdir_np(&actions, command.working_directory.c_str());
  }
  posix_spawnattr_t attributes;
  posix_spawnattr_init(&attributes);
  sigset_t none;
  sigemptyset(&none);
  sigset_t all;
  sigfillset(&all);
  posix_spawnattr_setsigmask(&attributes, &none);
  posix_spawnattr_setsigdefault(&attributes, &all);
  short flags = POSIX_SPAWN_SETSIGMASK | POSIX_SPAWN_SETSIGDEF;
  if (command.own_process_group) {
    flags |= POSIX_SPAWN_SETPGROUP;
    posix_spawnattr_setpgroup(&attributes, 0);
  }
  posix_spawnattr_setflags(&attributes, flags);
  // The personality is the calling thread's, is inherited by the child and
  // acts only at its exec: set around the spawn and restored (this
  // process's own layout was fixed at its own exec).
  int persona = -1;
  bool no_aslr = false;
  if (command.no_address_randomization) {
    persona = personality(0xffffffff);
    no_aslr = persona != -1 && personality(static_cast<unsigned long>(persona) | ADDR_NO_RANDOMIZE) != -1;
  }
  pid_t pid = -1;
  const int spawned = posix_spawn(&pid, command.argv[0].c_str(), &actions, &attributes, arrays.argv.data(),
                                  command.inherit_environment ? environ : arrays.env());
  if (no_aslr) personality(static_cast<unsigned long>(persona));
  posix_spawn_file_actions_destroy(&actions);
  posix_spawnattr_destroy(&attributes);
  if (spawned != 0) {
    child.start_error_ = spawned;
    return child;
  }
  child.pid_ = pid;
  child.own_group_ = command.own_process_group;
  child.pidfd_.Reset(static_cast<int>(syscall(SYS_pidfd_open, pid, 0)));
  return child;
}

Child Spawn(const Command& command, const Sandbox& sandbox) {
  Child child;
  if (command.argv.empty()) {
    child.start_error_ = EINVAL;
    return child;
  }
  const ExecArrays arrays(command);
  char* const* environment = command.inherit_environment ? environ : arrays.env();
  const LiftedRedirects lifted(command.descriptors);
  const std::vector<Redirect>& redirects = lifted.redirects();
  int report_pipe[2];
  if (pipe2(report_pipe, O_CLOEXEC) != 0) {
    child.start_error_ = errno;
    return child;
  }
  Fd report_read(report_pipe[0]);
  Fd report_write(report_pipe[1]);
  const Fd null_fd(open("/dev/null", O_RDONLY | O_CLOEXEC));
  const CallerIdMaps id_maps = CallerIdMaps::OfCaller();
  const bool stdin_named = lifted.names_stdin();
  const int keep_from = lifted.highest() + 1;
  const pid_t pid = fork();
  if (pid == 0) {
    // Async-signal-safe from here on (the caller may have threads).
    const int report_fd = report_write.get();
    setpgid(0, 0);
    prctl(PR_SET_PDEATHSIG, SIGKILL);
    ReportFrame report;
    auto fail = [&](SandboxFailure failure) {
      report.failure = static_cast<int>(failure);
      report.failure_errno = errno;
      (void)WriteAll(report_fd, &report, sizeof report);
      _exit(125);
    };
    if (sandbox.enter_user_namespace >= 0 && setns(sandbox.enter_user_namespace, CLONE_NEWUSER) != 0) {
      fail(SandboxFailure::kEnterNamespace);
    }
    if (sandbox.enter_mount_namespace >= 0 && setns(sandbox.enter_mount_namespace, CLONE_NEWNS) != 0) {
      fail(SandboxFailure::kEnterNamespace);
    }
    auto network_only = [&]() {
      report.isolation_errno = errno;
      report.isolation = static_cast<int>(unshare(CLONE_NEWNET) == 0 ? Isolation::kNetworkOnly : Isolation::kNone);
    };
    if (sandbox.drop_to_nobody) {
      // The namespaces while root may make them, then the uid.
      if (unshare(kNamespaces) == 0) {
        report.isolation = static_cast<int>(Isolation::kFull);
      } else {
        network_only();
      }
      if (const int refused = DropToNobody(); refused != 0) {
        errno = refused;
        fail(SandboxFailure::kUid);
      }
    } else if (unshare(CLONE_NEWUSER | kNamespaces) == 0) {
      report.isolation = static_cast<int>(Isolation::kFull);
      if (!MapCallerIds(id_maps)) report.isolation_errno = errno;
    } else {
      network_only();
    }
    for (const Limit& limit : sandbox.limits) SetLimit(limit.resource, limit.value);
    if (sandbox.files != nullptr && sandbox.files->created()) {
      if (const int refused = sandbox.files->RestrictSelf(); refused != 0) {
        errno = refused;
        fail(SandboxFailure::kLandlock);
      }
    } else {
      prctl(PR_SET_NO_NEW_PRIVS, 1, 0, 0, 0);
    }
    if (!sandbox.syscalls.empty()) {
      const sock_fprog program{static_cast<unsigned short>(sandbox.syscalls.size()),
                               const_cast<sock_filter*>(sandbox.syscalls.data())};
      if (prctl(PR_SET_SECCOMP, SECCOMP_MODE_FILTER, &program) != 0) fail(SandboxFailure::kFilter);
    }
    (void)WriteAll(report_fd, &report, sizeof report);
    auto exec_program = [&]() {
      if (!stdin_named && null_fd.valid()) dup2(null_fd.get(), 0);
      for (const Redirect& redirect : redirects) dup2(redirect.parent, redirect.child);
      // Nothing but the redirects reaches the program: not a file the
      // caller had open without close-on-exec, nor one another thread
      // opened in the moment of the fork.
      CloseDescriptorsFrom(keep_from);
      if (!command.working_directory.empty() && chdir(command.working_directory.c_str()) != 0) _exit(126);
      execve(arrays.argv[0], arrays.argv.data(), environment);
      if (!command.exec_failure_text.empty()) {
        (void)WriteAll(2, command.exec_failure_text.data(), command.exec_failure_text.size());
      }
      _exit(127);
    };
    if (report.isolation != static_cast<int>(Isolation::kFull)) exec_program();
    // The namespace's init (pid 1 inside), then the program under it.
    const pid_t init = fork();
    if (init < 0) _exit(125);
    if (init > 0) {
      int status = 0;
      while (waitpid(init, &status, 0) < 0 && errno == EINTR) {
      }
      _exit(WIFEXITED(status) ? WEXITSTATUS(status) : 125);
    }
    prctl(PR_SET_PDEATHSIG, SIGKILL);
    const pid_t program = fork();
    if (program < 0) _exit(125);
    if (program == 0) exec_program();
    // The init keeps only its report: it shares the program's uid and
    // Landlock domain, so what it held would be one ptrace away.
    CloseAllBut(report_fd, report_fd);
    for (;;) {
      int status = 0;
      const pid_t reaped = waitpid(-1, &status, 0);
      if (reaped == program) {
        (void)WriteAll(report_fd, &status, sizeof status);
        _exit(WIFEXITED(status) ? WEXITSTATUS(status) : 125);
      }
      if (reaped < 0 && errno != EINTR) _exit(125);
    }
  }
  report_write.Reset();
  if (pid < 0) {
    child.start_error_ = errno;
    return child;
  }
  child.pid_ = pid;
  child.own_group_ = true;
  setpgid(pid, pid);  // also from here: no moment where a kill of the group misses
  ReportFrame report;
  ssize_t got;
  do {
    got = read(report_read.get(), &report, sizeof report);
  } while (got < 0 && errno == EINTR);
  if (got == static_cast<ssize_t>(sizeof report)) {
    child.report_.isolation = static_cast<Isolation>(report.isolation);
    child.report_.isolation_errno = report.isolation_errno;
    child.report_.failure = static_cast<SandboxFailure>(report.failure);
    child.report_.failure_errno = report.failure_errno;
  }
  child.report_pipe_ = std::move(report_read);
  child.pidfd_.Reset(static_cast<int>(syscall(SYS_pidfd_open, pid, 0)));
  return child;
}

}  // namespace syrof::process
