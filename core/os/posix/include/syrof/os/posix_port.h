// The POSIX port: each task on its own thread, timed by the monotonic clock.
// For robots that run as host processes (DDS, software in the loop). Host only.
#pragma once

#include <condition_variable>
#include <cstddef>
#include <memory>
#include <mutex>
#include <thread>
#include <vector>

#include "syrof/os/port.h"

namespace syrof::os {

struct PosixPortOptions {
  size_t max_tasks = 32;
  /// Ask for SCHED_FIFO with the task's priority (needs CAP_SYS_NICE; when
  /// refused, the thread keeps the default policy). Off by default so that
  /// tests and desktop runs never starve the machine.
  bool realtime_priorities = false;
};

class PosixPort final : public Port {
 public:
  explicit PosixPort(PosixPortOptions options = {});
  /// Stops the port (if running) and joins every thread.
  ~PosixPort();
  PosixPort(const PosixPort&) = delete;
  PosixPort& operator=(const PosixPort&) = delete;

  base::Result<TaskId, PortError> AddTask(Task& task, const TaskConfig& config) override;
  /// Starts one thread per task. Periodic activations are absolute
  /// (start + offset + k * period, like vTaskDelayUntil): a late step does
  /// not shift later ones. Returns kSystemError if a thread cannot start.
  PortError Start() override;
  /// Wakes every thread, lets steps in progress finish, joins the threads.
  PortError Stop() override;
  void Notify(TaskId task) override;
  /// Nanoseconds of the monotonic clock since the port was constructed.
  int64_t now_ns() const override;
  void Lock() override { critical_.lock(); }
  void Unlock() override { critical_.unlock(); }

 private:
  struct Worker;
  void RunPeriodic(Worker& worker);
  void RunNotified(Worker& worker);

  PosixPortOptions options_;
  std::chrono::steady_clock::time_point epoch_;
  std::mutex state_mutex_;  // guards running_ and every Worker::pending
  bool running_ = false;
  std::chrono::steady_clock::time_point started_;  // written before threads start
  std::mutex critical_;
  std::vector<std::unique_ptr<Worker>> workers_;
};

}  // namespace syrof::os
