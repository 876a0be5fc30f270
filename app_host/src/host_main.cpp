// syrof-app-host: runs one robot's app library in a hardened process
// (docs/app_host.md). Started by HostedApp (host_process.cpp) with
//   syrof-app-host run|check LIBRARY PARENT_PID ADDRESS_SPACE_BYTES
// and descriptors 0 /dev/null, 1 and 2 the output pipe, 3 the channel
// (protocol.h). It hardens itself, loads the library, sends a hello frame,
// then answers one request per callback until the channel closes. `check`
// stops after the hello (CheckLibrary).
//
// Whatever the app does wrong ends this process; what the host can name it
// names first in a fault frame (a forbidden system call, a refused
// allocation, a library that does not load); the parent reads signals and
// exits from the process itself.
#include <dirent.h>
#include <dlfcn.h>
#include <fcntl.h>
#include <linux/capability.h>
#include <sched.h>
#include <seccomp.h>
#include <signal.h>
#include <sys/ioctl.h>
#include <sys/personality.h>
#include <sys/prctl.h>
#include <sys/resource.h>
#include <sys/socket.h>
#include <sys/stat.h>
#include <sys/syscall.h>
#include <termios.h>
#include <unistd.h>

#include <algorithm>
#include <cerrno>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <string_view>

#include <string>

#include "allocation_guard.h"
#include "platform_binding.h"
#include "protocol.h"
#include "syrof/app/call_status.h"
#include "syrof/process/confine.h"
#include "syrof/process/fd.h"
#include "syrof/process/landlock.h"

namespace syrof::app_host {
namespace {

namespace p = protocol;
using app::Verdict;

constexpr int kMaxSyscall = 512;

// Names of system calls by number, resolved before any filter is loaded so
// the SIGSYS handler only indexes an array.
const char* syscall_names[kMaxSyscall];

uint32_t current_sequence = 0;
p::Reply reply;        // the reply being built for the current call
p::Reply fault_reply;  // written by the fault paths only

// Copies `text` into `out` (size bytes, NUL-terminated); signal-safe.
void CopyText(char* out, size_t size, const char* text) {
  size_t i = 0;
  for (; text != nullptr && text[i] != '\0' && i + 1 < size; ++i) out[i] = text[i];
  out[i] = '\0';
}

// Appends the decimal `value` to the NUL-terminated `out`; signal-safe.
void AppendNumber(char* out, size_t size, uint64_t value) {
  char digits[24];
  size_t count = 0;
  do {
    digits[count++] = static_cast<char>('0' + value % 10);
    value /= 10;
  } while (value != 0);
  size_t length = strlen(out);
  while (count > 0 && length + 1 < size) out[length++] = digits[--count];
  out[length] = '\0';
}

// Sends one frame on the channel; the parent gone, the host ends.
// Signal-safe.
void Send(const p::Reply& frame) {
  if (!process::WriteAll(p::kChannelFd, &frame, sizeof(frame))) _exit(p::kExitParentGone);
}

// Reports a fault and ends the process; signal-safe.
[[noreturn]] void ReportFault(Verdict verdict, const char* detail) {
  fault_reply = p::Reply{};
  fault_reply.sequence = current_sequence;
  fault_reply.kind = static_cast<uint8_t>(p::ReplyKind::kFault);
  fault_reply.verdict = static_cast<uint8_t>(verdict);
  CopyText(fault_reply.text, sizeof(fault_reply.text), detail);
  Send(fault_reply);
  _exit(p::kExitFaultReported);
}

void OnSigsys(int, siginfo_t* info, void*) {
  char detail[p::kTextBytes];
  const int number = info->si_syscall;
  if (number >= 0 && number < kMaxSyscall && syscall_names[number] != nullptr) {
    CopyText(detail, sizeof(detail), syscall_names[number]);
  } else {
    CopyText(detail, sizeof(detail), "syscall ");
    AppendNumber(detail, sizeof(detail), static_cast<uint64_t>(number < 0 ? 0 : number));
  }
  ReportFault(Verdict::kForbiddenSyscall, detail);
}

void OnAllocationRefused(size_t size) {
  char detail[p::kTextBytes];
  CopyText(detail, sizeof(detail), "allocation of ");
  AppendNumber(detail, sizeof(detail), size);
  const size_t length = strlen(detail);
  CopyText(detail + length, sizeof(detail) - length, " bytes refused");
  ReportFault(Verdict::kMemory, detail);
}

[[noreturn]] void Fail(Verdict verdict, const char* what, const char* why) {
  char detail[p::kTextBytes];
  CopyText(detail, sizeof(detail), what);
  if (why != nullptr) {
    const size_t length = strlen(detail);
    CopyText(detail + length, sizeof(detail) - length, why);
  }
  ReportFault(verdict, detail);
}

// One argument comparison (libseccomp's SCMP_A* macros are C compound
// literals, which C++ compilers warn about).
scmp_arg_cmp Arg(unsigned int index, scmp_compare op, scmp_datum_t a, scmp_datum_t b = 0) {
  scmp_arg_cmp comparison{};
  comparison.arg = index;
  comparison.op = op;
  comparison.datum_a = a;
  comparison.datum_b = b;
  return comparison;
}

// The rules both filters share: what a callback may do. Everything else
// traps (SIGSYS, reported by name).
// `any_target`: a held host's loader filter, whose copies (other pids)
// inherit it: signals to any process, which Landlock's signal scope (ABI 6)
// keeps to the held host's own domain (docs/app_host.md "The fork server").
bool AddCallbackRules(scmp_filter_ctx filter, pid_t self_pid, bool any_target = false) {
  const auto self = static_cast<scmp_datum_t>(self_pid);
  const int allowed[] = {
      SCMP_SYS(read),          SCMP_SYS(write),         SCMP_SYS(readv),           SCMP_SYS(writev),
      SCMP_SYS(close),         SCMP_SYS(fstat),         SCMP_SYS(lseek),           SCMP_SYS(brk),
      SCMP_SYS(mmap),          SCMP_SYS(munmap),        SCMP_SYS(mremap),          SCMP_SYS(mprotect),
      SCMP_SYS(madvise),       SCMP_SYS(futex),         SCMP_SYS(clock_gettime),   SCMP_SYS(clock_getres),
      SCMP_SYS(gettimeofday),  SCMP_SYS(time),          SCMP_SYS(nanosleep),       SCMP_SYS(clock_nanosleep),
      SCMP_SYS(sched_yield),   SCMP_SYS(getpid),        SCMP_SYS(gettid),          SCMP_SYS(getppid),
      SCMP_SYS(getuid),        SCMP_SYS(geteuid),       SCMP_SYS(getgid),          SCMP_SYS(getegid),
      SCMP_SYS(getrandom),     SCMP_SYS(uname),         SCMP_SYS(rt_sigprocmask),  SCMP_SYS(rt_sigreturn),
      SCMP_SYS(sigaltstack),   SCMP_SYS(exit),          SCMP_SYS(exit_group),      SCMP_SYS(fcntl),
      SCMP_SYS(getrlimit),     SCMP_SYS(restart_syscall),
  };
  for (const int number : allowed) {
    if (seccomp_rule_add(filter, SCMP_ACT_ALLOW, number, 0) != 0) return false;
  }
#if defined(SYROF_APP_HOST_SANITIZED)
  // The sanitizers' runtime checks whether memory is readable by writing it
  // to a pipe of its own (sanitizer_common's IsAccessibleMemoryRange).
  for (const int number : {SCMP_SYS(pipe), SCMP_SYS(pipe2)}) {
    if (seccomp_rule_add(filter, SCMP_ACT_ALLOW, number, 0) != 0) return false;
  }
#endif
  // Signals: only to itself (abort, raise); never to another process.
  if (any_target) {
    for (const int number : {SCMP_SYS(kill), SCMP_SYS(tgkill), SCMP_SYS(tkill)}) {
      if (seccomp_rule_add(filter, SCMP_ACT_ALLOW, number, 0) != 0) return false;
    }
  } else if (seccomp_rule_add(filter, SCMP_ACT_ALLOW, SCMP_SYS(kill), 1, Arg(0, SCMP_CMP_EQ, self)) != 0) {
    return false;
  }
  if (!any_target) {
    if (seccomp_rule_add(filter, SCMP_ACT_ALLOW, SCMP_SYS(tgkill), 1, Arg(0, SCMP_CMP_EQ, self)) != 0) return false;
    if (seccomp_rule_add(filter, SCMP_ACT_ALLOW, SCMP_SYS(tkill), 1, Arg(0, SCMP_CMP_EQ, self)) != 0) return false;
  }
  // Any handler but SIGSYS's, which reports forbidden calls.
  if (seccomp_rule_add(filter, SCMP_ACT_ALLOW, SCMP_SYS(rt_sigaction), 1, Arg(0, SCMP_CMP_NE, SIGSYS)) != 0) {
    return false;
  }
  // isatty(): stdio asks it.
  if (seccomp_rule_add(filter, SCMP_ACT_ALLOW, SCMP_SYS(ioctl), 1, Arg(1, SCMP_CMP_EQ, TCGETS)) != 0) return false;
  // Reading limits is fine; setting them is not.
  if (seccomp_rule_add(filter, SCMP_ACT_ALLOW, SCMP_SYS(prlimit64), 2, Arg(0, SCMP_CMP_EQ, 0),
                       Arg(2, SCMP_CMP_EQ, 0)) != 0) {
    return false;
  }
  return true;
}

// Stage 1, for the dynamic loader and the library's constructors: the
// callback rules plus opening files read-only, the stat family, and what
// loading stage 2 needs (seccomp; prctl for no_new_privs only). A held
// host (`hold`) also needs what making a copy takes: recvmsg (the copy's
// descriptors), the one clone of protocol::kCopyCloneFlags, the copy's
// parent-death SIGKILL and sigpending (the check of what the constructors
// left). docs/app_host.md, "The fork server", says why a constructor gains
// nothing from them.
scmp_filter_ctx LoaderFilter(pid_t self, bool hold) {
  scmp_filter_ctx filter = seccomp_init(SCMP_ACT_TRAP);
  if (filter == nullptr) return nullptr;
  bool ok = seccomp_attr_set(filter, SCMP_FLTATR_CTL_NNP, 0) == 0 && AddCallbackRules(filter, self, hold);
  const scmp_datum_t write_flags = O_ACCMODE | O_CREAT | O_TRUNC | __O_TMPFILE;
  ok = ok && seccomp_rule_add(filter, SCMP_ACT_ALLOW, SCMP_SYS(openat), 1,
                              Arg(2, SCMP_CMP_MASKED_EQ, write_flags, 0)) == 0;
  ok = ok && seccomp_rule_add(filter, SCMP_ACT_ALLOW, SCMP_SYS(open), 1,
                              Arg(1, SCMP_CMP_MASKED_EQ, write_flags, 0)) == 0;
  const int allowed[] = {SCMP_SYS(newfstatat), SCMP_SYS(stat),      SCMP_SYS(lstat),      SCMP_SYS(statx),
                         SCMP_SYS(access),     SCMP_SYS(faccessat), SCMP_SYS(faccessat2), SCMP_SYS(readlink),
                         SCMP_SYS(readlinkat), SCMP_SYS(getcwd),    SCMP_SYS(pread64),    SCMP_SYS(seccomp)};
  for (const int number : allowed) ok = ok && seccomp_rule_add(filter, SCMP_ACT_ALLOW, number, 0) == 0;
  // prctl only as libseccomp may use it to load stage 2: a constructor may
  // not undo the parent-death signal or the dumpable flag.
  ok = ok && seccomp_rule_add(filter, SCMP_ACT_ALLOW, SCMP_SYS(prctl), 1,
                              Arg(0, SCMP_CMP_EQ, PR_SET_NO_NEW_PRIVS)) == 0;
  if (hold) {
    ok = ok && seccomp_rule_add(filter, SCMP_ACT_ALLOW, SCMP_SYS(clone), 1,
                                Arg(0, SCMP_CMP_EQ, p::kCopyCloneFlags)) == 0;
    ok = ok && seccomp_rule_add(filter, SCMP_ACT_ALLOW, SCMP_SYS(prctl), 2, Arg(0, SCMP_CMP_EQ, PR_SET_PDEATHSIG),
                                Arg(1, SCMP_CMP_EQ, SIGKILL)) == 0;
    ok = ok && seccomp_rule_add(filter, SCMP_ACT_ALLOW, SCMP_SYS(recvmsg), 0) == 0;
    ok = ok && seccomp_rule_add(filter, SCMP_ACT_ALLOW, SCMP_SYS(rt_sigpending), 0) == 0;
  }
  if (!ok) {
    seccomp_release(filter);
    return nullptr;
  }
  return filter;
}

// Stage 2, for the callbacks: nothing that opens, creates, connects, forks,
// executes, signals another process or traces.
scmp_filter_ctx CallbackFilter(pid_t self) {
  scmp_filter_ctx filter = seccomp_init(SCMP_ACT_TRAP);
  if (filter == nullptr) return nullptr;
  if (seccomp_attr_set(filter, SCMP_FLTATR_CTL_NNP, 0) != 0 || !AddCallbackRules(filter, self)) {
    seccomp_release(filter);
    return nullptr;
  }
  return filter;
}

// The payload sink of the platform binding: records each call for the reply
// (flushing a full batch), and answers as the robot does.
int RecordPayload(void*, const uint8_t* payload, size_t length) {
  if (reply.call_count == p::kCallsPerReply) {
    reply.kind = static_cast<uint8_t>(p::ReplyKind::kBatch);
    Send(reply);
    reply.call_count = 0;
    for (p::PayloadCall& call : reply.calls) call = p::PayloadCall{};
  }
  p::PayloadCall& call = reply.calls[reply.call_count++];
  ++reply.calls_total;
  call.length = length > UINT32_MAX ? UINT32_MAX : static_cast<uint32_t>(length);
  if (length > SYROF_APP_MAX_PAYLOAD_BYTES) return SYROF_APP_PAYLOAD_TOO_LONG;
  if (length > 0) memcpy(call.bytes, payload, length);
  return SYROF_APP_OK;
}

// The scenario's parameters and this robot's private inputs, from the init
// request: the app's syrofAppParameter and syrofAppInput are answered here,
// in the host, without a round trip.
struct NamedValues {
  p::ParameterEntry entries[p::kMaxParameters];
  size_t count = 0;
};
NamedValues parameters;
NamedValues inputs;

int LookUp(const NamedValues& table, const char* name, size_t length, double* value, int missing) {
  const std::string_view wanted(name, length);
  for (size_t i = 0; i < table.count; ++i) {
    if (wanted == table.entries[i].name) {
      *value = table.entries[i].value;
      return SYROF_APP_OK;
    }
  }
  return missing;
}
int LookUpParameter(void*, const char* name, size_t length, double* value) {
  return LookUp(parameters, name, length, value, SYROF_APP_NO_SUCH_PARAMETER);
}
int LookUpInput(void*, const char* name, size_t length, double* value) {
  return LookUp(inputs, name, length, value, SYROF_APP_NO_SUCH_INPUT);
}

// Takes `count` entries from `data` into `table` (at most `most`); false
// for a malformed list: too many, or a name that is empty or fills its
// field without a NUL.
bool ReadNamedValues(const unsigned char* data, size_t count, size_t most, NamedValues& table) {
  if (count > most) return false;
  for (size_t i = 0; i < count; ++i) {
    memcpy(&table.entries[i], data + i * sizeof(p::ParameterEntry), sizeof(p::ParameterEntry));
    const size_t length = strnlen(table.entries[i].name, sizeof(table.entries[i].name));
    if (length == 0 || length == sizeof(table.entries[i].name)) return false;
  }
  table.count = count;
  return true;
}

// Takes the parameters, then the inputs, that follow an init request's
// header (`bytes` of them, the counts announced); false for a wrong size
// or a malformed list.
bool ReadInitTables(const unsigned char* data, size_t bytes, size_t parameter_count, size_t input_count) {
  if (bytes != (parameter_count + input_count) * sizeof(p::ParameterEntry)) return false;
  return ReadNamedValues(data, parameter_count, p::kMaxParameters, parameters) &&
         ReadNamedValues(data + parameter_count * sizeof(p::ParameterEntry), input_count, p::kMaxInputs, inputs);
}

alignas(8) unsigned char request_buffer[p::kMaxRequestBytes];

std::string FolderOf(const std::string& path) {
  const size_t slash = path.rfind('/');
  if (slash == std::string::npos) return ".";
  return slash == 0 ? "/" : path.substr(0, slash);
}

// A shared object's file name: NAME.so, NAME.so.1, NAME.so.1.2.
bool IsSharedObjectName(const char* name) {
  for (const char* so = strstr(name, ".so"); so != nullptr; so = strstr(so + 1, ".so")) {
    if (so != name && (so[3] == '\0' || so[3] == '.')) return true;
  }
  return false;
}

// Allows reading and executing each shared object directly beside
// `library` (a library of the student's own that it links), each file by
// its own rule: no folder, so nothing else beside it and nothing beneath
// it. Symbolic links are left out (their targets beside it have rules of
// their own).
bool AllowSharedObjectsBeside(syrof::process::FileRuleset& rules, const char* library) {
  const std::string folder = FolderOf(library);
  DIR* listing = opendir(folder.c_str());
  if (listing == nullptr) return true;  // nothing beside it can be allowed
  bool ok = true;
  while (const dirent* entry = readdir(listing)) {
    if (!IsSharedObjectName(entry->d_name)) continue;
    ok = ok && rules.AllowPlainFile(folder + "/" + entry->d_name, syrof::process::FileRuleset::Access::kReadExecute);
  }
  closedir(listing);
  return ok;
}

// What the dynamic loader and the library's constructors may read: the
// library's file and the shared objects directly beside it (file rules,
// not the folder: a library run from the top of a course folder reads
// nothing of the course), libsyrof_app's folder, and the system's library
// folders with the loader's cache. Nothing may be written, nor any other
// file read (docs/app_host.md, "What a library may touch"). Built while the
// host is still the caller's uid (it may have to reach a folder only the
// caller reads); applied after the uid drop. False when a rule is refused
// (`rules.error()` says which); `rules.created()` false when Landlock is
// missing.
bool LoaderFileRules(syrof::process::FileRuleset& rules, const char* library) {
  using Access = syrof::process::FileRuleset::Access;
  if (!rules.Create()) return true;
  std::string own_library;
  Dl_info info{};
  if (dladdr(reinterpret_cast<void*>(&syrof_internal_host_bind), &info) != 0 && info.dli_fname != nullptr) {
    own_library = info.dli_fname;
  }
  bool ok = rules.Allow(library, Access::kReadExecute) && AllowSharedObjectsBeside(rules, library);
  if (!own_library.empty()) ok = ok && rules.Allow(FolderOf(own_library), Access::kReadExecute);
  for (const char* system : {"/lib", "/lib32", "/lib64", "/libx32", "/usr/lib", "/usr/lib32", "/usr/lib64",
                             "/usr/libx32", "/usr/local/lib", "/etc/ld.so.cache"}) {
    ok = ok && rules.Allow(system, Access::kReadExecute);
  }
  return ok;
}

// What a held host checks before it offers copies: the descriptors it was
// given (0-3) as they were before the library loaded, and /proc/self/maps,
// opened while it could be.
struct HoldState {
  struct stat standard[p::kChannelFd + 1];
  int maps_fd = -1;
  int pagemap_fd = -1;  // /proc/self/pagemap, for the pages a copy takes over at once
  sigset_t load_mask;  // the signal mask the constructors left (the copies get it back)
  pid_t parent = 0;
  scmp_filter_ctx callbacks = nullptr;  // built before the load, as a run host does
  p::Reply hello;
};
HoldState hold;

void RecordStandardDescriptors() {
  for (int fd = 0; fd <= p::kChannelFd; ++fd) {
    if (fstat(fd, &hold.standard[fd]) != 0) hold.standard[fd] = {};
  }
}

// Whether /proc/self/maps lists a mapping shared with another process
// (MAP_SHARED: the fourth permission letter is 's'). Reads with the
// descriptor opened before Landlock; false when it cannot read.
bool HasSharedMapping(bool& checked) {
  static char text[1 << 16];
  checked = false;
  if (hold.maps_fd < 0 || lseek(hold.maps_fd, 0, SEEK_SET) != 0) return false;
  bool at_line_start = true;
  int field = 0;     // 0: the address range, 1: the permissions
  int position = 0;  // within the permissions
  for (;;) {
    const ssize_t got = read(hold.maps_fd, text, sizeof(text));
    if (got < 0 && errno == EINTR) continue;
    if (got < 0) return false;
    if (got == 0) break;
    for (ssize_t i = 0; i < got; ++i) {
      const char c = text[i];
      if (c == '\n') {
        at_line_start = true;
        continue;
      }
      if (at_line_start) {
        at_line_start = false;
        field = 0;
        position = 0;
      }
      if (c == ' ') {
        ++field;
        continue;
      }
      if (field == 1 && position++ == 3 && c == 's') {
        checked = true;
        return true;
      }
    }
  }
  checked = true;
  return false;
}

// What the constructors left that a fork would not copy as a fresh host
// has it: protocol::HoldBits, 0 when every copy starts as a fresh host.
// Threads and timers need no check: the loader's filter refuses clone3,
// clone (but the copy's), setitimer, alarm and timer_create, and a fork
// copies neither.
uint32_t WhatCopiesWouldShare() {
  uint32_t bits = 0;
  bool checked = false;
  if (HasSharedMapping(checked)) bits |= p::kHoldSharedMapping;
  if (!checked) bits |= p::kHoldUnchecked;
  if (hold.maps_fd >= 0) close(hold.maps_fd);
  hold.maps_fd = -1;
  for (int fd = 0; fd <= p::kChannelFd; ++fd) {
    struct stat now {};
    if (fstat(fd, &now) != 0 || now.st_dev != hold.standard[fd].st_dev || now.st_ino != hold.standard[fd].st_ino) {
      bits |= p::kHoldStandardDescriptors;
    }
  }
  rlimit files{};
  const int last = getrlimit(RLIMIT_NOFILE, &files) == 0 && files.rlim_cur < 4096 ? static_cast<int>(files.rlim_cur) : 4096;
  for (int fd = p::kChannelFd + 1; fd < last; ++fd) {
    if (fcntl(fd, F_GETFD) >= 0) bits |= p::kHoldOpenDescriptor;
  }
  sigset_t pending;
  sigemptyset(&pending);
  if (sigpending(&pending) != 0 || !sigisemptyset(&pending)) bits |= p::kHoldPendingSignal;
  return bits;
}

// The held host's writable private pages that are in memory when it starts
// holding, as runs of whole pages. A copy shares them copy-on-write, so its
// first write to each would take a page fault in the callback that writes
// first. The budget counts user time, but tick-based accounting splits a
// process's run time by where its ticks land, and a loop of faulting writes
// is caught in user mode often (docs/app_host.md): a copy's first callback
// would pay what a fresh host pays while it loads. Each copy writes them in
// before its hello instead (BecomeCopy). At most kMaxPresentRuns runs (the
// rest fault in the callbacks, as before).
struct PageRun {
  uintptr_t start;
  size_t length;
};
constexpr size_t kMaxPresentRuns = 4096;
PageRun present_runs[kMaxPresentRuns];
size_t present_run_count = 0;

void AddPresentPage(uintptr_t page, size_t page_size) {
  if (present_run_count > 0) {
    PageRun& last = present_runs[present_run_count - 1];
    if (last.start + last.length == page) {
      last.length += page_size;
      return;
    }
  }
  if (present_run_count < kMaxPresentRuns) present_runs[present_run_count++] = {page, page_size};
}

// Adds the present pages of [start, end) (pagemap's bit 63).
void AddPresentPages(uintptr_t start, uintptr_t end, size_t page_size) {
  static uint64_t entries[512];
  for (uintptr_t page = start; page < end;) {
    const size_t count = std::min<size_t>(512, (end - page) / page_size);
    const ssize_t got = pread(hold.pagemap_fd, entries, count * sizeof(uint64_t),
                              static_cast<off_t>(page / page_size * sizeof(uint64_t)));
    if (got <= 0) return;
    const size_t read_count = static_cast<size_t>(got) / sizeof(uint64_t);
    for (size_t i = 0; i < read_count; ++i) {
      if ((entries[i] >> 63) != 0) AddPresentPage(page + i * page_size, page_size);
    }
    page += read_count * page_size;
  }
}

// Fills present_runs from /proc/self/maps (its writable private mappings)
// and /proc/self/pagemap, both opened before Landlock; closes pagemap.
void RecordPresentPages() {
  static char text[1 << 16];
  if (hold.maps_fd >= 0 && hold.pagemap_fd >= 0 && lseek(hold.maps_fd, 0, SEEK_SET) == 0) {
    const size_t page_size = static_cast<size_t>(sysconf(_SC_PAGESIZE));
    // A line's start and end (hex) and permissions, parsed as they come.
    uintptr_t bounds[2] = {0, 0};
    char permissions[4] = {};
    int field = 0;     // 0 start, 1 end, 2 permissions, 3 the rest
    int position = 0;  // within the permissions
    for (;;) {
      const ssize_t got = read(hold.maps_fd, text, sizeof(text));
      if (got < 0 && errno == EINTR) continue;
      if (got <= 0) break;
      for (ssize_t i = 0; i < got; ++i) {
        const char c = text[i];
        if (c == '\n') {
          if (field >= 2 && permissions[1] == 'w' && permissions[3] == 'p') {
            AddPresentPages(bounds[0], bounds[1], page_size);
          }
          bounds[0] = bounds[1] = 0;
          field = 0;
          position = 0;
          continue;
        }
        if (field < 2) {
          if ((field == 0 && c == '-') || (field == 1 && c == ' ')) {
            ++field;
          } else {
            const int digit = c >= '0' && c <= '9' ? c - '0' : c >= 'a' && c <= 'f' ? c - 'a' + 10 : 0;
            bounds[field] = bounds[field] * 16 + static_cast<uintptr_t>(digit);
          }
        } else if (field == 2) {
          if (c == ' ') {
            field = 3;
          } else if (position < 4) {
            permissions[position++] = c;
          }
        }
      }
    }
  }
  if (hold.pagemap_fd >= 0) close(hold.pagemap_fd);
  hold.pagemap_fd = -1;
}

// A copy's first write to each page the held host had: done now, before
// the hello (under the load's wall cap, as a fresh host's own loading),
// not in its first callback (under the CPU budget). Each page's first byte
// is read and written back from user mode, which changes nothing the
// library sees (one thread, every signal blocked). Not madvise's
// MADV_POPULATE_WRITE: on the VM this was measured on, a page populated so
// still cost about 8 us at its first write from user mode (32768 pages:
// 280 ms), where a page written once costs 50 ns.
void TakeOverPresentPages() {
  const size_t page_size = static_cast<size_t>(sysconf(_SC_PAGESIZE));
  for (size_t i = 0; i < present_run_count; ++i) {
    for (size_t offset = 0; offset < present_runs[i].length; offset += page_size) {
      volatile unsigned char* const byte = reinterpret_cast<volatile unsigned char*>(present_runs[i].start + offset);
      *byte = *byte;
    }
  }
}

[[noreturn]] void Serve();

// A copy, just made: arms its own death with the parent (a fork clears
// it), puts its channel on 3 and its output on 1 and 2, closes every other
// descriptor, loads the callbacks' filter with its own pid (the rule
// letting it signal itself names it), gives back the signal mask the
// constructors left, says hello as the held host did, and serves. No code
// of the library runs before the filter is on.
[[noreturn]] void BecomeCopy(int channel, int output) {
  prctl(PR_SET_PDEATHSIG, SIGKILL);
  if (getppid() != hold.parent) _exit(p::kExitParentGone);
  // 0-3 are open (checked), so each F_DUPFD lands on the number closed.
  close(1);
  if (fcntl(output, F_DUPFD, 1) != 1) _exit(p::kExitUsage);
  close(2);
  if (fcntl(output, F_DUPFD, 2) != 2) _exit(p::kExitUsage);
  close(p::kChannelFd);
  if (fcntl(channel, F_DUPFD, p::kChannelFd) != p::kChannelFd) _exit(p::kExitUsage);
  rlimit files{};
  const int last = getrlimit(RLIMIT_NOFILE, &files) == 0 && files.rlim_cur < 4096 ? static_cast<int>(files.rlim_cur) : 4096;
  for (int fd = p::kChannelFd + 1; fd < last; ++fd) close(fd);
  TakeOverPresentPages();
  seccomp_release(hold.callbacks);
  scmp_filter_ctx callbacks = CallbackFilter(getpid());
  if (callbacks == nullptr || seccomp_load(callbacks) != 0) {
    Fail(Verdict::kLoadFailed, "cannot install the callback filter", nullptr);
  }
  seccomp_release(callbacks);
  sigprocmask(SIG_SETMASK, &hold.load_mask, nullptr);
  Send(hold.hello);
  Serve();
}

// The held host's loop: one copy per ForkRequest, until the parent closes
// the channel. Every signal is blocked (no handler of the library runs
// here) and nothing of the library is called.
[[noreturn]] void Hold() {
  for (;;) {
    p::ForkRequest request;
    iovec part{&request, sizeof(request)};
    alignas(cmsghdr) char control[CMSG_SPACE(2 * sizeof(int))];
    msghdr message{};
    message.msg_iov = &part;
    message.msg_iovlen = 1;
    message.msg_control = control;
    message.msg_controllen = sizeof(control);
    ssize_t got;
    do {
      got = recvmsg(p::kChannelFd, &message, MSG_CMSG_CLOEXEC);
    } while (got < 0 && errno == EINTR);
    if (got <= 0) _exit(0);  // the parent closed the channel: the search is over
    int descriptors[2] = {-1, -1};
    int received = 0;
    for (cmsghdr* header = CMSG_FIRSTHDR(&message); header != nullptr; header = CMSG_NXTHDR(&message, header)) {
      if (header->cmsg_level != SOL_SOCKET || header->cmsg_type != SCM_RIGHTS) continue;
      const size_t count = (header->cmsg_len - CMSG_LEN(0)) / sizeof(int);
      for (size_t i = 0; i < count; ++i) {
        int fd;
        memcpy(&fd, CMSG_DATA(header) + i * sizeof(int), sizeof(int));
        if (received < 2) {
          descriptors[received] = fd;
        } else {
          close(fd);
        }
        ++received;
      }
    }
    if (static_cast<size_t>(got) != sizeof(request) || request.magic != p::kForkMagic || received != 2 ||
        (message.msg_flags & MSG_CTRUNC) != 0) {
      _exit(p::kExitUsage);
    }
    const long pid = syscall(SYS_clone, p::kCopyCloneFlags, 0, nullptr, nullptr, 0);
    if (pid == 0) BecomeCopy(descriptors[0], descriptors[1]);
    const int error = pid < 0 ? errno : 0;
    close(descriptors[0]);
    close(descriptors[1]);
    p::ForkReply made;
    made.pid = pid > 0 ? static_cast<int32_t>(pid) : 0;
    made.error = error;
    if (!process::WriteAll(p::kChannelFd, &made, sizeof(made))) _exit(p::kExitParentGone);
  }
}

[[noreturn]] void Serve() {
  for (;;) {
    ssize_t got;
    do {
      got = read(p::kChannelFd, request_buffer, sizeof(request_buffer));
    } while (got < 0 && errno == EINTR);
    if (got <= 0) _exit(0);  // the parent closed the channel: the robot is done
    p::RequestHeader header;
    if (static_cast<size_t>(got) < sizeof(header)) _exit(p::kExitUsage);
    memcpy(&header, request_buffer, sizeof(header));
    const size_t tail_bytes = static_cast<size_t>(got) - sizeof(header);
    if (header.magic != p::kRequestMagic) _exit(p::kExitUsage);
    if (header.kind == static_cast<uint8_t>(p::RequestKind::kInit)) {
      if (header.member_count != 0 || !ReadInitTables(request_buffer + sizeof(header), tail_bytes,
                                                      header.parameter_count, header.input_count)) {
        _exit(p::kExitUsage);
      }
    } else if (header.parameter_count != 0 || header.input_count != 0 || header.member_count > p::kMaxMembers ||
               tail_bytes != header.member_count * sizeof(syrof_member_state)) {
      _exit(p::kExitUsage);
    }
    current_sequence = header.sequence;
    reply = p::Reply{};
    reply.sequence = header.sequence;
    const syrof_ldmap ldmap{header.epoch, header.mode, header.self_id, header.member_count,
                            reinterpret_cast<const syrof_member_state*>(request_buffer + sizeof(header))};
    switch (static_cast<p::RequestKind>(header.kind)) {
      case p::RequestKind::kInit:
        reply.global_state = syrof_internal_host_init(&header.info);
        break;
      case p::RequestKind::kNewRound: {
        syrof_car_command command{};
        command.kind = SYROF_COMMAND_STOP;
        reply.global_state =
            syrof_internal_host_new_round(&command, &ldmap, header.global_state, header.clock_ms);
        reply.command = command;
        break;
      }
      case p::RequestKind::kEndOfRound:
        reply.global_state = syrof_internal_host_end_of_round(&ldmap, header.global_state, header.clock_ms);
        break;
      default:
        _exit(p::kExitUsage);
    }
    // What the app printed is in the pipe before the reply is on the
    // channel: stdio's buffers are flushed first, so the parent's log is
    // complete (and the same on every run) when it sees the reply.
    fflush(stdout);
    fflush(stderr);
    reply.kind = static_cast<uint8_t>(p::ReplyKind::kDone);
    Send(reply);
  }
}

// The command line: run|check|hold LIBRARY PARENT_PID ADDRESS_SPACE_BYTES.
struct HostArguments {
  bool check_only = false;
  bool hold_mode = false;  // hold: the fork server's held host (docs/app_host.md "The fork server")
  const char* library = nullptr;
  pid_t parent = 0;
  unsigned long long address_space = 0;
};

HostArguments ReadArguments(char** argv) {
  HostArguments arguments;
  arguments.check_only = strcmp(argv[1], "check") == 0;
  arguments.hold_mode = strcmp(argv[1], "hold") == 0;
  arguments.library = argv[2];
  arguments.parent = static_cast<pid_t>(strtol(argv[3], nullptr, 10));
  arguments.address_space = strtoull(argv[4], nullptr, 10);
  return arguments;
}

// Addresses the same on every run, so even an app that hashes pointers is
// repeatable: the parent spawns the host with ADDR_NO_RANDOMIZE set (the
// personality takes effect at exec); say so if that did not happen.
void NoteAddressRandomization(uint32_t& notes) {
  if ((personality(0xffffffff) & ADDR_NO_RANDOMIZE) == 0) notes |= p::kNoteNoAslrOff;
}

// 1. Die with the parent (and make sure it has not died already).
void DieWithParent(pid_t parent) {
  prctl(PR_SET_PDEATHSIG, SIGKILL);
  if (getppid() != parent) _exit(p::kExitParentGone);
}

// 2. Every descriptor but 0-3 closed: nothing the parent had open
//    without close-on-exec reaches the library (docs/app_host.md).
void CloseInheritedDescriptors(uint32_t& notes) {
  if (!syrof::process::CloseDescriptorsFrom(p::kChannelFd + 1)) notes |= p::kNoteNoCloseRange;
}

// 3. Limits: no core files, no files written, few descriptors, bounded memory.
void SetLimits(unsigned long long address_space, uint32_t& notes) {
  using syrof::process::SetLimit;
  SetLimit(RLIMIT_CORE, 0);
  SetLimit(RLIMIT_FSIZE, 0);
  SetLimit(RLIMIT_NOFILE, 16);
#if defined(SYROF_APP_HOST_SANITIZED)
  (void)address_space;
  notes |= p::kNoteSanitized;
#else
  (void)notes;
  SetLimit(RLIMIT_AS, static_cast<rlim_t>(address_space));
#endif
  SetAllocationRefusedHandler(OnAllocationRefused);
}

// 3, continued. stdio's own buffer for stdout: glibc would allocate one at
// the first printf, after asking fstat about the descriptor, which the
// callback filter refuses. (stderr is unbuffered and asks nothing.)
void GiveStdoutItsBuffer() {
  static char stdout_buffer[4096];
  setvbuf(stdout, stdout_buffer, _IOFBF, sizeof(stdout_buffer));
}

// 4. The library is opened while the host may still read where it lies
//    (a 0700 folder of the caller's); it is loaded later through
//    /proc/self/fd, after the uid is dropped. The loader's file rules are
//    built now too, and applied in step 7a. Returns the library's descriptor.
int OpenLibrary(const char* library, syrof::process::FileRuleset& file_rules, uint32_t& notes) {
  const int library_fd = open(library, O_RDONLY | O_CLOEXEC);
  if (library_fd < 0) Fail(syrof::app::Verdict::kLoadFailed, "cannot open the library: ", strerror(errno));
  if (!LoaderFileRules(file_rules, library)) {
    Fail(syrof::app::Verdict::kLoadFailed, "cannot confine the loader: ", file_rules.error().c_str());
  }
  if (!file_rules.created()) notes |= p::kNoteNoLandlock;
  return library_fd;
}

// 4, a held host. Its copies inherit its loader filter, which cannot name
// their pids: it lets signals through, and only Landlock's signal scope
// keeps them in the held host's domain. Without the scope there is no
// holding: the hello says so and the host ends. With it, what is checked
// after the load is opened now.
void PrepareToHold(const syrof::process::FileRuleset& file_rules, uint32_t notes) {
  const bool can_hold = file_rules.created() && syrof::process::LandlockAbi() >= 6;
  if (!can_hold) {
    p::Reply refused;
    refused.kind = static_cast<uint8_t>(p::ReplyKind::kHello);
    refused.notes = notes | p::kHoldNoSignalScope;
    Send(refused);
    _exit(0);
  }
  // Read after the load, to find a mapping a constructor shared; /proc is
  // out of Landlock's rules, so it is opened now.
  hold.maps_fd = open("/proc/self/maps", O_RDONLY | O_CLOEXEC);
  hold.pagemap_fd = open("/proc/self/pagemap", O_RDONLY | O_CLOEXEC);
  RecordStandardDescriptors();
}

// 5. An unprivileged uid when started as root; no process may then be
//    started under it (RLIMIT_NPROC 0: the host never forks).
void DropPrivileges(pid_t parent, bool hold_mode, uint32_t& notes) {
  if (geteuid() == 0) {
    // (DropToNobody sets the parent-death signal again: a change of uid or
    // gid clears it.)
    if (const int refused = syrof::process::DropToNobody(); refused != 0) {
      Fail(syrof::app::Verdict::kLoadFailed, "cannot drop to uid 65534: ", strerror(refused));
    }
  } else {
    notes |= p::kNoteNotRoot;
  }
  // (A held host makes its copies: it keeps the limit it was given. A
  // process its constructors start stays in its process group, where the
  // parent finds it after the load: docs/app_host.md "The fork server".)
  if (!hold_mode) syrof::process::SetLimit(RLIMIT_NPROC, 0);
  prctl(PR_SET_DUMPABLE, 1);  // keeps /proc/self/fd/N readable after the uid change
  // The parent may have gone while the death signal was cleared.
  if (getppid() != parent) _exit(p::kExitParentGone);
}

// 6. Namespaces: no network, no IPC, its own hostname, no uid outside.
void EnterNamespaces(uint32_t& notes) {
  if (unshare(CLONE_NEWUSER | CLONE_NEWNET | CLONE_NEWIPC | CLONE_NEWUTS) != 0) notes |= p::kNoteNoNamespaces;
  // A new user namespace gives its first process every capability inside
  // it; the host needs none of them.
  __user_cap_header_struct cap_header{_LINUX_CAPABILITY_VERSION_3, 0};
  __user_cap_data_struct no_caps[2] = {};
  (void)syscall(SYS_capset, &cap_header, no_caps);
}

// 7. No new privileges, after the SIGSYS handler is in place. The names of
//    the calls are resolved first (the SIGSYS handler cannot allocate).
void ForbidNewPrivileges() {
  for (int number = 0; number < kMaxSyscall; ++number) {
    syscall_names[number] = seccomp_syscall_resolve_num_arch(SCMP_ARCH_NATIVE, number);
  }
  struct sigaction action {};
  action.sa_sigaction = OnSigsys;
  action.sa_flags = SA_SIGINFO | SA_RESETHAND | SA_NODEFER;
  sigemptyset(&action.sa_mask);
  sigaction(SIGSYS, &action, nullptr);
  if (prctl(PR_SET_NO_NEW_PRIVS, 1, 0, 0, 0) != 0) {
    Fail(syrof::app::Verdict::kLoadFailed, "no_new_privs refused: ", strerror(errno));
  }
}

// 7a. Landlock: from here on only the library's and the system's library
//     folders can be opened, and only for reading (LoaderFileRules).
void RestrictFiles(syrof::process::FileRuleset& file_rules) {
  if (file_rules.created()) {
    if (const int refused = file_rules.RestrictSelf(); refused != 0) {
      Fail(syrof::app::Verdict::kLoadFailed, "Landlock refused the loader's file rules: ", strerror(refused));
    }
    file_rules.Close();  // descriptors 0-3 only, as before
  }
}

// 7, the system call filters: the loader's is installed; the callbacks'
//    is built now, with this pid, and returned for step 9 (or 9').
scmp_filter_ctx InstallLoaderFilter(bool hold_mode) {
  const pid_t self = getpid();
  scmp_filter_ctx loader = LoaderFilter(self, hold_mode);
  scmp_filter_ctx callbacks = CallbackFilter(self);
  if (loader == nullptr || callbacks == nullptr || seccomp_load(loader) != 0) {
    Fail(syrof::app::Verdict::kLoadFailed, "cannot install the system call filter", nullptr);
  }
  seccomp_release(loader);
  return callbacks;
}

// 8. Load, find the entry, check the ABI. Returns the app's descriptor.
const syrof_app_descriptor* LoadApp(int library_fd) {
  char proc_path[64];
  CopyText(proc_path, sizeof(proc_path), "/proc/self/fd/");
  AppendNumber(proc_path, sizeof(proc_path), static_cast<uint64_t>(library_fd));
  void* handle = dlopen(proc_path, RTLD_NOW | RTLD_LOCAL);
  if (handle == nullptr) Fail(syrof::app::Verdict::kLoadFailed, "cannot load: ", dlerror());
  close(library_fd);
  dlerror();
  void* entry_symbol = dlsym(handle, SYROF_APP_ENTRY_SYMBOL);
  if (entry_symbol == nullptr) Fail(syrof::app::Verdict::kLoadFailed, "no symbol " SYROF_APP_ENTRY_SYMBOL, nullptr);
  const syrof_app_entry_fn entry = reinterpret_cast<syrof_app_entry_fn>(entry_symbol);
  const syrof_app_descriptor* descriptor = entry();
  if (descriptor != nullptr && descriptor->abi_version != SYROF_APP_ABI_VERSION) {
    char detail[p::kTextBytes];
    CopyText(detail, sizeof(detail), "built for app ABI ");
    AppendNumber(detail, sizeof(detail), descriptor->abi_version);
    size_t length = strlen(detail);
    CopyText(detail + length, sizeof(detail) - length, ", this SyROF has ");
    AppendNumber(detail, sizeof(detail), SYROF_APP_ABI_VERSION);
    ReportFault(syrof::app::Verdict::kBadAbi, detail);
  }
  const int bound = syrof_internal_host_bind(descriptor, RecordPayload, LookUpParameter, LookUpInput, nullptr);
  if (bound == 1) Fail(syrof::app::Verdict::kBadAbi, SYROF_APP_ENTRY_SYMBOL "() returned no descriptor", nullptr);
  if (bound != 0) Fail(syrof::app::Verdict::kBadAbi, "the descriptor lacks a callback", nullptr);
  return descriptor;
}

// Writes the hello a host says once loaded: its notes and the app's name.
void WriteHello(const syrof_app_descriptor* descriptor, uint32_t notes, p::Reply& hello) {
  hello.kind = static_cast<uint8_t>(p::ReplyKind::kHello);
  hello.notes = notes;
  CopyText(hello.text, sizeof(hello.text), descriptor->name != nullptr ? descriptor->name : "c_app");
}

// 9'. The fork server: no callbacks' filter here; each copy loads its
//     own (BecomeCopy). The hello says whether copies would start
//     clean; if not, the parent starts a fresh host per robot instead.
[[noreturn]] void HoldForCopies(pid_t parent, scmp_filter_ctx callbacks, const syrof_app_descriptor* descriptor,
                                uint32_t notes) {
  RecordPresentPages();
  const uint32_t unclean = WhatCopiesWouldShare();
  sigset_t all;
  sigfillset(&all);
  sigprocmask(SIG_SETMASK, &all, &hold.load_mask);
  hold.parent = parent;
  hold.callbacks = callbacks;
  fflush(stdout);
  fflush(stderr);
  WriteHello(descriptor, notes, hold.hello);
  p::Reply held = hold.hello;
  held.notes |= unclean;
  Send(held);
  if (unclean != 0) _exit(0);
  Hold();
}

// 9. The callbacks' filter: from here on nothing is opened.
void InstallCallbackFilter(scmp_filter_ctx callbacks) {
  if (seccomp_load(callbacks) != 0) {
    Fail(syrof::app::Verdict::kLoadFailed, "cannot install the callback filter", nullptr);
  }
  seccomp_release(callbacks);
}

// What the library printed while it loaded goes out before the hello.
void SayHello(const syrof_app_descriptor* descriptor, uint32_t notes) {
  fflush(stdout);
  fflush(stderr);
  p::Reply hello;
  WriteHello(descriptor, notes, hello);
  Send(hello);
}

}  // namespace
}  // namespace syrof::app_host

int main(int argc, char** argv) {
  using namespace syrof::app_host;
  if (argc != 5) {
    fprintf(stderr, "usage: syrof-app-host run|check|hold LIBRARY PARENT_PID ADDRESS_SPACE_BYTES\n"
                    "(started by SyROF; not meant to be run by hand)\n");
    return protocol::kExitUsage;
  }
  const HostArguments arguments = ReadArguments(argv);
  uint32_t notes = 0;
  NoteAddressRandomization(notes);
  // The order matters: each step relies on those before it (docs/app_host.md,
  // "What the host does, in order", which counts the line above as step 1).
  DieWithParent(arguments.parent);                                            // 1
  CloseInheritedDescriptors(notes);                                           // 2
  SetLimits(arguments.address_space, notes);                                  // 3
  GiveStdoutItsBuffer();
  syrof::process::FileRuleset file_rules;
  const int library_fd = OpenLibrary(arguments.library, file_rules, notes);  // 4
  if (arguments.hold_mode) PrepareToHold(file_rules, notes);
  DropPrivileges(arguments.parent, arguments.hold_mode, notes);               // 5
  EnterNamespaces(notes);                                                     // 6
  ForbidNewPrivileges();                                                      // 7
  RestrictFiles(file_rules);                                                  // 7a
  const scmp_filter_ctx callbacks = InstallLoaderFilter(arguments.hold_mode);
  const syrof_app_descriptor* descriptor = LoadApp(library_fd);              // 8
  if (arguments.hold_mode) HoldForCopies(arguments.parent, callbacks, descriptor, notes);  // 9'
  InstallCallbackFilter(callbacks);                                           // 9
  SayHello(descriptor, notes);
  if (arguments.check_only) _exit(0);
  Serve();
}
