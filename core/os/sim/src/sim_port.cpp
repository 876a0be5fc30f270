#include "syrof/os/sim_port.h"

#include <algorithm>

#include "syrof/base/check.h"

namespace syrof::os {
namespace {

// std heap algorithms keep the "largest" element on top, so "a before b"
// means b has the higher claim to run first.
struct RunsLater {
  template <typename Activation>
  bool operator()(const Activation& a, const Activation& b) const {
    if (a.time_ns != b.time_ns) return a.time_ns > b.time_ns;
    if (a.priority != b.priority) return a.priority < b.priority;
    return a.task_index > b.task_index;
  }
};

}  // namespace

SimScheduler::SimScheduler(size_t max_tasks) : max_tasks_(max_tasks) {
  tasks_.reserve(max_tasks);
  heap_.reserve(max_tasks);
}

base::Result<uint32_t, PortError> SimScheduler::RegisterTask(SimPort& port, Task& task,
                                                             const TaskConfig& config, TaskId local_id) {
  if (tasks_.size() == max_tasks_) return PortError::kTooManyTasks;
  tasks_.push_back(TaskRecord{&task, &port, config, local_id, false});
  return static_cast<uint32_t>(tasks_.size() - 1);
}

void SimScheduler::Schedule(uint32_t task_index, int64_t time_ns) {
  TaskRecord& record = tasks_[task_index];
  SYROF_CHECK(!record.pending);
  // Each task has at most one pending activation and heap_ has room for one
  // per task, so this never reallocates.
  SYROF_CHECK(heap_.size() < max_tasks_);
  record.pending = true;
  heap_.push_back(Activation{time_ns, record.config.priority, task_index});
  std::push_heap(heap_.begin(), heap_.end(), RunsLater{});
}

void SimScheduler::CancelPort(const SimPort& port) {
  const auto belongs_to_port = [&](const Activation& activation) {
    return tasks_[activation.task_index].port == &port;
  };
  for (const Activation& activation : heap_) {
    if (belongs_to_port(activation)) tasks_[activation.task_index].pending = false;
  }
  heap_.erase(std::remove_if(heap_.begin(), heap_.end(), belongs_to_port), heap_.end());
  std::make_heap(heap_.begin(), heap_.end(), RunsLater{});
}

int64_t SimScheduler::next_activation_ns() const { return heap_.empty() ? -1 : heap_.front().time_ns; }

bool SimScheduler::RunNext() {
  if (heap_.empty()) return false;
  std::pop_heap(heap_.begin(), heap_.end(), RunsLater{});
  const Activation activation = heap_.back();
  heap_.pop_back();

  TaskRecord& record = tasks_[activation.task_index];
  record.pending = false;
  SYROF_CHECK(activation.time_ns >= now_ns_);
  now_ns_ = activation.time_ns;

  // The next periodic activation is due one period after this one was due
  // (vTaskDelayUntil semantics), and is queued before the step runs so that a
  // step which stops its own port also cancels it.
  if (record.config.trigger.kind == TriggerKind::kPeriodic) {
    Schedule(activation.task_index, activation.time_ns + record.config.trigger.period_ns);
  }
  ++steps_run_;
  if (trace_ != nullptr) trace_->OnStep(now_ns_, *record.port, record.local_id, record.config);
  record.task->Step(now_ns_);
  return true;
}

void SimScheduler::RunUntil(int64_t end_ns) {
  while (!heap_.empty() && heap_.front().time_ns <= end_ns) RunNext();
  now_ns_ = std::max(now_ns_, end_ns);
}

SimPort::SimPort(SimScheduler& scheduler, const char* name) : scheduler_(scheduler), name_(name) {}

base::Result<TaskId, PortError> SimPort::AddTask(Task& task, const TaskConfig& config) {
  if (running_) return PortError::kAlreadyStarted;
  if (const PortError error = Validate(config.trigger); error != PortError::kOk) return error;
  const auto local_id = static_cast<TaskId>(task_indices_.size());
  if (task_indices_.size() >= UINT16_MAX) return PortError::kTooManyTasks;
  const auto registered = scheduler_.RegisterTask(*this, task, config, local_id);
  if (!registered) return registered.error();
  task_indices_.push_back(registered.value());
  return local_id;
}

PortError SimPort::Start() {
  if (running_) return PortError::kAlreadyStarted;
  running_ = true;
  const int64_t now = scheduler_.now_ns();
  for (const uint32_t index : task_indices_) {
    const Trigger& trigger = scheduler_.tasks_[index].config.trigger;
    if (trigger.kind == TriggerKind::kPeriodic) scheduler_.Schedule(index, now + trigger.offset_ns);
  }
  return PortError::kOk;
}

PortError SimPort::Stop() {
  if (!running_) return PortError::kNotStarted;
  running_ = false;
  scheduler_.CancelPort(*this);
  return PortError::kOk;
}

void SimPort::Notify(TaskId task) {
  if (!running_ || task >= task_indices_.size()) return;
  const uint32_t index = task_indices_[task];
  const SimScheduler::TaskRecord& record = scheduler_.tasks_[index];
  if (record.config.trigger.kind != TriggerKind::kNotified || record.pending) return;
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
