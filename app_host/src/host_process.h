// The parent's side of one syrof-app-host process: spawn, the hello, one
// call at a time under a CPU budget and a wall cap, the robot's log, and the
// verdict when anything goes wrong (docs/app_host.md).
#pragma once

#include <sys/types.h>
#include <time.h>

#include <cstdint>
#include <functional>
#include <string>
#include <vector>

#include "protocol.h"
#include "syrof/app/call_status.h"
#include "syrof/app_host/hosted_app.h"
#include "syrof/process/fd.h"
#include "syrof/process/spawn.h"

namespace syrof::app_host {

class LoadedLibrary;

class HostProcess {
 public:
  /// kHold: the fork server's held host (docs/app_host.md "The fork
  /// server"): no log, its output kept in `load_output()` instead.
  enum class Mode { kRun, kCheck, kHold };

  HostProcess() = default;
  /// Kills the host if it still runs, reaps it, closes the log.
  ~HostProcess();
  HostProcess(const HostProcess&) = delete;
  HostProcess& operator=(const HostProcess&) = delete;

  /// Starts the host and waits for its hello (load_wall_cap_ms). A fault
  /// (load_failed, bad_abi, crashed during load, ...) is returned and kept;
  /// `full_detail()` then holds the whole text (CallStatus keeps 47 bytes).
  app::CallStatus Start(const HostOptions& options, uint16_t robot_id, Mode mode);

  /// Start's first half: the host is spawned and loads on its own while the
  /// caller goes on (the lab starts every robot's host before the first
  /// Init, so they load side by side); the first Call waits for the hello.
  /// The load wall cap counts from when that wait begins.
  app::CallStatus Spawn(const HostOptions& options, uint16_t robot_id, Mode mode);

  /// Spawn for a copy of `library`'s held host: the copy is asked of the
  /// held host, adopted as this process's child, and begins its log with
  /// what the library printed while it loaded (as a fresh host's log
  /// would). A fresh host (Spawn) when `library` no longer holds.
  app::CallStatus SpawnCopy(const HostOptions& options, uint16_t robot_id, LoadedLibrary& library);

  /// A held host's side of a copy: sends the copy's two descriptors and
  /// waits (load wall cap) for its pid. kGone: the held host ended or did
  /// not answer (it is then killed and reaped); kRefused: its clone
  /// failed (`error`).
  enum class Copy { kMade, kGone, kRefused };
  Copy MakeCopy(int child_channel, int child_output, pid_t& pid, int& error);

  /// What the host wrote while it loaded (kHold): the kept bytes (at most
  /// log_keep_bytes) and how many there were in all.
  const std::string& load_output() const { return captured_; }
  uint64_t output_bytes() const { return output_bytes_; }

  /// Start's second half (Call does it when needed).
  app::CallStatus AwaitHello(protocol::Reply& hello);

  /// AwaitHello unless done: the app's name is known after it.
  void EnsureStarted() {
    protocol::Reply hello;
    if (!started_ && !faulted_) (void)AwaitHello(hello);
  }

  /// The fault so far (ok while none).
  const app::CallStatus& fault() const { return fault_; }

  /// One callback: sends `request` (a RequestHeader and its members), hands
  /// each sendMessageData call of the app to `on_call` in order, and fills
  /// `done` with the final reply. A fault ends the process; every later call
  /// returns the same fault.
  app::CallStatus Call(const void* request, size_t size, uint32_t sequence,
                       const std::function<void(const protocol::PayloadCall&)>& on_call, protocol::Reply& done);

  const std::string& app_name() const { return app_name_; }
  uint32_t notes() const { return notes_; }
  const std::string& full_detail() const { return full_detail_; }
  pid_t pid() const { return child_.reaped() ? -1 : child_.pid(); }

 private:
  enum class Wait { kMessage, kFault };
  // Waits for the next reply under the caps, draining the output. `load` is
  // the start-up wait (wall cap only, "during load" in details).
  Wait WaitForReply(protocol::Reply& reply, bool load);
  Wait Accept(protocol::Reply& reply, bool malformed, bool load);
  // Reads one pending reply if there is one; false if none. Sets a bad_abi
  // fault for a malformed message.
  bool TryReceive(protocol::Reply& reply, bool& malformed);
  // Moves what the host wrote to the log; false past the output limit.
  bool DrainOutput();
  void SetFault(app::Verdict verdict, const std::string& detail);
  // The fault of a process that ended (reaps it).
  void FaultFromExit(bool load);
  void KillAndReap();
  void FinishLog();
  // The log file (options.log_directory) and the channel and output pipe;
  // false (a fault set) when they cannot be made.
  bool OpenPipes(const HostOptions& options, uint16_t robot_id, process::Fd& child_channel,
                 process::Fd& child_output);
  // Opens the host's /proc/PID/stat, whose utime the CPU budget counts, for
  // a spawned host and a copy alike.
  void OpenCpuStat();

  HostLimits limits_;
  process::Child child_;
  process::Fd channel_;
  process::Fd output_;
  process::Fd log_;
  process::Fd cpu_stat_;  // the host's /proc/PID/stat: its user CPU time
  bool have_cpu_clock_ = false;
  uint64_t output_bytes_ = 0;
  uint64_t log_written_ = 0;
  bool faulted_ = false;
  bool output_open_ = true;  // false once the host's output pipe hung up
  bool started_ = false;   // the hello was awaited
  app::CallStatus fault_;
  std::string full_detail_;
  std::string app_name_;
  std::string library_path_;
  uint32_t notes_ = 0;
  bool capture_ = false;   // kHold: output kept in captured_, no log
  std::string captured_;
};

}  // namespace syrof::app_host
