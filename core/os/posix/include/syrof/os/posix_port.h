// The POSIX port: each task on its own thread, timed by the monotonic clock.
// For robots that run as host processes (DDS, software in the loop). Host only.
#pragma once

#include <chrono>
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
  /// not shift later ones. A step so late that further grid points have
  /// passed (the process was stopped) runs once and the passed points are
  /// skipped: no burst of stale activations. Returns kSystemError if a thread
  /// cannot start.
  PortError Start() override;
  /// Start() with the periodic grid anchored at `origin_ns` (port time, may
  /// be in the past or the future): a task's activations are at origin +
  /// offset + k * period for the whole k that are not before now. Robots
  /// started at different moments share a grid this way when they are given
  /// the same origin (the DDS world publishes one; MonotonicToPort converts
  /// it). The origin may be before the port existed (negative: a process
  /// started after the run began, a joiner): the grid is the same.
  PortError StartAt(int64_t origin_ns);
  /// Wakes every thread, lets steps in progress finish, joins the threads.
  PortError Stop() override;
  void Notify(TaskId task) override;
  /// Nanoseconds of the monotonic clock since the port was constructed.
  int64_t now_ns() const override;
  /// Moves a periodic task's next activation by `delta_ns`, never before now
  /// (port.h). From any thread: from the task's own step it moves the
  /// activation after the step; a waiting thread re-waits for the new time.
  /// Before Start it does nothing (kOk).
  PortError ShiftPeriodic(TaskId task, int64_t delta_ns) override;
  /// Port time of a CLOCK_MONOTONIC reading (ns; steady_clock is
  /// CLOCK_MONOTONIC on Linux), and back: every process on one host reads
  /// the same monotonic clock, so this is how a grid origin crosses processes.
  int64_t MonotonicToPort(int64_t monotonic_ns) const;
  int64_t PortToMonotonic(int64_t port_ns) const;
  /// The current CLOCK_MONOTONIC reading in ns.
  static int64_t MonotonicNowNs();
  void Lock() override { critical_.lock(); }
  void Unlock() override { critical_.unlock(); }

 private:
  struct Worker;
  PortError StartFrom(std::chrono::steady_clock::time_point origin, bool skip_past);
  void RunPeriodic(Worker& worker);
  void RunNotified(Worker& worker);

  PosixPortOptions options_;
  std::chrono::steady_clock::time_point epoch_;
  std::mutex state_mutex_;  // guards running_ and every Worker::pending
  bool running_ = false;
  std::mutex critical_;
  std::vector<std::unique_ptr<Worker>> workers_;
};

}  // namespace syrof::os
