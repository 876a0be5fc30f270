// The OS port: how robot code runs on an operating system without knowing
// which one.
//
// Robot software is a set of tasks. A task is a run-to-completion step with a
// declared trigger: a period (the paper's vTaskDelayUntil loops) or a
// notification (the paper's xTaskNotifyWait loops, raised by the broker when
// data arrives on a subscribed topic). A port runs the steps:
//   - SimPort (core/os/sim): a deterministic discrete-event scheduler in
//     virtual time, for the simulated lab and tests;
//   - PosixPort (core/os/posix): one thread per task and the monotonic clock,
//     for robots running as processes;
//   - NvicPort (firmware/kernel), a kernel on the NVIC, for the Teensy 3.2.
// Code above the port (broker, estimator, synchronizer, app) sees only this
// header, so it cannot tell which runtime it runs in.
#pragma once

#include <cstdint>

#include "syrof/base/result.h"

namespace syrof::os {

/// Identifies a task within one port; assigned by Port::add_task in
/// registration order, starting at 0.
using TaskId = uint16_t;

enum class TriggerKind : uint8_t {
  kPeriodic,  ///< activated every period_ns, at start + offset_ns + k * period_ns
  kNotified,  ///< activated by Port::notify; notifications before the step runs coalesce
};

/// When a task's step runs.
struct Trigger {
  TriggerKind kind = TriggerKind::kNotified;
  int64_t period_ns = 0;  ///< kPeriodic: > 0
  int64_t offset_ns = 0;  ///< kPeriodic: first activation this long after start, >= 0

  static constexpr Trigger periodic(int64_t period_ns, int64_t offset_ns = 0) {
    return Trigger{TriggerKind::kPeriodic, period_ns, offset_ns};
  }
  static constexpr Trigger notified() { return Trigger{TriggerKind::kNotified, 0, 0}; }
};

/// How a task is declared to a port.
struct TaskConfig {
  const char* name = "";  ///< for traces and logs; must outlive the port
  Trigger trigger;
  /// Higher runs first when several tasks are ready at the same instant
  /// (SimPort), or preempts lower (real-time ports).
  uint8_t priority = 0;
};

/// A run-to-completion step. step() must return in bounded time and must not
/// block; it may publish, notify and read the clock.
class Task {
 public:
  /// Runs one activation. `now_ns` is the port's clock at activation, in
  /// nanoseconds since the port's epoch (virtual time on SimPort): for a
  /// periodic task its release on the grid, which a real-time port's thread
  /// may run a little after (now_ns() then reads later).
  virtual void Step(int64_t now_ns) = 0;

 protected:
  ~Task() = default;
};

enum class [[nodiscard]] PortError : uint8_t {
  kOk = 0,
  kTooManyTasks,      ///< the port's fixed task capacity is exhausted
  kInvalidTrigger,    ///< period <= 0 or offset < 0 for a periodic task
  kAlreadyStarted,    ///< add_task or start after Start()
  kNotStarted,        ///< Stop() before Start()
  kSystemError,       ///< the host refused a thread or clock (PosixPort only)
  kUnsupported,       ///< the port cannot do this (ShiftPeriodic on a port without it)
};

/// A short, stable name for logs and tests.
const char* ToString(PortError error);

/// The port interface. Lifecycle: add every task, then Start(); tasks run
/// until Stop(). Task objects must outlive the port's use of them.
class Port {
 public:
  /// Declares a task. Only before Start(). Returns the task's id.
  virtual base::Result<TaskId, PortError> AddTask(Task& task, const TaskConfig& config) = 0;

  /// Starts activating tasks: periodic tasks at start + offset, notified
  /// tasks when notified.
  virtual PortError Start() = 0;

  /// Stops activating tasks. A step in progress completes first. Pending
  /// activations are dropped.
  virtual PortError Stop() = 0;

  /// Wakes a notified task. Safe to call from any task (and, on threaded
  /// ports, any thread). Notifying a task that is already pending does
  /// nothing more: the step will see all data published before it runs.
  /// Notifying a periodic task or an unknown id is ignored.
  virtual void Notify(TaskId task) = 0;

  /// The port's clock in nanoseconds since its epoch (monotonic).
  virtual int64_t now_ns() const = 0;

  /// Moves a periodic task's grid by `delta_ns` (later when positive) from
  /// its next activation on; the period stays. Round alignment
  /// (sync/round_alignment.h) moves the round task's boundary this way. The
  /// next activation never moves before now. Call it from a task of this
  /// port. kInvalidTrigger for a notified task or an unknown id;
  /// kUnsupported on a port that cannot (the default).
  virtual PortError ShiftPeriodic(TaskId /*task*/, int64_t /*delta_ns*/) { return PortError::kUnsupported; }

  /// A short critical section that excludes every other task of this port
  /// (used by the broker around queue copies). Not recursive.
  virtual void Lock() = 0;
  virtual void Unlock() = 0;

 protected:
  ~Port() = default;
};

/// Holds a port's critical section for a scope.
class CriticalSection {
 public:
  explicit CriticalSection(Port& port) : port_(port) { port_.Lock(); }
  ~CriticalSection() { port_.Unlock(); }
  CriticalSection(const CriticalSection&) = delete;
  CriticalSection& operator=(const CriticalSection&) = delete;

 private:
  Port& port_;
};

/// Validates a task's trigger; shared by every port implementation.
PortError Validate(const Trigger& trigger);

}  // namespace syrof::os
