#include "host_process.h"

#include "loaded_library.h"

#include <fcntl.h>
#include <poll.h>
#include <signal.h>
#include <sys/resource.h>
#include <sys/socket.h>
#include <unistd.h>

#include <algorithm>
#include <cerrno>
#include <chrono>
#include <cstdlib>
#include <cstring>
#include <filesystem>
#include <string>
#include <system_error>
#include <utility>

namespace syrof::app_host {
namespace {

namespace p = protocol;
using app::CallStatus;
using app::Verdict;

int64_t Nanoseconds(clockid_t clock) {
  timespec now{};
  if (clock_gettime(clock, &now) != 0) return -1;
  return int64_t{now.tv_sec} * 1'000'000'000 + now.tv_nsec;
}

// The user-mode CPU time of process `stat_fd`'s (an open /proc/PID/stat),
// in nanoseconds (the kernel counts it in clock ticks); -1 if unreadable.
// Only user time is held against a callback's CPU budget: system time
// includes what the kernel does on the host's behalf when the machine is
// short of memory (a page fault that enters direct reclaim was seen to take
// 100 ms), which the app does not control; the wall cap bounds it.
int64_t UserNanoseconds(int stat_fd) {
  char text[1024];
  const ssize_t got = pread(stat_fd, text, sizeof text - 1, 0);
  if (got <= 0) return -1;
  text[got] = '\0';
  // The command name (field 2) is in parentheses and may hold spaces:
  // fields 3 onwards follow the last ')'. utime is field 14.
  const char* field = strrchr(text, ')');
  if (field == nullptr) return -1;
  for (int i = 2; i < 14; ++i) {
    field = strchr(field + 1, ' ');
    if (field == nullptr) return -1;
  }
  char* end = nullptr;
  const unsigned long long ticks = strtoull(field + 1, &end, 10);
  if (end == field + 1) return -1;
  static const long kTicksPerSecond = sysconf(_SC_CLK_TCK);
  if (kTicksPerSecond <= 0) return -1;
  return static_cast<int64_t>(ticks) * (1'000'000'000 / kTicksPerSecond);
}

// Raises this process's soft descriptor limit to its hard limit (at most
// 1 << 20). Each host holds four descriptors here (channel, output, pidfd,
// log): a swarm of a few hundred passes the usual soft limit of 1024.
// Called only when a descriptor could not be made (EMFILE). False if
// nothing could be raised.
bool RaiseDescriptorLimit() {
  rlimit limit{};
  if (getrlimit(RLIMIT_NOFILE, &limit) != 0) return false;
  const rlim_t wanted = std::min<rlim_t>(limit.rlim_max, rlim_t{1} << 20);
  if (limit.rlim_cur >= wanted) return false;
  limit.rlim_cur = wanted;
  return setrlimit(RLIMIT_NOFILE, &limit) == 0;
}

std::string SignalName(int signal) {
  const char* abbreviation = sigabbrev_np(signal);
  return abbreviation != nullptr ? std::string("SIG") + abbreviation : "signal " + std::to_string(signal);
}

}  // namespace

HostProcess::~HostProcess() {
  KillAndReap();
  FinishLog();
}

void HostProcess::SetFault(Verdict verdict, const std::string& detail) {
  if (faulted_) return;
  faulted_ = true;
  fault_ = CallStatus::Fault(verdict, detail.c_str());
  full_detail_ = detail;
}

void HostProcess::KillAndReap() {
  if (child_.started() && !child_.reaped()) {
    // The host alone: a held host's copies, in its group, run on (the
    // group goes with the LoadedLibrary).
    child_.Kill();
    (void)child_.Reap();
  }
  // Whatever was still in the pipe belongs in the log.
  if (output_.valid()) (void)DrainOutput();
  output_.Reset();
  channel_.Reset();
}

void HostProcess::FinishLog() {
  if (!log_.valid()) return;
  if (output_bytes_ > log_written_) {
    const std::string line = "\n[syrof] " + std::to_string(output_bytes_ - log_written_) +
                             " more bytes were written and not kept (log_keep_bytes " +
                             std::to_string(limits_.log_keep_bytes) + ")\n";
    (void)process::WriteAll(log_.get(), line.data(), line.size());  // a full disk loses log bytes, not the run
  }
  log_.Reset();
}

bool HostProcess::DrainOutput() {
  char buffer[65536];
  for (;;) {
    const ssize_t got = read(output_.get(), buffer, sizeof(buffer));
    if (got < 0 && errno == EINTR) continue;
    if (got <= 0) return output_bytes_ <= limits_.output_limit_bytes;
    const uint64_t size = static_cast<uint64_t>(got);
    if (capture_ && captured_.size() < limits_.log_keep_bytes) {
      captured_.append(buffer, std::min<uint64_t>(size, limits_.log_keep_bytes - captured_.size()));
    }
    if (log_.valid() && log_written_ < limits_.log_keep_bytes) {
      const uint64_t keep = std::min(size, limits_.log_keep_bytes - log_written_);
      (void)process::WriteAll(log_.get(), buffer, keep);
      log_written_ += keep;
    }
    output_bytes_ += size;
    if (output_bytes_ > limits_.output_limit_bytes) return false;
  }
}

bool HostProcess::OpenPipes(const HostOptions& options, uint16_t robot_id, process::Fd& child_channel,
                            process::Fd& child_output) {
  limits_ = options.limits;
  library_path_ = options.library_path;
  if (!options.log_directory.empty() && !capture_) {
    // Parents too (OUT/robots before OUT exists). A log that cannot be
    // opened loses the robot's output, not the robot.
    std::error_code ignored;
    std::filesystem::create_directories(options.log_directory, ignored);
    const std::string log_path = options.log_directory + "/" + std::to_string(robot_id) + ".log";
    log_.Reset(open(log_path.c_str(), O_WRONLY | O_CREAT | O_TRUNC | O_CLOEXEC, 0644));
    if (!log_.valid() && errno == EMFILE && RaiseDescriptorLimit()) {
      log_.Reset(open(log_path.c_str(), O_WRONLY | O_CREAT | O_TRUNC | O_CLOEXEC, 0644));
    }
  }

  int channel[2] = {-1, -1};
  int output[2] = {-1, -1};
  for (int attempt = 0;; ++attempt) {
    if (socketpair(AF_UNIX, SOCK_SEQPACKET | SOCK_CLOEXEC, 0, channel) == 0 && pipe2(output, O_CLOEXEC) == 0) break;
    const int error = errno;
    // A channel made before the pipe was refused is closed.
    const process::Fd made_a(std::exchange(channel[0], -1));
    const process::Fd made_b(std::exchange(channel[1], -1));
    if (attempt == 0 && error == EMFILE && RaiseDescriptorLimit()) continue;
    SetFault(Verdict::kLoadFailed, std::string("cannot create the host's channel: ") + strerror(error));
    log_.Reset();
    return false;
  }
  channel_.Reset(channel[0]);
  child_channel.Reset(channel[1]);
  output_.Reset(output[0]);
  child_output.Reset(output[1]);
  fcntl(output_.get(), F_SETFL, O_NONBLOCK);
  return true;
}

CallStatus HostProcess::Spawn(const HostOptions& options, uint16_t robot_id, Mode mode) {
  capture_ = mode == Mode::kHold;
  const std::string host = options.host_binary.empty() ? FindHostBinary() : options.host_binary;
  if (host.empty()) {
    limits_ = options.limits;
    library_path_ = options.library_path;
    SetFault(Verdict::kLoadFailed, "syrof-app-host not found (set SYROF_APP_HOST)");
    return fault_;
  }
  process::Fd child_channel;
  process::Fd child_output;
  if (!OpenPipes(options, robot_id, child_channel, child_output)) return fault_;

  process::Command command;
  const char* verb = mode == Mode::kCheck ? "check" : mode == Mode::kHold ? "hold" : "run";
  command.argv = {host, verb, options.library_path, std::to_string(getpid()),
                  std::to_string(limits_.address_space_bytes)};
  // A fixed, minimal environment: the app sees the same on every run. A
  // test of a kernel without Landlock passes its pretence on (it can only
  // take the host's Landlock layer away).
  command.environment = {"PATH=/usr/bin:/bin", "LC_ALL=C"};
  const char* pretend = std::getenv("SYROF_PRETEND_NO_LANDLOCK");
  if (pretend != nullptr && pretend[0] == '1') command.environment.push_back("SYROF_PRETEND_NO_LANDLOCK=1");
  // 0 /dev/null, 1 and 2 the output pipe, 3 the channel (protocol.h).
  command.descriptors = {{1, child_output.get()}, {2, child_output.get()}, {p::kChannelFd, child_channel.get()}};
  // Address randomisation off for the host (docs/app_host.md).
  command.no_address_randomization = true;
  // A held host leads a group of its own: its copies, and any process its
  // library's constructors started, are in it (docs/app_host.md).
  command.own_process_group = mode == Mode::kHold;
  child_ = process::Spawn(command);
  if (!child_.started()) {
    SetFault(Verdict::kLoadFailed, "cannot start " + host + ": " + strerror(child_.start_error()));
    KillAndReap();
    return fault_;
  }
  // A pidfd of -1 (old kernels): the channel's hang-up says it too.
  OpenCpuStat();
  return CallStatus::Ok();
}

void HostProcess::OpenCpuStat() {
  cpu_stat_ = process::Fd(open(("/proc/" + std::to_string(child_.pid()) + "/stat").c_str(), O_RDONLY | O_CLOEXEC));
  have_cpu_clock_ = cpu_stat_.get() >= 0 && UserNanoseconds(cpu_stat_.get()) >= 0;
}

CallStatus HostProcess::Start(const HostOptions& options, uint16_t robot_id, Mode mode) {
  if (!Spawn(options, robot_id, mode).ok()) return fault_;
  p::Reply hello;
  return AwaitHello(hello);
}

CallStatus HostProcess::AwaitHello(p::Reply& hello) {
  if (faulted_) return fault_;
  started_ = true;
  if (WaitForReply(hello, /*load=*/true) == Wait::kFault) return fault_;
  if (hello.kind != static_cast<uint8_t>(p::ReplyKind::kHello)) {
    SetFault(Verdict::kBadAbi, "the host's first reply is not its hello");
    KillAndReap();
    return fault_;
  }
  hello.text[sizeof(hello.text) - 1] = '\0';
  app_name_ = hello.text;  // printable: TryReceive made it so
  notes_ = hello.notes;
  return CallStatus::Ok();
}

bool HostProcess::TryReceive(p::Reply& reply, bool& malformed) {
  malformed = false;
  p::Reply buffer;
  ssize_t got;
  do {
    got = recv(channel_.get(), &buffer, sizeof(buffer), MSG_DONTWAIT | MSG_TRUNC);
  } while (got < 0 && errno == EINTR);
  if (got < 0) return false;  // nothing pending
  if (got == 0) return false; // the host closed its end (it is ending)
  if (static_cast<size_t>(got) != sizeof(buffer) || buffer.magic != p::kReplyMagic ||
      buffer.protocol_version != p::kProtocolVersion || buffer.call_count > p::kCallsPerReply ||
      buffer.kind < static_cast<uint8_t>(p::ReplyKind::kHello) ||
      buffer.kind > static_cast<uint8_t>(p::ReplyKind::kFault)) {
    malformed = true;
    return true;
  }
  buffer.text[sizeof(buffer.text) - 1] = '\0';
  // The text is the app's name or a fault's detail, printed in run summaries
  // and reports, and the student's code can write it (the descriptor's name,
  // or a reply forged on the channel): a byte outside printable ASCII (an
  // escape sequence, a byte that is not UTF-8, a bidirectional override)
  // becomes '?'.
  for (char& c : buffer.text) {
    if (c == '\0') break;
    if (c < 0x20 || c > 0x7E) c = '?';
  }
  reply = buffer;
  return true;
}

void HostProcess::FaultFromExit(bool load) {
  // The channel hangs up as the host's descriptors close, a moment before
  // the process is a zombie; a host that closed the channel itself and goes
  // on is stopped after a short grace.
  std::optional<process::ExitStatus> status = child_.Wait(std::chrono::milliseconds(200));
  const bool killed = !status.has_value();
  if (killed) {
    child_.Kill();
    status = child_.Reap();
  } else if (status->how == process::ExitStatus::How::kUnknown) {
    SetFault(Verdict::kCrashed, std::string("the host vanished") + (load ? " during load" : ""));
    return;
  }
  const std::string when = load ? " during load" : "";
  if (killed) {
    SetFault(Verdict::kBadAbi, "the host closed its channel" + when);
  } else if (status->exited()) {
    if (status->code == p::kExitParentGone) {
      SetFault(Verdict::kExited, "the host lost its channel" + when);
    } else {
      SetFault(Verdict::kExited, "exit status " + std::to_string(status->code) + when);
    }
  } else if (status->signal == SIGSYS) {
    // Killed by the filter itself (the app blocked SIGSYS): not named.
    SetFault(Verdict::kForbiddenSyscall, "a forbidden system call (SIGSYS)" + when);
  } else {
    SetFault(Verdict::kCrashed, SignalName(status->signal) + when);
  }
}

// Handles one reply taken off the channel: a fault frame ends the host.
HostProcess::Wait HostProcess::Accept(p::Reply& reply, bool malformed, bool load) {
  if (malformed) {
    SetFault(Verdict::kBadAbi, "a malformed reply from the host");
    KillAndReap();
    return Wait::kFault;
  }
  if (reply.kind != static_cast<uint8_t>(p::ReplyKind::kFault)) return Wait::kMessage;
  const bool known = reply.verdict > static_cast<uint8_t>(Verdict::kAppError) &&
                     reply.verdict <= static_cast<uint8_t>(app::kLastVerdict);
  std::string detail = reply.text;
  // dlerror() names the descriptor the host loaded through: "/proc/self/fd/
  // N: undefined symbol: x". The reason alone is kept (CheckLibrary's message
  // names the file first; a CallStatus keeps only 47 bytes); elsewhere in
  // the text the descriptor becomes the file's path.
  const size_t proc = detail.find("/proc/self/fd/");
  if (proc != std::string::npos) {
    size_t end = proc + 14;
    while (end < detail.size() && detail[end] >= '0' && detail[end] <= '9') ++end;
    if (detail.compare(end, 2, ": ") == 0) {
      detail.erase(proc, end + 2 - proc);
    } else {
      detail.replace(proc, end - proc, library_path_);
    }
  }
  if (load && (reply.verdict == static_cast<uint8_t>(Verdict::kForbiddenSyscall) ||
               reply.verdict == static_cast<uint8_t>(Verdict::kMemory))) {
    detail += " during load";
  }
  // What the host wrote before it reported is in the log.
  if (!DrainOutput()) {
    SetFault(Verdict::kOutputLimit, "wrote over " + std::to_string(limits_.output_limit_bytes) + " bytes");
  }
  SetFault(known ? static_cast<Verdict>(reply.verdict) : Verdict::kBadAbi,
           known ? detail : "a fault reply with an unknown verdict");
  KillAndReap();
  return Wait::kFault;
}

HostProcess::Wait HostProcess::WaitForReply(p::Reply& reply, bool load) {
  // (A batch may be followed by replies already queued: the poll sees them.)
  bool malformed = false;
  // The load cap counts from when the parent starts waiting, not from the
  // spawn: a swarm's hosts all start at once and load side by side, and the
  // last robot's turn may come long after its host was spawned.
  const int64_t wall_start = Nanoseconds(CLOCK_MONOTONIC);
  const int64_t cpu_start = !load && have_cpu_clock_ ? UserNanoseconds(cpu_stat_.get()) : -1;
  const int64_t wall_cap = int64_t{load ? limits_.load_wall_cap_ms : limits_.wall_cap_ms} * 1'000'000;
  const int64_t cpu_budget = int64_t{limits_.cpu_budget_ms} * 1'000'000;
  int64_t wait_ns = cpu_start >= 0 ? std::min(wall_cap, cpu_budget) : wall_cap;
  for (;;) {
    // The CPU clock cannot run faster than the wall clock (one thread), so
    // waking when either could first be over is enough.
    wait_ns = std::max<int64_t>(wait_ns, 0) + 1'000'000;  // past the cap, not just before it
    const timespec timeout{static_cast<time_t>(wait_ns / 1'000'000'000), static_cast<long>(wait_ns % 1'000'000'000)};
    pollfd fds[3] = {
        {channel_.get(), POLLIN, 0}, {output_open_ ? output_.get() : -1, POLLIN, 0}, {child_.pidfd(), POLLIN, 0}};
    const int ready = ppoll(fds, child_.pidfd() >= 0 ? 3 : 2, &timeout, nullptr);
    if (ready < 0 && errno != EINTR) {
      KillAndReap();
      SetFault(Verdict::kCrashed, std::string("cannot wait for the host: ") + strerror(errno));
      return Wait::kFault;
    }
    if (ready > 0) {
      // Output first: the host writes it before its reply, so a reply seen
      // in this poll has its output readable in the same poll.
      if ((fds[1].revents & POLLIN) != 0 && !DrainOutput()) {
        KillAndReap();
        SetFault(Verdict::kOutputLimit, "wrote over " + std::to_string(limits_.output_limit_bytes) + " bytes");
        return Wait::kFault;
      }
      // Both output descriptors closed (by the app, or because the host is
      // ending): nothing more comes; the pidfd or the channel says the rest.
      if ((fds[1].revents & (POLLHUP | POLLERR)) != 0 && (fds[1].revents & POLLIN) == 0) output_open_ = false;
      if ((fds[0].revents & POLLIN) != 0 && TryReceive(reply, malformed)) return Accept(reply, malformed, load);
      if ((fds[2].revents & POLLIN) != 0 || (fds[0].revents & (POLLHUP | POLLERR)) != 0) {
        // The host ended (or closed its channel): a last frame may be queued.
        if (TryReceive(reply, malformed)) return Accept(reply, malformed, load);
        if (!DrainOutput()) {
          SetFault(Verdict::kOutputLimit, "wrote over " + std::to_string(limits_.output_limit_bytes) + " bytes");
        }
        FaultFromExit(load);
        KillAndReap();
        return Wait::kFault;
      }
    }
    const int64_t wall_used = Nanoseconds(CLOCK_MONOTONIC) - wall_start;
    const int64_t cpu_used = cpu_start >= 0 ? UserNanoseconds(cpu_stat_.get()) - cpu_start : 0;
    if (cpu_start >= 0 && cpu_used > cpu_budget) {
      KillAndReap();
      // Not the CPU time measured: it varies from run to run, and the
      // detail reaches metrics.json, which must repeat byte for byte.
      SetFault(Verdict::kTimeout, "CPU time over " + std::to_string(limits_.cpu_budget_ms) + " ms");
      return Wait::kFault;
    }
    if (wall_used > wall_cap) {
      KillAndReap();
      SetFault(Verdict::kTimeout, "wall time over " + std::to_string(wall_cap / 1'000'000) + " ms" +
                                      (load ? " during load" : ""));
      return Wait::kFault;
    }
    wait_ns = wall_cap - wall_used;
    if (cpu_start >= 0) wait_ns = std::min(wait_ns, cpu_budget - cpu_used);
  }
}

CallStatus HostProcess::Call(const void* request, size_t size, uint32_t sequence,
                             const std::function<void(const p::PayloadCall&)>& on_call, p::Reply& done) {
  if (faulted_) return fault_;
  if (!started_) {
    // The first call waits for the hello (MakeHostedApp only spawned).
    p::Reply hello;
    if (!AwaitHello(hello).ok()) return fault_;
  }
  ssize_t sent;
  do {
    // Never blocks: the host has read every earlier request, so its queue
    // is empty; a full one means it is not taking requests.
    sent = send(channel_.get(), request, size, MSG_NOSIGNAL | MSG_DONTWAIT);
  } while (sent < 0 && errno == EINTR);
  if (sent != static_cast<ssize_t>(size)) {
    // The host is gone (or going): its exit or signal is the verdict.
    p::Reply ignored;
    if (WaitForReply(ignored, false) == Wait::kFault) return fault_;
    KillAndReap();
    SetFault(Verdict::kBadAbi, "the host took no request");
    return fault_;
  }
  uint32_t calls_seen = 0;
  for (;;) {
    if (WaitForReply(done, false) == Wait::kFault) return fault_;
    const bool batch = done.kind == static_cast<uint8_t>(p::ReplyKind::kBatch);
    const bool final = done.kind == static_cast<uint8_t>(p::ReplyKind::kDone);
    if ((!batch && !final) || done.sequence != sequence) {
      KillAndReap();
      SetFault(Verdict::kBadAbi, "a reply out of order");
      return fault_;
    }
    for (uint8_t i = 0; i < done.call_count; ++i) on_call(done.calls[i]);
    calls_seen += done.call_count;
    if (final) {
      if (done.calls_total != calls_seen) {
        KillAndReap();
        SetFault(Verdict::kBadAbi, "the reply's call count does not add up");
        return fault_;
      }
      return CallStatus::Ok();
    }
  }
}

CallStatus HostProcess::SpawnCopy(const HostOptions& options, uint16_t robot_id, LoadedLibrary& library) {
  process::Fd child_channel;
  process::Fd child_output;
  if (!OpenPipes(options, robot_id, child_channel, child_output)) return fault_;
  const LoadedLibrary::CopyStart copy = library.StartCopy(child_channel.get(), child_output.get());
  if (!copy.made) {
    // Fresh, as without the fork server: the same host from the start.
    channel_.Reset();
    output_.Reset();
    log_.Reset();
    return Spawn(options, robot_id, Mode::kRun);
  }
  child_ = process::Adopt(copy.pid);
  if (!child_.started()) {
    // Not ours (cannot happen with CLONE_PARENT): never left running.
    kill(copy.pid, SIGKILL);
    SetFault(Verdict::kLoadFailed, std::string("cannot hold the host's copy: ") + strerror(child_.start_error()));
    KillAndReap();
    return fault_;
  }
  // The log begins as a fresh host's would: with what the library printed
  // while it loaded.
  if (log_.valid() && !copy.load_output.empty()) {
    (void)process::WriteAll(log_.get(), copy.load_output.data(), copy.load_output.size());
  }
  log_written_ = copy.load_output.size();
  output_bytes_ = copy.load_output_bytes;
  // Its CPU budget is counted as a fresh host's: user time only.
  OpenCpuStat();
  return CallStatus::Ok();
}

HostProcess::Copy HostProcess::MakeCopy(int child_channel, int child_output, pid_t& pid, int& error) {
  pid = -1;
  error = 0;
  if (faulted_ || !started_ || child_.reaped()) return Copy::kGone;
  p::ForkRequest request;
  iovec part{&request, sizeof(request)};
  alignas(cmsghdr) char control[CMSG_SPACE(2 * sizeof(int))] = {};
  msghdr message{};
  message.msg_iov = &part;
  message.msg_iovlen = 1;
  message.msg_control = control;
  message.msg_controllen = sizeof(control);
  cmsghdr* header = CMSG_FIRSTHDR(&message);
  header->cmsg_level = SOL_SOCKET;
  header->cmsg_type = SCM_RIGHTS;
  header->cmsg_len = CMSG_LEN(2 * sizeof(int));
  const int descriptors[2] = {child_channel, child_output};
  std::memcpy(CMSG_DATA(header), descriptors, sizeof(descriptors));
  ssize_t sent;
  do {
    sent = sendmsg(channel_.get(), &message, MSG_NOSIGNAL | MSG_DONTWAIT);
  } while (sent < 0 && errno == EINTR);
  if (sent != static_cast<ssize_t>(sizeof(request))) {
    KillAndReap();
    SetFault(Verdict::kCrashed, "the held host took no request");
    return Copy::kGone;
  }
  const int64_t deadline = Nanoseconds(CLOCK_MONOTONIC) + int64_t{limits_.load_wall_cap_ms} * 1'000'000;
  for (;;) {
    p::ForkReply reply;
    ssize_t got;
    do {
      got = recv(channel_.get(), &reply, sizeof(reply), MSG_DONTWAIT | MSG_TRUNC);
    } while (got < 0 && errno == EINTR);
    if (got == static_cast<ssize_t>(sizeof(reply)) && reply.magic == p::kForkMagic) {
      if (reply.pid > 0) {
        pid = reply.pid;
        return Copy::kMade;
      }
      error = reply.error;
      return Copy::kRefused;
    }
    const int64_t left = deadline - Nanoseconds(CLOCK_MONOTONIC);
    if (got >= 0 || (errno != EAGAIN && errno != EWOULDBLOCK) || left <= 0) break;  // hung up, malformed, or late
    const timespec timeout{static_cast<time_t>(left / 1'000'000'000), static_cast<long>(left % 1'000'000'000)};
    pollfd fds[2] = {{channel_.get(), POLLIN, 0}, {child_.pidfd(), POLLIN, 0}};
    const int ready = ppoll(fds, child_.pidfd() >= 0 ? 2 : 1, &timeout, nullptr);
    if (ready > 0 && (fds[0].revents & POLLIN) == 0 && (fds[1].revents & POLLIN) != 0) break;  // it ended
  }
  KillAndReap();
  SetFault(Verdict::kCrashed, "the held host ended");
  return Copy::kGone;
}

}  // namespace syrof::app_host
