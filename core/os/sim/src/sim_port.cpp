#include "syrof/os/sim_port.h"

#include <algorithm>
#include <cstddef>
#include <cstdint>
#include <vector>

#include "syrof/base/check.h"

namespace syrof::os {
namespace {

// Children per node of the activation heap (sim_port.h says why 2).
constexpr size_t kHeapArity = 2;

// The order's high half: the priority (inverted).
constexpr uint64_t kRankMask = ~uint64_t{UINT32_MAX};

// Whether `a` runs before `b`: earlier, then higher priority, then
// registered first (the order documented in sim_port.h).
template <typename Activation>
bool RunsFirst(const Activation& a, const Activation& b) {
  return a.time_ns < b.time_ns || (a.time_ns == b.time_ns && a.order < b.order);
}

}  // namespace

SimScheduler::SimScheduler(size_t max_tasks) : max_tasks_(max_tasks) {
  tasks_.reserve(max_tasks);
  heap_.reserve(max_tasks);
  batch_.reserve(max_tasks);
  batch_steps_.reserve(max_tasks);
  batch_ports_.reserve(max_tasks);
  batch_deferred_.reserve(max_tasks);
}

base::Result<uint32_t, PortError> SimScheduler::RegisterTask(SimPort& port, Task& task,
                                                             const TaskConfig& config, TaskId local_id) {
  if (tasks_.size() == max_tasks_) return PortError::kTooManyTasks;
  tasks_.push_back(TaskRecord{&task, &port, config, local_id, false, 0, kNoTask});
  return static_cast<uint32_t>(tasks_.size() - 1);
}

void SimScheduler::Schedule(uint32_t task_index, int64_t time_ns) {
  TaskRecord& record = tasks_[task_index];
  SYROF_CHECK(!record.pending);
  record.pending = true;
  Queue(MakeActivation(task_index, time_ns), scheduled_run_);
}

void SimScheduler::PushActivation(const Activation& activation) {
  // Each run holds at least one pending activation, each task at most one,
  // and heap_ has room for one per task, so this never reallocates.
  SYROF_CHECK(heap_.size() < max_tasks_);
  heap_.push_back(activation);
  SiftUp(heap_.size() - 1);
}

bool SimScheduler::OpenRun::Takes(const Activation& activation) const {
  return open && activation.time_ns == last.time_ns && (activation.order & kRankMask) == (last.order & kRankMask) &&
         activation.order > last.order;
}

void SimScheduler::Queue(const Activation& activation, OpenRun& run) {
  if (run.Takes(activation)) {
    tasks_[run.last.task_index()].next_in_run = activation.task_index();
  } else {
    PushActivation(activation);
    run.open = true;
  }
  run.last = activation;
}

void SimScheduler::CloseRunsEndingWith(uint32_t task_index) {
  if (requeued_run_.last.task_index() == task_index) requeued_run_.open = false;
  if (scheduled_run_.last.task_index() == task_index) scheduled_run_.open = false;
}

void SimScheduler::AddToDigest(base::StateDigest& digest) const {
  SYROF_CHECK(!in_batch_);
  // By task, not by heap position: equal queues may be laid out apart.
  std::vector<int64_t> due(tasks_.size(), INT64_MIN);
  for (const Activation& run : heap_) {
    for (uint32_t index = run.task_index(); index != kNoTask; index = tasks_[index].next_in_run) {
      due[index] = run.time_ns;
    }
  }
  for (size_t i = 0; i < tasks_.size(); ++i) {
    digest.AddValue(due[i]);
    digest.AddValue(tasks_[i].local_due_ns);
    digest.AddValue(tasks_[i].port->running());
    digest.AddValue(tasks_[i].port->drift_ppb());
  }
}

void SimScheduler::CancelPort(const SimPort& port) {
  requeued_run_.open = false;
  scheduled_run_.open = false;
  // Unlinks the port's tasks from every run, keeping the others in order;
  // a run left empty leaves the heap.
  size_t kept = 0;
  for (const Activation& run : heap_) {
    uint32_t first = kNoTask;
    uint32_t* link = &first;
    for (uint32_t index = run.task_index(); index != kNoTask;) {
      TaskRecord& record = tasks_[index];
      const uint32_t next = record.next_in_run;
      if (record.port == &port) {
        record.pending = false;
        record.next_in_run = kNoTask;
      } else {
        *link = index;
        link = &record.next_in_run;
      }
      index = next;
    }
    *link = kNoTask;
    if (first != kNoTask) heap_[kept++] = Activation{run.time_ns, (run.order & kRankMask) | first};
  }
  heap_.erase(heap_.begin() + static_cast<std::ptrdiff_t>(kept), heap_.end());
  for (size_t position = heap_.size() / kHeapArity + 1; position-- > 0;) {
    if (position < heap_.size()) SiftDown(position);
  }
}

int64_t SimScheduler::next_activation_ns() const { return heap_.empty() ? -1 : heap_.front().time_ns; }

bool SimScheduler::RunNext() {
  if (heap_.empty()) return false;
  if (batch_runner_ != nullptr && trace_ == nullptr && BatchAhead()) {
    RunBatch();
    return true;
  }
  int64_t step_now_ns = 0;
  TaskRecord& record = tasks_[TakeFront(step_now_ns)];
  ++steps_run_;
  if (trace_ != nullptr) trace_->OnStep(now_ns_, *record.port, record.local_id, record.config);
  record.task->Step(step_now_ns);
  return true;
}

// Inlined: RunNext runs it for every step, and a call costs 0.5% at 100 robots.
[[gnu::always_inline]] inline uint32_t SimScheduler::TakeFront(int64_t& step_now_ns) {
  const Activation activation = heap_.front();
  const uint32_t index = activation.task_index();
  TaskRecord& record = tasks_[index];
  SYROF_CHECK(activation.time_ns >= now_ns_);
  now_ns_ = activation.time_ns;
  CloseRunsEndingWith(index);

  // The front run's next task takes its place; it mostly still runs before
  // both children (the same run's next robot), and then needs no sift.
  const uint32_t next = record.next_in_run;
  record.next_in_run = kNoTask;
  bool front_empty = next == kNoTask;
  if (!front_empty) {
    Activation& front = heap_.front();
    front.order = (front.order & kRankMask) | next;
    const bool still_first = (heap_.size() < 2 || RunsFirst(front, heap_[1])) &&
                             (heap_.size() < 3 || RunsFirst(front, heap_[2]));
    if (!still_first) SiftDown(0);
  }

  // The next periodic activation is due one period after this one was due
  // (vTaskDelayUntil semantics), and is queued before the step runs so that a
  // step which stops its own port also cancels it. It joins the run that the
  // previous periodic step's next activation went to when it may (no sift),
  // else takes the place of an emptied front run (one sift instead of a
  // removal and an insertion), else is pushed.
  // A periodic step is told the local time it was due (the first scheduler
  // instant at or after it may read a nanosecond later on a drifting clock).
  step_now_ns = record.port->now_ns();
  if (record.config.trigger.kind == TriggerKind::kPeriodic) {
    step_now_ns = record.local_due_ns;
    record.local_due_ns += record.config.trigger.period_ns;
    const Activation again = MakeActivation(index, record.port->TrueFromLocal(record.local_due_ns));
    if (front_empty && !requeued_run_.Takes(again)) {
      heap_.front() = again;
      SiftDown(0);
      front_empty = false;
      requeued_run_ = OpenRun{true, again};
    } else {
      Queue(again, requeued_run_);
    }
  } else {
    record.pending = false;
  }
  if (front_empty) {
    heap_.front() = heap_.back();
    heap_.pop_back();
    if (!heap_.empty()) SiftDown(0);
  }
  return index;
}

// Due together: the second activation in order (the front run's next task,
// else the earlier child's first) has the front's time and priority (the
// order's high half) and another port.
bool SimScheduler::BatchAhead() const {
  const Activation& front = heap_.front();
  const TaskRecord& first = tasks_[front.task_index()];
  if (first.next_in_run != kNoTask) return tasks_[first.next_in_run].port != first.port;
  if (heap_.size() < 2) return false;
  size_t child = 1;
  if (heap_.size() > 2 && RunsFirst(heap_[2], heap_[1])) child = 2;
  const Activation& other = heap_[child];
  return other.time_ns == front.time_ns && (other.order & kRankMask) == (front.order & kRankMask) &&
         tasks_[other.task_index()].port != first.port;
}

void SimScheduler::RunBatch() {
  const int64_t time_ns = heap_.front().time_ns;
  const uint64_t rank = heap_.front().order >> 32;
  const uint64_t mark = ++batch_mark_;
  batch_.clear();
  batch_steps_.clear();
  batch_ports_.clear();
  batch_deferred_.clear();
  while (!heap_.empty() && heap_.front().time_ns == time_ns && (heap_.front().order >> 32) == rank) {
    SimPort& port = *tasks_[heap_.front().task_index()].port;
    if (port.batch_mark_ == mark) break;  // a port's steps never run side by side
    JoinBatch(port);
    int64_t step_now_ns = 0;
    const uint32_t index = TakeFront(step_now_ns);
    batch_.push_back(index);
    batch_steps_.push_back(SimStep{tasks_[index].task, &port, step_now_ns, port.index_});
  }
  ++batches_run_;
  steps_run_ += batch_.size();
  in_batch_ = true;
  batch_runner_->RunBatch(batch_steps_);
  in_batch_ = false;
  const uint64_t last_order = MakeActivation(batch_.back(), now_ns_).order;
  ApplyDeferred(&last_order);
}

void SimScheduler::BeginSideBySide(std::span<SimPort* const> ports) {
  SYROF_CHECK(!in_batch_);
  const uint64_t mark = ++batch_mark_;
  batch_ports_.clear();
  batch_deferred_.clear();
  for (SimPort* port : ports) {
    SYROF_CHECK(&port->scheduler_ == this && port->batch_mark_ != mark);
    JoinBatch(*port);
  }
  in_batch_ = true;
}

void SimScheduler::JoinBatch(SimPort& port) {
  port.batch_mark_ = batch_mark_;
  port.batch_position_ = static_cast<uint32_t>(batch_ports_.size());
  batch_ports_.push_back(&port);
  batch_deferred_.push_back(0);
}

void SimScheduler::EndSideBySide() {
  SYROF_CHECK(in_batch_);
  in_batch_ = false;
  ApplyDeferred(nullptr);
}

void SimScheduler::ApplyDeferred(const uint64_t* last_order) {
  for (size_t position = 0; position < batch_ports_.size(); ++position) {
    if (batch_deferred_[position] == 0) continue;
    SimPort& port = *batch_ports_[position];
    const bool last = position + 1 == batch_ports_.size();
    for (const SimPort::Deferred& deferred : port.deferred_) {
      // One at a time, an activation due now that orders before the batch's
      // last step would have run inside the batch (sim_port.h).
      SYROF_CHECK(last_order == nullptr || last || deferred.time_ns > now_ns_ ||
                  MakeActivation(deferred.task_index, now_ns_).order > *last_order);
      if (port.stop_deferred_) {
        if (!deferred.reschedule) tasks_[deferred.task_index].pending = false;  // never queued
      } else if (deferred.reschedule) {
        Reschedule(deferred.task_index, deferred.time_ns);
      } else {
        Queue(MakeActivation(deferred.task_index, deferred.time_ns), scheduled_run_);
      }
    }
    port.deferred_.clear();
    if (port.stop_deferred_) {
      port.stop_deferred_ = false;
      CancelPort(port);
    }
  }
}

SimScheduler::Activation SimScheduler::MakeActivation(uint32_t task_index, int64_t time_ns) const {
  const uint64_t rank = 255u - tasks_[task_index].config.priority;
  return Activation{time_ns, (rank << 32) | task_index};
}

void SimScheduler::SiftUp(size_t position) {
  const Activation moving = heap_[position];
  while (position > 0) {
    const size_t parent = (position - 1) / kHeapArity;
    if (!RunsFirst(moving, heap_[parent])) break;
    heap_[position] = heap_[parent];
    position = parent;
  }
  heap_[position] = moving;
}

// Bottom-up: the hole at `position` goes down to a leaf along the earlier
// child (one comparison a level), then the moving activation climbs back
// to its place (rarely far: a periodic task's next activation is late).
// Keys are unique, so this leaves the array exactly as the usual sift down
// (which compares the moving activation at every level too) would.
void SimScheduler::SiftDown(size_t position) {
  const Activation moving = heap_[position];
  const size_t size = heap_.size();
  size_t hole = position;
  for (;;) {
    const size_t first_child = kHeapArity * hole + 1;
    if (first_child >= size) break;
    const size_t end = std::min(first_child + kHeapArity, size);
    size_t child = first_child;
    for (size_t other = first_child + 1; other < end; ++other) {
      if (RunsFirst(heap_[other], heap_[child])) child = other;
    }
    heap_[hole] = heap_[child];
    hole = child;
  }
  while (hole > position) {
    const size_t parent = (hole - 1) / kHeapArity;
    if (!RunsFirst(moving, heap_[parent])) break;
    heap_[hole] = heap_[parent];
    hole = parent;
  }
  heap_[hole] = moving;
}

void SimScheduler::Restore(size_t position) {
  if (position > 0 && RunsFirst(heap_[position], heap_[(position - 1) / kHeapArity])) {
    SiftUp(position);
  } else {
    SiftDown(position);
  }
}

// Unlinks the task from its run, then queues it again as a run of its own.
void SimScheduler::Reschedule(uint32_t task_index, int64_t time_ns) {
  TaskRecord& record = tasks_[task_index];
  for (size_t position = 0; position < heap_.size(); ++position) {
    uint32_t previous = kNoTask;
    uint32_t index = heap_[position].task_index();
    while (index != kNoTask && index != task_index) {
      previous = index;
      index = tasks_[index].next_in_run;
    }
    if (index == kNoTask) continue;
    const uint32_t next = record.next_in_run;
    record.next_in_run = kNoTask;
    CloseRunsEndingWith(task_index);
    if (previous != kNoTask) {
      tasks_[previous].next_in_run = next;
    } else if (next != kNoTask) {
      heap_[position].order = (heap_[position].order & kRankMask) | next;
      SiftDown(position);
    } else {
      heap_[position] = heap_.back();
      heap_.pop_back();
      if (position < heap_.size()) Restore(position);
    }
    PushActivation(MakeActivation(task_index, time_ns));
    return;
  }
  SYROF_CHECK(false);  // the task had no pending activation
}

void SimScheduler::RunUntil(int64_t end_ns) {
  while (!heap_.empty() && heap_.front().time_ns <= end_ns) RunNext();
  now_ns_ = std::max(now_ns_, end_ns);
}

SimPort::SimPort(SimScheduler& scheduler, const char* name)
    : scheduler_(scheduler), name_(name), index_(scheduler.ports_++) {}

// Room for one notification and one shift per task (each coalesces), so a
// batch never allocates.
void SimPort::Defer(uint32_t task_index, int64_t time_ns, bool reschedule) {
  SYROF_CHECK(batch_mark_ == scheduler_.batch_mark_);  // only a port of the batch (or side by side)
  scheduler_.batch_deferred_[batch_position_] = 1;
  for (Deferred& deferred : deferred_) {
    if (deferred.task_index == task_index && deferred.reschedule == reschedule) {
      deferred.time_ns = time_ns;
      return;
    }
  }
  SYROF_CHECK(deferred_.size() < deferred_.capacity());
  deferred_.push_back(Deferred{task_index, time_ns, reschedule});
}

base::Result<TaskId, PortError> SimPort::AddTask(Task& task, const TaskConfig& config) {
  if (running_) return PortError::kAlreadyStarted;
  if (const PortError error = Validate(config.trigger); error != PortError::kOk) return error;
  const auto local_id = static_cast<TaskId>(task_indices_.size());
  if (task_indices_.size() >= UINT16_MAX) return PortError::kTooManyTasks;
  const auto registered = scheduler_.RegisterTask(*this, task, config, local_id);
  if (!registered) return registered.error();
  task_indices_.push_back(registered.value());
  deferred_.reserve(2 * task_indices_.size());
  return local_id;
}

PortError SimPort::Start() { return StartAfter(0); }

PortError SimPort::StartAfter(int64_t delay_ns) {
  if (running_) return PortError::kAlreadyStarted;
  if (delay_ns < 0) return PortError::kInvalidTrigger;
  SYROF_CHECK(!scheduler_.in_batch_);  // sim_port.h: Start during a batch
  running_ = true;
  const int64_t now = now_ns();
  for (const uint32_t index : task_indices_) {
    SimScheduler::TaskRecord& record = scheduler_.tasks_[index];
    if (record.config.trigger.kind != TriggerKind::kPeriodic) continue;
    record.local_due_ns = now + delay_ns + record.config.trigger.offset_ns;
    scheduler_.Schedule(index, TrueFromLocal(record.local_due_ns));
  }
  return PortError::kOk;
}

PortError SimPort::ShiftPeriodic(TaskId task, int64_t delta_ns) {
  if (task >= task_indices_.size()) return PortError::kInvalidTrigger;
  const uint32_t index = task_indices_[task];
  SimScheduler::TaskRecord& record = scheduler_.tasks_[index];
  if (record.config.trigger.kind != TriggerKind::kPeriodic) return PortError::kInvalidTrigger;
  if (!record.pending || delta_ns == 0) return PortError::kOk;
  const int64_t now = now_ns();
  record.local_due_ns = std::max(record.local_due_ns + delta_ns, now);
  const int64_t due_ns = std::max(TrueFromLocal(record.local_due_ns), scheduler_.now_ns());
  if (scheduler_.in_batch_) {
    Defer(index, due_ns, true);
  } else {
    scheduler_.Reschedule(index, due_ns);
  }
  return PortError::kOk;
}

void SimPort::SetDriftPpb(int32_t drift_ppb) {
  SYROF_CHECK(drift_ppb > -100'000'000 && drift_ppb < 100'000'000);
  drift_ppb_ = drift_ppb;
}

int64_t SimPort::LocalFromTrue(int64_t true_ns) const {
  if (drift_ppb_ == 0) return true_ns;
  // floor(t * ppb / 10^9) without overflow: whole seconds times ppb is exact,
  // the rest of a second times ppb stays below 10^17.
  constexpr int64_t kBillion = 1'000'000'000;
  const int64_t seconds = true_ns / kBillion;
  const int64_t rest = (true_ns % kBillion) * drift_ppb_;
  int64_t rest_ns = rest / kBillion;
  if (rest % kBillion != 0 && rest < 0) --rest_ns;  // floor
  return true_ns + seconds * drift_ppb_ + rest_ns;
}

int64_t SimPort::TrueFromLocal(int64_t local_ns) const {
  if (drift_ppb_ == 0) return local_ns;
  // A close guess, then exact steps (local time is strictly increasing).
  int64_t t = static_cast<int64_t>(static_cast<double>(local_ns) / (1.0 + drift_ppb_ * 1e-9));
  if (t < 0) t = 0;
  while (LocalFromTrue(t) < local_ns) ++t;
  while (t > 0 && LocalFromTrue(t - 1) >= local_ns) --t;
  return t;
}

PortError SimPort::Stop() {
  if (!running_) return PortError::kNotStarted;
  running_ = false;
  if (scheduler_.in_batch_) {
    SYROF_CHECK(batch_mark_ == scheduler_.batch_mark_);  // only a port of the batch (or side by side)
    stop_deferred_ = true;
    scheduler_.batch_deferred_[batch_position_] = 1;
  } else {
    scheduler_.CancelPort(*this);
  }
  return PortError::kOk;
}

void SimPort::Notify(TaskId task) {
  if (!running_ || task >= task_indices_.size()) return;
  const uint32_t index = task_indices_[task];
  SimScheduler::TaskRecord& record = scheduler_.tasks_[index];
  if (record.config.trigger.kind != TriggerKind::kNotified || record.pending) return;
  if (scheduler_.in_batch_) {
    record.pending = true;  // coalesces later notifications, as a queued one does
    Defer(index, scheduler_.now_ns(), false);
    return;
  }
  scheduler_.Schedule(index, scheduler_.now_ns());
}

void SimPort::Lock() {
  SYROF_CHECK(!locked_);  // critical sections must not nest
  locked_ = true;
}

void SimPort::Unlock() {
  SYROF_CHECK(locked_);
  locked_ = false;
}

}  // namespace syrof::os
