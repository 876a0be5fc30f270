#include "syrof/process/spawn.h"

#include <fcntl.h>
#include <linux/seccomp.h>
#include <poll.h>
#include <sched.h>
#include <signal.h>
#include <spawn.h>
#include <sys/personality.h>
#include <sys/prctl.h>
#include <sys/resource.h>
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

// How a child that wait4 reaped ended, and its CPU time.
ExitStatus Ended(int wait_status, const rusage& usage) {
  ExitStatus status = ExitStatus::FromWaitStatus(wait_status);
  status.cpu_seconds = static_cast<double>(usage.ru_utime.tv_sec + usage.ru_stime.tv_sec) +
                       static_cast<double>(usage.ru_utime.tv_usec + usage.ru_stime.tv_usec) * 1e-6;
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

// Starts `command` by fork and exec, for the steps posix_spawn has no
// attribute for (die_with_parent, network_namespace), with every other step
// of Command as posix_spawn takes it. Returns the child's pid, or -1 and
// `error` the errno of the step that failed: as with posix_spawn, a child
// that could not exec tells so through a close-on-exec pipe and is reaped
// here.
pid_t ForkAndExec(const Command& command, const ExecArrays& arrays, const LiftedRedirects& lifted, int& error) {
  int error_pipe[2];
  if (pipe2(error_pipe, O_CLOEXEC) != 0) {
    error = errno;
    return -1;
  }
  const Fd error_read(error_pipe[0]);
  // Above every redirect's target, so that no dup2 replaces it.
  Fd error_write(fcntl(error_pipe[1], F_DUPFD_CLOEXEC, lifted.highest() + 1));
  close(error_pipe[1]);
  const Fd null_fd(lifted.names_stdin() ? -1 : open("/dev/null", O_RDONLY | O_CLOEXEC));
  if (!error_write.valid() || (!lifted.names_stdin() && !null_fd.valid())) {
    error = errno;
    return -1;
  }
  char* const* environment = command.inherit_environment ? environ : arrays.env();
  const pid_t parent = getpid();
  const pid_t pid = fork();
  if (pid == 0) {
    // Async-signal-safe from here on (the caller may have threads).
    auto fail = [&]() {
      const int failed = errno;
      (void)WriteAll(error_write.get(), &failed, sizeof failed);
      _exit(127);
    };
    if (command.own_process_group && setpgid(0, 0) != 0) fail();
    if (command.die_with_parent) {
      if (prctl(PR_SET_PDEATHSIG, SIGKILL) != 0) fail();
      if (getppid() != parent) _exit(127);  // gone before the signal was armed
    }
    struct sigaction default_action {};
    default_action.sa_handler = SIG_DFL;
    for (int number = 1; number < NSIG; ++number) (void)sigaction(number, &default_action, nullptr);
    sigset_t none;
    sigemptyset(&none);
    (void)sigprocmask(SIG_SETMASK, &none, nullptr);
    if (command.no_address_randomization) {
      const int persona = personality(0xffffffff);
      if (persona != -1) (void)personality(static_cast<unsigned long>(persona) | ADDR_NO_RANDOMIZE);
    }
    if (command.fifo_priority > 0) {
      sched_param parameters{};
      parameters.sched_priority = command.fifo_priority;
      if (sched_setscheduler(0, SCHED_FIFO, &parameters) != 0) fail();
    }
    if (command.network_namespace >= 0 && setns(command.network_namespace, CLONE_NEWNET) != 0) fail();
    if (null_fd.valid() && dup2(null_fd.get(), 0) < 0) fail();
    for (const Redirect& redirect : lifted.redirects()) {
      // The same number on both sides (it could not be lifted): passed on
      // as it is.
      const bool passed = redirect.parent == redirect.child ? fcntl(redirect.child, F_SETFD, 0) == 0
                                                            : dup2(redirect.parent, redirect.child) >= 0;
      if (!passed) fail();
    }
    if (!command.working_directory.empty() && chdir(command.working_directory.c_str()) != 0) fail();
    if (command.search_path) {
      execvpe(arrays.argv[0], arrays.argv.data(), environment);
    } else {
      execve(arrays.argv[0], arrays.argv.data(), environment);
    }
    fail();
  }
  const int fork_error = errno;
  error_write.Reset();
  if (pid < 0) {
    error = fork_error;
    return -1;
  }
  if (command.own_process_group) setpgid(pid, pid);  // also from here: no moment where a kill of the group misses
  int failed = 0;
  ssize_t got;
  do {
    got = read(error_read.get(), &failed, sizeof failed);
  } while (got < 0 && errno == EINTR);
  if (got != static_cast<ssize_t>(sizeof failed)) return pid;  // exec closed the pipe
  while (waitpid(pid, nullptr, 0) < 0 && errno == EINTR) {
  }
  error = failed;
  return -1;
}

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
    status_.cpu_seconds = status.cpu_seconds;  // the init's, which waited for the program
  }
  report_pipe_.Reset();
}

std::optional<ExitStatus> Child::Wait(std::chrono::milliseconds timeout) {
  if (!started()) return ExitStatus{};
  if (reaped_) return status_;
  const auto deadline = std::chrono::steady_clock::now() + timeout;
  for (;;) {
    int wait_status = 0;
    rusage usage{};
    const pid_t waited = wait4(pid_, &wait_status, WNOHANG, &usage);
    if (waited < 0) {
      if (errno == EINTR) continue;
      Finish(ExitStatus{});  // not ours to wait for any more
      return status_;
    }
    if (waited == pid_) {
      Finish(Ended(wait_status, usage));
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
  int wait_status = 0;
  rusage usage{};
  pid_t waited;
  do {
    waited = wait4(pid_, &wait_status, 0, &usage);
  } while (waited < 0 && errno == EINTR);
  Finish(waited == pid_ ? Ended(wait_status, usage) : ExitStatus{});
  return status_;
}

void Child::Kill() { Signal(SIGKILL); }

void Child::Signal(int signal) {
  if (started() && !reaped_) kill(pid_, signal);
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
  if (command.die_with_parent || command.network_namespace >= 0) {
    const pid_t pid = ForkAndExec(command, arrays, lifted, child.start_error_);
    if (pid < 0) return child;
    child.pid_ = pid;
    child.own_group_ = command.own_process_group;
    child.pidfd_.Reset(static_cast<int>(syscall(SYS_pidfd_open, pid, 0)));
    return child;
  }
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
  if (command.fifo_priority > 0) {
    flags |= POSIX_SPAWN_SETSCHEDULER;
    posix_spawnattr_setschedpolicy(&attributes, SCHED_FIFO);
    sched_param parameters{};
    parameters.sched_priority = command.fifo_priority;
    posix_spawnattr_setschedparam(&attributes, &parameters);
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
  const auto start = command.search_path ? posix_spawnp : posix_spawn;
  const int spawned = start(&pid, command.argv[0].c_str(), &actions, &attributes, arrays.argv.data(),
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

Child ForkHelper(const std::function<int()>& body) {
  Child child;
  const pid_t parent = getpid();
  const pid_t pid = fork();
  if (pid == 0) {
    // Async-signal-safe from here on: what `body` promises.
    prctl(PR_SET_PDEATHSIG, SIGKILL);
    if (getppid() != parent) _exit(1);  // gone before the signal was armed
    _exit(body());
  }
  if (pid < 0) {
    child.start_error_ = errno;
    return child;
  }
  child.pid_ = pid;
  child.pidfd_.Reset(static_cast<int>(syscall(SYS_pidfd_open, pid, 0)));
  return child;
}

Child Adopt(pid_t pid) {
  Child child;
  siginfo_t info{};
  // WNOWAIT: only looks; a pid that is not our child (or already reaped)
  // gives ECHILD.
  if (pid <= 0 || waitid(P_PID, static_cast<id_t>(pid), &info, WEXITED | WNOHANG | WNOWAIT) != 0) {
    child.start_error_ = pid <= 0 ? EINVAL : errno;
    return child;
  }
  child.pid_ = pid;
  child.pidfd_.Reset(static_cast<int>(syscall(SYS_pidfd_open, pid, 0)));
  return child;
}

}  // namespace syrof::process
