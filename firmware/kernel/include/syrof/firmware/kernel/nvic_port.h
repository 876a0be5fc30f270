// NvicPort: the firmware's os::Port, a preemptive run-to-completion kernel on
// the Cortex-M NVIC (the design RTIC and QP's QK use; written for SyROF).
//
// Every task priority is an interrupt level. A level's interrupt, pended in
// software, runs that level's ready tasks to completion in registration
// order, then returns; a higher level preempts a lower one in the middle of a
// step, and the lower one resumes where it was, on the same stack. A timer
// interrupt above every level releases periodic tasks at absolute instants
// (start + offset + k * period; a late interrupt catches up from the clock,
// so releases never drift). Notify marks a task ready and pends its level;
// notifications before the step starts coalesce. Lock() masks the timer and
// every level (BASEPRI on the M4). No heap, and every call is bounded by
// kMaxTasks.
//
// A periodic task that is still ready or running at its next release missed
// its deadline: the release is counted as an overrun (overruns()) and does
// not queue a second step; the task runs once, then keeps the grid.
//
// Usage (the board wires its interrupts to RunLevel and OnTimer):
//   Mps2An386Hardware hardware;          // NVIC, BASEPRI, CMSDK timers
//   NvicPort port(hardware);
//   hardware.Attach(port);
//   port.AddTask(sensor, {"imu", Trigger::periodic(2'000'000), 6});
//   port.Start();
//   for (;;) wait_for_interrupt();       // thread mode idles
#pragma once

#include <array>
#include <cstdint>

#include "syrof/base/result.h"
#include "syrof/firmware/kernel/hardware.h"
#include "syrof/os/port.h"

namespace syrof::firmware::kernel {

/// Most tasks one port holds (the ready sets are 32-bit masks).
inline constexpr uint16_t kMaxTasks = 32;

class NvicPort final : public os::Port {
 public:
  /// `hardware` must outlive the port; `max_tasks` (at most kMaxTasks) is
  /// the port's task capacity.
  explicit NvicPort(KernelHardware& hardware, uint16_t max_tasks = kMaxTasks);
  NvicPort(const NvicPort&) = delete;
  NvicPort& operator=(const NvicPort&) = delete;

  /// Tasks added from now on with `priority` run at interrupt level `level`
  /// (by default a task's level is its priority). A board whose schedule
  /// needs another order than the registry's data flow (docs/firmware.md,
  /// "Utilisation and response times") maps it here; kAlreadyStarted after
  /// Start, kUnsupported for a priority or level >= kLevelCount.
  os::PortError MapPriority(uint8_t priority, uint8_t level);
  /// As os::Port; also kUnsupported when config.priority >= kLevelCount.
  base::Result<os::TaskId, os::PortError> AddTask(os::Task& task, const os::TaskConfig& config) override;
  /// Releases each periodic task first at now + offset.
  os::PortError Start() override;
  /// As Start(), but the grid begins at `start_ns` (<= now, the clock's
  /// time of an event already past): each periodic task is released first
  /// at start_ns + offset, at once when that has passed. kUnsupported for
  /// a start_ns after now; a negative start_ns is now (Start()).
  os::PortError StartAt(int64_t start_ns);
  /// Drops ready tasks and the release calendar; a step in progress
  /// completes. Start() again begins a new grid from that instant.
  os::PortError Stop() override;
  /// Safe from any task and from interrupts whose priority the kernel mask
  /// covers (at or below the timer's).
  void Notify(os::TaskId task) override;
  int64_t now_ns() const override;
  /// Moves the task's release grid by delta_ns from its next release on,
  /// never before now.
  os::PortError ShiftPeriodic(os::TaskId task, int64_t delta_ns) override;
  /// Masks the timer and every level; not recursive.
  void Lock() override;
  void Unlock() override;

  // --- Called by the hardware's interrupt handlers. ---
  /// The level's interrupt: runs its ready tasks until none is left.
  void RunLevel(uint8_t level);
  /// The timer's interrupt: releases every periodic task that is due, pends
  /// their levels, and sets the alarm for the next release.
  void OnTimer();

  // --- Counters for tests, benchmarks and a health topic. ---
  /// Releases of `task` that found it still ready or running (deadline
  /// misses); 0 for notified tasks and unknown ids.
  uint32_t overruns(os::TaskId task) const;
  /// Sum of overruns() over every task.
  uint32_t total_overruns() const;
  /// Steps `task` has run.
  uint32_t steps(os::TaskId task) const;
  /// The next release of a periodic task (ns on now_ns()'s clock), -1 when
  /// stopped or for a notified task.
  int64_t next_release_ns(os::TaskId task) const;
  bool running() const { return started_; }
  /// Tasks added so far (ids 0 .. task_count() - 1).
  uint16_t task_count() const { return task_count_; }
  /// The name `task` was added with; "" for unknown ids.
  const char* task_name(os::TaskId task) const { return task < task_count_ ? tasks_[task].config.name : ""; }
  /// The interrupt level `task` runs at (its priority, unless mapped); 0 for unknown ids.
  uint8_t level(os::TaskId task) const { return task < task_count_ ? tasks_[task].level : 0; }

 private:
  struct TaskRecord {
    os::Task* task = nullptr;
    os::TaskConfig config;
    int64_t next_release_ns = -1;  ///< periodic, while started
    int64_t release_ns = -1;       ///< periodic: the grid instant of the pending activation (its step's now_ns)
    uint32_t overruns = 0;
    uint32_t steps = 0;
    bool in_step = false;
    uint8_t level = 0;  ///< the interrupt level it runs at
  };

  /// Earliest next release, or -1; kernel masked.
  int64_t EarliestRelease() const;

  KernelHardware& hardware_;
  std::array<TaskRecord, kMaxTasks> tasks_{};
  uint16_t task_count_ = 0;
  uint16_t max_tasks_;
  /// Bit t of ready_[level] is set when task t (of that level) is ready.
  std::array<uint32_t, kLevelCount> ready_{};
  std::array<uint8_t, kLevelCount> level_of_priority_{0, 1, 2, 3, 4, 5, 6, 7, 8, 9};
  uint32_t periodic_mask_ = 0;  ///< bit t set for periodic tasks
  bool started_ = false;
  uint32_t lock_saved_mask_ = 0;
  bool locked_ = false;
};

}  // namespace syrof::firmware::kernel
