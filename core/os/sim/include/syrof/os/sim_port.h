// The simulation port: tasks of many robots driven by one deterministic
// discrete-event scheduler in virtual time.
//
// One SimScheduler holds the virtual clock of a whole simulated world; each
// robot has its own SimPort on it. Steps take no virtual time. Ordering is
// total and documented, so two runs of the same program give the same trace:
//   1. earlier activation time first;
//   2. at the same instant, higher task priority first;
//   3. then the task registered first on the scheduler (across all ports).
// A notification raised during a step schedules the notified task at the
// current instant; it runs after the current step returns (run to
// completion), in the same order as above.
//
// A port may have its own drifting clock (SetDriftPpb, the lab's clocks,
// docs/clocks.md): its now_ns() and its tasks' `now_ns` read local time,
// local(t) = t + floor(t * drift_ppb / 1e9) for the scheduler's time t, and
// its periodic tasks keep their grid in local time (each activation runs at
// the first scheduler instant whose local time has reached it). Without
// drift local time is the scheduler's time.
//
// Batches (set_batch_runner): activations due at the same instant with the
// same priority on different ports may be handed to a SimBatchRunner all at
// once, which may run them in any order or at the same time (the lab's
// `--threads`). The scheduler itself stays single-threaded: it takes the
// whole batch off the queue before the runner starts, and what the batch's
// steps ask of it (Notify, ShiftPeriodic, Stop) waits in each port until the
// batch ends, then takes effect in the batch's order.
#pragma once

#include <cstddef>
#include <cstdint>
#include <span>
#include <vector>

#include "syrof/base/state_digest.h"
#include "syrof/os/port.h"

namespace syrof::os {

class SimPort;

/// Receives every step the scheduler runs, in order (for traces and tests).
class SimTraceSink {
 public:
  virtual void OnStep(int64_t time_ns, const SimPort& port, TaskId task, const TaskConfig& config) = 0;

 protected:
  ~SimTraceSink() = default;
};

/// One step of a batch: what SimScheduler::RunNext would have run.
struct SimStep {
  Task* task;
  const SimPort* port;
  int64_t now_ns;       ///< what Task::Step is told (the port's local time)
  uint32_t port_index;  ///< port->index(), at hand without touching the port
};

/// Runs the steps of one batch (SimScheduler::set_batch_runner).
class SimBatchRunner {
 public:
  /// Must call `task->Step(now_ns)` of every step exactly once and return
  /// when all have returned. `steps` are on different ports, in the order a
  /// one-at-a-time run takes them; the runner may reorder them or run them
  /// at the same time, as long as what each step touches besides its own
  /// port is made safe by the runner.
  virtual void RunBatch(std::span<const SimStep> steps) = 0;

 protected:
  ~SimBatchRunner() = default;
};

/// The virtual clock and event queue shared by every SimPort of a world.
class SimScheduler {
 public:
  /// Reserves room for `max_tasks` tasks over all ports; nothing is allocated
  /// after construction.
  explicit SimScheduler(size_t max_tasks);
  SimScheduler(const SimScheduler&) = delete;
  SimScheduler& operator=(const SimScheduler&) = delete;

  /// Virtual time in nanoseconds since the scheduler was created.
  int64_t now_ns() const { return now_ns_; }

  /// Runs the earliest pending activation. Returns false if none is pending.
  bool RunNext();

  /// Runs every activation due at or before `end_ns` (including those that
  /// steps schedule on the way), then advances the clock to `end_ns`.
  void RunUntil(int64_t end_ns);

  /// RunUntil(now_ns() + duration_ns).
  void RunFor(int64_t duration_ns) { RunUntil(now_ns_ + duration_ns); }

  /// Time of the earliest pending activation, or -1 if none is pending.
  int64_t next_activation_ns() const;

  /// Number of steps run so far.
  uint64_t steps_run() const { return steps_run_; }

  /// Installs (or, with nullptr, removes) a sink that sees every step.
  void set_trace(SimTraceSink* sink) { trace_ = sink; }

  /// Installs (or, with nullptr, removes) a runner for batches. From then
  /// on, when the earliest two activations are due at the same instant with
  /// the same priority on different ports, RunNext() takes all activations
  /// due then with that priority (in the order above, up to the first that
  /// repeats a port) and hands them to `runner` at once; never while a
  /// trace sink is installed.
  /// During a batch, a step's Notify, ShiftPeriodic and Stop take effect
  /// when the batch ends, port by port in the batch's order, which gives the
  /// same queue as running the steps one at a time, unless a step raised an
  /// activation due at this instant that would have run before a later step
  /// of the batch: that stops the program (SYROF_CHECK), so batch only tasks
  /// that raise none. Start() during a batch is refused the same way.
  void set_batch_runner(SimBatchRunner* runner) { batch_runner_ = runner; }

  /// Batches handed to the runner so far (each counts its steps in steps_run()).
  uint64_t batches_run() const { return batches_run_; }

  /// Lets the step running now (a world task's, not a batch) step parts of
  /// other ports' software side by side, as a batch's steps are run: from
  /// BeginSideBySide to EndSideBySide, a Notify, ShiftPeriodic or Stop on
  /// one of `ports` waits, and EndSideBySide applies them port by port in
  /// `ports`' order, which gives the same queue as making them one at a
  /// time (what they raise runs after the current step either way). The
  /// lab's simulated sensors publish to every robot's broker this way on
  /// `--threads`. No other port may be touched in between, and `ports`
  /// (distinct) must stay valid until EndSideBySide.
  void BeginSideBySide(std::span<SimPort* const> ports);
  void EndSideBySide();

  /// The queue into `digest` (base/state_digest.h): each task's next
  /// activation, if any, and whether its port runs. Between steps only.
  void AddToDigest(base::StateDigest& digest) const;

 private:
  friend class SimPort;

  struct TaskRecord {
    Task* task;
    SimPort* port;
    TaskConfig config;
    TaskId local_id;
    bool pending;  // has a pending activation (in a run of the heap)
    int64_t local_due_ns;  // periodic: the pending activation, in the port's local time
    uint32_t next_in_run;  // the next task of its run, or kNoTask
  };
  static constexpr uint32_t kNoTask = UINT32_MAX;
  // Ordered by (time_ns, order): order packs "higher priority first, then
  // earlier registration" into one integer, so a comparison is two; 16
  // bytes, the task index read from the order's low half.
  //
  // A heap entry is a run: tasks due at one time with one priority, linked
  // through TaskRecord::next_in_run in increasing task index; its key is its
  // first task's activation. Taking the front takes the front run's first
  // task, so the heap merges the sorted runs and steps keep the documented
  // order whatever the runs. Why runs: every robot's periodic tasks fall due
  // together, and a periodic task queued right after the one before it (at
  // the same time and priority, a higher index) joins that task's run with
  // no sift, while the front run's next task mostly stays in front with none;
  // so do a sensor's notifications of every robot's task.
  struct Activation {
    int64_t time_ns;
    uint64_t order;  // (255 - priority) << 32 | task_index (into tasks_): the run's first task
    uint32_t task_index() const { return static_cast<uint32_t>(order); }
  };

  base::Result<uint32_t, PortError> RegisterTask(SimPort& port, Task& task, const TaskConfig& config,
                                                  TaskId local_id);
  void Schedule(uint32_t task_index, int64_t time_ns);
  Activation MakeActivation(uint32_t task_index, int64_t time_ns) const;
  // A min-heap of runs on their keys (time_ns, order). Each task has at most
  // one activation and order is unique per task, so any heap pops the same
  // sequence (the arity, kHeapArity in sim_port.cpp, is 2: a 4-ary heap ran
  // 20% more instructions at 100 robots).
  void SiftUp(size_t position);
  void SiftDown(size_t position);
  // Sifts the run at `position` up or down after its key changed.
  void Restore(size_t position);
  void CancelPort(const SimPort& port);
  // Moves task_index's pending activation to time_ns (it must be pending).
  void Reschedule(uint32_t task_index, int64_t time_ns);
  // A run that activations may still join: the run of the activation
  // queued last by one path, while that activation is its last task.
  struct OpenRun {
    bool open = false;
    Activation last{};  // the run's last task's activation
    // Whether `activation` may follow `last` in the run: same time, same
    // priority, higher task index.
    bool Takes(const Activation& activation) const;
  };
  // Queues `activation` at the end of `run` if it takes it, else as a run of
  // its own, which becomes `run`.
  void Queue(const Activation& activation, OpenRun& run);
  // Queues `activation` as a run of its own.
  void PushActivation(const Activation& activation);
  // Closes the open runs that end with the task (it leaves its run).
  void CloseRunsEndingWith(uint32_t task_index);
  // Takes the earliest activation off the queue (queueing a periodic task's
  // next one) and returns its task index; `step_now_ns` is what Step is told.
  uint32_t TakeFront(int64_t& step_now_ns);
  // Whether the earliest two activations are due together at one priority.
  bool BatchAhead() const;
  void RunBatch();
  // Applies what batch_ports_ asked for during a batch (or side by side),
  // in their order; `last_order`: the order of a batch's last step, which
  // nothing due now may precede (none for side by side).
  void ApplyDeferred(const uint64_t* last_order);

  size_t max_tasks_;
  std::vector<TaskRecord> tasks_;
  std::vector<Activation> heap_;  // runs; at most one per pending task
  OpenRun requeued_run_;  // periodic tasks' next activations (TakeFront)
  OpenRun scheduled_run_;  // notifications and starts (Schedule)
  int64_t now_ns_ = 0;
  uint64_t steps_run_ = 0;
  SimTraceSink* trace_ = nullptr;
  uint32_t ports_ = 0;  // SimPorts built on this scheduler
  // Batches.
  SimBatchRunner* batch_runner_ = nullptr;
  bool in_batch_ = false;  // a batch or side by side: Notify, ShiftPeriodic and Stop wait
  uint64_t batches_run_ = 0;
  uint64_t batch_mark_ = 0;  // the current batch's (or side by side's) number, over both kinds
  std::vector<uint32_t> batch_;     // task indices, in queue order
  std::vector<SimStep> batch_steps_;
  std::vector<SimPort*> batch_ports_;  // the ports of batch_ (or side by side), in order
  // Per position of batch_ports_: 1 when that port deferred something (each
  // byte written by its own port's step only), so that ApplyDeferred need
  // not touch the others.
  std::vector<uint8_t> batch_deferred_;
  // Adds a port to batch_ports_ under the current batch mark.
  void JoinBatch(SimPort& port);
};

/// One robot's port on a SimScheduler. Single-threaded: Lock() only checks
/// that critical sections do not nest.
class SimPort final : public Port {
 public:
  /// `name` labels the port in traces; it must outlive the port.
  explicit SimPort(SimScheduler& scheduler, const char* name = "");
  SimPort(const SimPort&) = delete;
  SimPort& operator=(const SimPort&) = delete;

  base::Result<TaskId, PortError> AddTask(Task& task, const TaskConfig& config) override;
  /// Schedules periodic tasks at now + offset. A stopped port may be started
  /// again (a robot that pauses and resumes).
  PortError Start() override;
  /// Start() with every periodic task's first activation `delay_ns` (local
  /// time, >= 0) later: a robot that boots part of a round after another.
  PortError StartAfter(int64_t delay_ns);
  /// Drops every pending activation of this port (a robot that crashes or
  /// pauses). Other ports are unaffected.
  PortError Stop() override;
  void Notify(TaskId task) override;
  /// The port's local time (the scheduler's without drift).
  int64_t now_ns() const override { return LocalFromTrue(scheduler_.now_ns()); }
  PortError ShiftPeriodic(TaskId task, int64_t delta_ns) override;

  /// The clock's rate error in parts per billion (|ppb| < 10^8); set before
  /// the first Start. 0: the scheduler's clock.
  void SetDriftPpb(int32_t drift_ppb);
  int32_t drift_ppb() const { return drift_ppb_; }
  /// Local time at scheduler time `true_ns` (>= 0).
  int64_t LocalFromTrue(int64_t true_ns) const;
  /// The first scheduler time whose local time is at least `local_ns`.
  int64_t TrueFromLocal(int64_t local_ns) const;
  void Lock() override;
  void Unlock() override;

  const char* name() const { return name_; }
  bool running() const { return running_; }
  size_t task_count() const { return task_indices_.size(); }
  /// The port's number on its scheduler: 0, 1, ... in construction order.
  uint32_t index() const { return index_; }

 private:
  friend class SimScheduler;

  // A Notify or ShiftPeriodic made during a batch (SimScheduler::RunBatch).
  struct Deferred {
    uint32_t task_index;
    int64_t time_ns;
    bool reschedule;  // ShiftPeriodic; otherwise a notification
  };
  void Defer(uint32_t task_index, int64_t time_ns, bool reschedule);

  SimScheduler& scheduler_;
  const char* name_;
  uint32_t index_;
  std::vector<uint32_t> task_indices_;  // local TaskId -> scheduler task index
  bool running_ = false;
  bool locked_ = false;
  int32_t drift_ppb_ = 0;
  // Written only by this port's own step during a batch; read after it.
  std::vector<Deferred> deferred_;  // room for two per task, reserved by AddTask
  bool stop_deferred_ = false;
  uint64_t batch_mark_ = 0;  // the batch (or side by side) this port was last in (SimScheduler::batch_mark_)
  uint32_t batch_position_ = 0;  // its place in SimScheduler::batch_ports_ then
};

}  // namespace syrof::os
