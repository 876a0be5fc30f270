// Starting a child process, waiting for it (with a timeout), killing it or
// its process group, and reaping it: the one place SyROF starts programs.
// Each user declares only what to start (a Command) and, for untrusted
// code, how to confine it (a Sandbox).
//
//   process::Command command;
//   command.argv = {"/usr/bin/cmake", "--build", dir};
//   command.descriptors = {{1, output.get()}, {2, output.get()}};
//   process::Child child = process::Spawn(command);
//   if (!child.started()) ...                    // child.start_error(): an errno
//   if (auto status = child.Wait(std::chrono::seconds(5))) ... else child.KillGroup();
//   const process::ExitStatus status = child.Reap();
//
// A Child that goes while its process runs kills it (its group when it has
// its own) and reaps it: no process outlives its owner unwaited.
#pragma once

#include <linux/filter.h>
#include <sys/resource.h>
#include <sys/types.h>

#include <chrono>
#include <functional>
#include <optional>
#include <string>
#include <vector>

#include "syrof/process/fd.h"

namespace syrof::process {

class FileRuleset;

/// How a child ended.
struct ExitStatus {
  enum class How {
    kExited,    ///< it called exit: `code`
    kSignaled,  ///< a signal ended it: `signal`
    kUnknown,   ///< it could not be waited for (reaped by someone else)
  };
  How how = How::kUnknown;
  int code = -1;
  int signal = 0;
  /// User and system CPU time of the child (and of the children it waited
  /// for), in seconds; 0 when unknown.
  double cpu_seconds = 0;

  bool exited() const { return how == How::kExited; }
  bool signaled() const { return how == How::kSignaled; }
  /// From a wait status (waitpid's `status`).
  static ExitStatus FromWaitStatus(int status);
};

/// One descriptor the child gets: the caller's `parent` becomes `child`
/// there. Descriptors not named are not passed on (SyROF opens every
/// descriptor close-on-exec; a sandboxed child closes the rest as well).
struct Redirect {
  int child = -1;
  int parent = -1;
};

/// What to start.
struct Command {
  /// argv[0] is the program's path (no PATH search unless `search_path`).
  std::vector<std::string> argv;
  /// An argv[0] without a slash is looked for in PATH, as a shell does.
  bool search_path = false;
  /// Exactly this environment, unless `inherit_environment`.
  std::vector<std::string> environment;
  bool inherit_environment = false;
  /// Standard input is /dev/null unless a Redirect names descriptor 0.
  std::vector<Redirect> descriptors;
  /// Empty: the caller's.
  std::string working_directory;
  /// The child leads a process group of its own (KillGroup then reaches
  /// whatever it starts and leaves in the group). Always so in a Sandbox.
  bool own_process_group = false;
  /// Address randomisation off for the program (its addresses the same on
  /// every run).
  bool no_address_randomization = false;
  /// > 0: the program runs under SCHED_FIFO at this priority (a real-time
  /// caller's children one step below it); 0: the caller's policy.
  int fifo_priority = 0;
  /// SIGKILL to the child when the thread that started it ends (a caller
  /// killed outright takes its children along), armed before exec; a child
  /// whose caller is already gone does not run the program.
  bool die_with_parent = false;
  /// A network namespace the child enters before exec (an open
  /// /proc/PID/ns/net or a bind mount of one); -1: the caller's.
  /// `die_with_parent` and this are steps posix_spawn has no attribute for:
  /// such a command is started by fork and exec, its failures reported the
  /// same way (start_error).
  int network_namespace = -1;
  /// Written to the child's standard error when the program cannot be
  /// executed (the exit status is then 127); empty: nothing.
  std::string exec_failure_text;
};

/// One resource limit (soft and hard) for a sandboxed child.
struct Limit {
  int resource = RLIMIT_CORE;
  rlim_t value = 0;
};

/// How a sandboxed child is confined, applied in this order between fork
/// and exec (docs/grading.md, "Threat model"):
///  1. its own process group; killed when the caller dies;
///  2. the namespaces `enter_*` (a holder's, e.g. a size-limited folder);
///  3. new network, PID, IPC and UTS namespaces: as root first, then uid
///     65534 (`drop_to_nobody`; never root inside or outside a namespace);
///     otherwise inside a new user namespace mapping the caller's own ids;
///     where refused, the network namespace alone, else none (reported);
///  4. `limits`;
///  5. no_new_privs and the Landlock ruleset `files` (no_new_privs alone
///     when null);
///  6. the seccomp program `syscalls` (none when empty);
///  7. every descriptor but the Redirects closed, then exec.
/// With a PID namespace the child is a small init that starts the program
/// and reaps; when it ends the kernel kills whatever is left in the
/// namespace, so nothing the program started outlives it.
struct Sandbox {
  int enter_user_namespace = -1;
  int enter_mount_namespace = -1;
  bool drop_to_nobody = false;  // only when started as root
  std::vector<Limit> limits;
  const FileRuleset* files = nullptr;
  std::vector<sock_filter> syscalls;
};

/// What a sandboxed child could set up, as it reported before exec.
enum class Isolation {
  kFull,         ///< network cut, processes in their own PID namespace
  kNetworkOnly,  ///< network cut only
  kNone,         ///< namespaces refused
};
/// A layer that must hold and did not: the program was not started.
enum class SandboxFailure { kNone, kUid, kLandlock, kFilter, kEnterNamespace };
struct SandboxReport {
  Isolation isolation = Isolation::kNone;
  int isolation_errno = 0;
  SandboxFailure failure = SandboxFailure::kNone;
  int failure_errno = 0;
};

/// A started child process (or a failed start).
class Child {
 public:
  Child() = default;
  /// Kills the child (its group when it has its own) if it still runs, and
  /// reaps it.
  ~Child();
  Child(Child&& other) noexcept;
  Child& operator=(Child&& other) noexcept;
  Child(const Child&) = delete;
  Child& operator=(const Child&) = delete;

  bool started() const { return pid_ > 0; }
  /// Why it did not start (an errno; 0 when it did).
  int start_error() const { return start_error_; }
  pid_t pid() const { return pid_; }
  /// Readable once the child has ended (-1 on kernels without pidfd_open):
  /// poll it together with the child's pipes.
  int pidfd() const { return pidfd_.get(); }
  /// A sandboxed child's report (kNone/kNone for a plain one).
  const SandboxReport& sandbox() const { return report_; }

  /// Waits at most `timeout` for the child to end: its status then (it is
  /// reaped), nullopt while it still runs. A zero timeout only looks.
  std::optional<ExitStatus> Wait(std::chrono::milliseconds timeout);
  /// Waits for the end however long it takes (no signal sent); the status.
  /// In a Sandbox with a PID namespace, the program's own status as its
  /// init reported it (else the child's). The same status on every call.
  ExitStatus Reap();
  /// SIGKILL to the child alone.
  void Kill();
  /// `signal` to the child alone (SIGSTOP, SIGCONT, ...); nothing once it
  /// is reaped, when its pid may be another process's.
  void Signal(int signal);
  /// SIGKILL to the child's process group (the child alone without one).
  /// With a group, also after Reap: what the child left in it goes too.
  void KillGroup();
  bool reaped() const { return reaped_; }

 private:
  friend Child Spawn(const Command& command);
  friend Child Spawn(const Command& command, const Sandbox& sandbox);
  friend Child ForkHelper(const std::function<int()>& body);
  friend Child Adopt(pid_t pid);
  void Finish(ExitStatus status);

  pid_t pid_ = -1;
  int start_error_ = 0;
  bool own_group_ = false;
  bool reaped_ = false;
  ExitStatus status_;
  Fd pidfd_;
  Fd report_pipe_;  // a sandboxed child's: its init reports the program's status
  SandboxReport report_;
};

/// Starts `command` (posix_spawn; fork and exec for the steps it lacks):
/// signals unblocked and at their defaults in the child. A program that
/// cannot be executed is a failed start (start_error: ENOENT, EACCES,
/// ENOEXEC...), not a child exiting 127.
Child Spawn(const Command& command);

/// Starts `command` confined by `sandbox` (fork, the steps of Sandbox,
/// exec). The report is read before this returns; a SandboxFailure means
/// the program never ran.
Child Spawn(const Command& command, const Sandbox& sandbox);

/// Starts a copy of the caller that runs `body` and exits with its return
/// value: a helper that must act on its caller from outside, such as
/// stopping and continuing it (no thread of a stopped process runs). `body`
/// runs in a copy of a process that may have threads: async-signal-safe
/// calls only, no allocation. The helper dies with the thread that started
/// it, and does not run `body` when the caller is already gone.
Child ForkHelper(const std::function<int()>& body);

/// A child of this process that another process started for it: a copy a
/// child of ours made with clone(CLONE_PARENT) (the app host's held
/// process, docs/app_host.md "The fork server"). From here on it is held
/// as a Child Spawn returned: waited for, killed and reaped here. `pid`
/// must be a child of this process not yet reaped (else it is not started).
Child Adopt(pid_t pid);

}  // namespace syrof::process
