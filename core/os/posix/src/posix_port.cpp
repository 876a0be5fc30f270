#include "syrof/os/posix_port.h"

#include <pthread.h>
#include <sched.h>

#include <algorithm>
#include <system_error>

namespace syrof::os {

struct PosixPort::Worker {
  Task* task;
  TaskConfig config;
  bool pending = false;
  // Periodic: the next activation (under state_mutex_). RunPeriodic moves it
  // one period on before each step, so ShiftPeriodic from the step itself
  // moves the activation after it.
  std::chrono::steady_clock::time_point due;
  std::condition_variable wake;
  std::thread thread;
};

PosixPort::PosixPort(PosixPortOptions options)
    : options_(options), epoch_(std::chrono::steady_clock::now()) {
  workers_.reserve(options_.max_tasks);
}

PosixPort::~PosixPort() { (void)Stop(); }

base::Result<TaskId, PortError> PosixPort::AddTask(Task& task, const TaskConfig& config) {
  std::lock_guard<std::mutex> guard(state_mutex_);
  if (running_) return PortError::kAlreadyStarted;
  if (const PortError error = Validate(config.trigger); error != PortError::kOk) return error;
  if (workers_.size() >= options_.max_tasks) return PortError::kTooManyTasks;
  auto worker = std::make_unique<Worker>();
  worker->task = &task;
  worker->config = config;
  workers_.push_back(std::move(worker));
  return static_cast<TaskId>(workers_.size() - 1);
}

PortError PosixPort::Start() { return StartFrom(std::chrono::steady_clock::now(), false); }

PortError PosixPort::StartAt(int64_t origin_ns) {
  return StartFrom(epoch_ + std::chrono::nanoseconds(origin_ns), true);
}

PortError PosixPort::StartFrom(std::chrono::steady_clock::time_point origin, bool skip_past) {
  {
    std::lock_guard<std::mutex> guard(state_mutex_);
    if (running_) return PortError::kAlreadyStarted;
    running_ = true;
    const auto now = std::chrono::steady_clock::now();
    for (auto& worker : workers_) {
      worker->pending = false;
      const Trigger& trigger = worker->config.trigger;
      if (trigger.kind != TriggerKind::kPeriodic) continue;
      worker->due = origin + std::chrono::nanoseconds(trigger.offset_ns);
      if (skip_past && worker->due < now) {
        // The first grid point at or after now.
        const int64_t behind_ns = std::chrono::duration_cast<std::chrono::nanoseconds>(now - worker->due).count();
        const int64_t periods = (behind_ns + trigger.period_ns - 1) / trigger.period_ns;
        worker->due += std::chrono::nanoseconds(periods * trigger.period_ns);
      }
    }
  }
  for (auto& worker : workers_) {
    Worker& w = *worker;
    try {
      if (w.config.trigger.kind == TriggerKind::kPeriodic) {
        w.thread = std::thread([this, &w] { RunPeriodic(w); });
      } else {
        w.thread = std::thread([this, &w] { RunNotified(w); });
      }
    } catch (const std::system_error&) {
      (void)Stop();
      return PortError::kSystemError;
    }
    if (options_.realtime_priorities) {
      sched_param parameters{};
      parameters.sched_priority = sched_get_priority_min(SCHED_FIFO) + w.config.priority;
      // Refusal (no CAP_SYS_NICE) is documented: the thread keeps SCHED_OTHER.
      (void)pthread_setschedparam(w.thread.native_handle(), SCHED_FIFO, &parameters);
    }
  }
  return PortError::kOk;
}

PortError PosixPort::Stop() {
  {
    std::lock_guard<std::mutex> guard(state_mutex_);
    if (!running_) return PortError::kNotStarted;
    running_ = false;
  }
  for (auto& worker : workers_) worker->wake.notify_all();
  for (auto& worker : workers_) {
    if (worker->thread.joinable()) worker->thread.join();
  }
  return PortError::kOk;
}

void PosixPort::Notify(TaskId task) {
  if (task >= workers_.size()) return;
  Worker& worker = *workers_[task];
  if (worker.config.trigger.kind != TriggerKind::kNotified) return;
  {
    std::lock_guard<std::mutex> guard(state_mutex_);
    if (!running_ || worker.pending) return;
    worker.pending = true;
  }
  worker.wake.notify_one();
}

PortError PosixPort::ShiftPeriodic(TaskId task, int64_t delta_ns) {
  if (task >= workers_.size()) return PortError::kInvalidTrigger;
  Worker& worker = *workers_[task];
  if (worker.config.trigger.kind != TriggerKind::kPeriodic) return PortError::kInvalidTrigger;
  {
    std::lock_guard<std::mutex> guard(state_mutex_);
    if (!running_ || delta_ns == 0) return PortError::kOk;
    worker.due = std::max(worker.due + std::chrono::nanoseconds(delta_ns), std::chrono::steady_clock::now());
  }
  worker.wake.notify_all();
  return PortError::kOk;
}

int64_t PosixPort::MonotonicNowNs() {
  return std::chrono::duration_cast<std::chrono::nanoseconds>(std::chrono::steady_clock::now().time_since_epoch())
      .count();
}

int64_t PosixPort::MonotonicToPort(int64_t monotonic_ns) const {
  return monotonic_ns - std::chrono::duration_cast<std::chrono::nanoseconds>(epoch_.time_since_epoch()).count();
}

int64_t PosixPort::PortToMonotonic(int64_t port_ns) const {
  return port_ns + std::chrono::duration_cast<std::chrono::nanoseconds>(epoch_.time_since_epoch()).count();
}

int64_t PosixPort::now_ns() const {
  return std::chrono::duration_cast<std::chrono::nanoseconds>(std::chrono::steady_clock::now() - epoch_).count();
}

void PosixPort::RunPeriodic(Worker& worker) {
  const auto period = std::chrono::nanoseconds(worker.config.trigger.period_ns);
  std::unique_lock<std::mutex> state(state_mutex_);
  while (running_) {
    // Re-wait when ShiftPeriodic moved the due time while we slept.
    const auto due = worker.due;
    if (worker.wake.wait_until(state, due, [&] { return !running_ || worker.due != due; })) {
      if (!running_) break;
      continue;
    }
    // An activation more than a period late (a stopped process, SIGSTOP)
    // runs once; the missed grid points are skipped, not run back to back.
    worker.due = due + period;
    const auto now = std::chrono::steady_clock::now();
    if (worker.due <= now) worker.due += ((now - worker.due) / period + 1) * period;
    // The step is given its release, the latest grid point at or before
    // now, not the moment the thread woke: what arrived after the release
    // belongs to the next activation however late this one runs.
    const auto release = worker.due - period;
    state.unlock();
    worker.task->Step(std::chrono::duration_cast<std::chrono::nanoseconds>(release - epoch_).count());
    state.lock();
  }
}

void PosixPort::RunNotified(Worker& worker) {
  std::unique_lock<std::mutex> state(state_mutex_);
  while (true) {
    worker.wake.wait(state, [&] { return worker.pending || !running_; });
    if (!running_) break;
    worker.pending = false;
    state.unlock();
    worker.task->Step(now_ns());
    state.lock();
  }
}

}  // namespace syrof::os
