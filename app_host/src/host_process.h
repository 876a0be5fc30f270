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

class HostProcess {
 public:
  enum class Mode { kRun, kCheck };

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
};

}  // namespace syrof::app_host
