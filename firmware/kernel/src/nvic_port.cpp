#include "syrof/firmware/kernel/nvic_port.h"

#include <atomic>

#include "syrof/base/check.h"

namespace syrof::firmware::kernel {

using os::PortError;
using os::TaskId;
using os::TriggerKind;

NvicPort::NvicPort(KernelHardware& hardware, uint16_t max_tasks)
    : hardware_(hardware), max_tasks_(max_tasks < kMaxTasks ? max_tasks : kMaxTasks) {}

PortError NvicPort::MapPriority(uint8_t priority, uint8_t level) {
  if (started_) return PortError::kAlreadyStarted;
  if (priority >= kLevelCount || level >= kLevelCount) return PortError::kUnsupported;
  level_of_priority_[priority] = level;
  return PortError::kOk;
}

base::Result<TaskId, PortError> NvicPort::AddTask(os::Task& task, const os::TaskConfig& config) {
  if (const PortError error = os::Validate(config.trigger); error != PortError::kOk) return error;
  if (started_) return PortError::kAlreadyStarted;
  if (task_count_ >= max_tasks_) return PortError::kTooManyTasks;
  if (config.priority >= kLevelCount) return PortError::kUnsupported;
  const TaskId id = task_count_++;
  TaskRecord record;
  record.task = &task;
  record.config = config;
  record.level = level_of_priority_[config.priority];
  tasks_[id] = record;
  if (config.trigger.kind == TriggerKind::kPeriodic) periodic_mask_ |= 1u << id;
  return id;
}

PortError NvicPort::Start() { return StartAt(-1); }

// start_ns -1: now.
PortError NvicPort::StartAt(int64_t start_ns) {
  if (started_) return PortError::kAlreadyStarted;
  const uint32_t saved = hardware_.MaskKernel();
  const int64_t now = hardware_.now_ns();
  if (start_ns < 0) start_ns = now;
  if (start_ns > now) {
    hardware_.RestoreMask(saved);
    return PortError::kUnsupported;
  }
  for (uint32_t periodic = periodic_mask_; periodic != 0; periodic &= periodic - 1) {
    TaskRecord& record = tasks_[__builtin_ctz(periodic)];
    record.next_release_ns = start_ns + record.config.trigger.offset_ns;
  }
  ready_ = {};
  started_ = true;
  hardware_.SetAlarm(EarliestRelease());
  hardware_.RestoreMask(saved);
  return PortError::kOk;
}

PortError NvicPort::Stop() {
  if (!started_) return PortError::kNotStarted;
  const uint32_t saved = hardware_.MaskKernel();
  started_ = false;
  ready_ = {};
  for (uint16_t id = 0; id < task_count_; ++id) tasks_[id].next_release_ns = -1;
  hardware_.SetAlarm(-1);
  hardware_.RestoreMask(saved);
  return PortError::kOk;
}

void NvicPort::Notify(TaskId task) {
  if (task >= task_count_ || (periodic_mask_ & (1u << task)) != 0) return;
  const uint8_t level = tasks_[task].level;
  const uint32_t bit = 1u << task;
  // Already ready: its step has not begun (the bit is cleared just before
  // the step starts), so it will see whatever the caller published; nothing
  // to do, and no need to mask. One aligned word read, atomic on one core;
  // the fence keeps the caller's writes before it.
  std::atomic_signal_fence(std::memory_order_seq_cst);
  if ((static_cast<const volatile uint32_t&>(ready_[level]) & bit) != 0) return;
  const uint32_t saved = hardware_.MaskKernel();
  if (started_ && (ready_[level] & bit) == 0) {
    ready_[level] |= bit;
    hardware_.PendLevel(level);
  }
  hardware_.RestoreMask(saved);
}

int64_t NvicPort::now_ns() const {
  const uint32_t saved = hardware_.MaskKernel();
  const int64_t now = hardware_.now_ns();
  hardware_.RestoreMask(saved);
  return now;
}

PortError NvicPort::ShiftPeriodic(TaskId task, int64_t delta_ns) {
  if (task >= task_count_ || (periodic_mask_ & (1u << task)) == 0) return PortError::kInvalidTrigger;
  const uint32_t saved = hardware_.MaskKernel();
  TaskRecord& record = tasks_[task];
  if (started_ && delta_ns != 0) {
    const int64_t now = hardware_.now_ns();
    const int64_t shifted = record.next_release_ns + delta_ns;
    record.next_release_ns = shifted > now ? shifted : now;
    hardware_.SetAlarm(EarliestRelease());
  }
  hardware_.RestoreMask(saved);
  return PortError::kOk;
}

void NvicPort::Lock() {
  const uint32_t saved = hardware_.MaskKernel();
  SYROF_CHECK(!locked_);  // Lock is not recursive
  locked_ = true;
  lock_saved_mask_ = saved;
}

void NvicPort::Unlock() {
  SYROF_CHECK(locked_);
  locked_ = false;
  hardware_.RestoreMask(lock_saved_mask_);
}

void NvicPort::RunLevel(uint8_t level) {
  SYROF_CHECK(level < kLevelCount);
  uint32_t saved = hardware_.MaskKernel();
  for (;;) {
    const uint32_t ready = ready_[level];
    if (ready == 0) break;
    const unsigned id = static_cast<unsigned>(__builtin_ctz(ready));
    ready_[level] = ready & ~(1u << id);
    TaskRecord& record = tasks_[id];
    record.in_step = true;
    // A periodic step is given its release on the grid, however long higher
    // levels kept it waiting: what arrived after the release (a beacon at the
    // round boundary) belongs to the next activation (os/port.h).
    const int64_t now =
        record.config.trigger.kind == os::TriggerKind::kPeriodic ? record.release_ns : hardware_.now_ns();
    hardware_.RestoreMask(saved);

    record.task->Step(now);

    saved = hardware_.MaskKernel();
    record.in_step = false;
    ++record.steps;
  }
  hardware_.RestoreMask(saved);
}

void NvicPort::OnTimer() {
  const uint32_t saved = hardware_.MaskKernel();
  if (!started_) {
    hardware_.SetAlarm(-1);
    hardware_.RestoreMask(saved);
    return;
  }
  const int64_t now = hardware_.now_ns();
  int64_t earliest = -1;
  for (uint32_t periodic = periodic_mask_; periodic != 0; periodic &= periodic - 1) {
    const unsigned id = static_cast<unsigned>(__builtin_ctz(periodic));
    TaskRecord& record = tasks_[id];
    if (record.next_release_ns <= now) {
      const int64_t period = record.config.trigger.period_ns;
      // Releases the interrupt came too late for are missed deadlines; the
      // grid stays where it was (absolute instants, no drift). Division only
      // when more than one period late.
      const int64_t late = now - record.next_release_ns;
      const int64_t skipped = late < period ? 0 : late / period;
      record.release_ns = record.next_release_ns + skipped * period;  // the latest grid point at or before now
      record.next_release_ns += (skipped + 1) * period;
      const uint8_t level = record.level;
      const uint32_t bit = 1u << id;
      uint32_t misses = static_cast<uint32_t>(skipped);
      if ((ready_[level] & bit) != 0 || record.in_step) ++misses;
      record.overruns += misses;
      ready_[level] |= bit;
      hardware_.PendLevel(level);
    }
    if (earliest < 0 || record.next_release_ns < earliest) earliest = record.next_release_ns;
  }
  hardware_.SetAlarm(earliest);
  hardware_.RestoreMask(saved);
}

int64_t NvicPort::EarliestRelease() const {
  int64_t earliest = -1;
  for (uint32_t periodic = periodic_mask_; periodic != 0; periodic &= periodic - 1) {
    const int64_t release = tasks_[__builtin_ctz(periodic)].next_release_ns;
    if (earliest < 0 || release < earliest) earliest = release;
  }
  return earliest;
}

uint32_t NvicPort::overruns(TaskId task) const { return task < task_count_ ? tasks_[task].overruns : 0; }

uint32_t NvicPort::total_overruns() const {
  uint32_t total = 0;
  for (uint16_t id = 0; id < task_count_; ++id) total += tasks_[id].overruns;
  return total;
}

uint32_t NvicPort::steps(TaskId task) const { return task < task_count_ ? tasks_[task].steps : 0; }

int64_t NvicPort::next_release_ns(TaskId task) const {
  return task < task_count_ && started_ ? tasks_[task].next_release_ns : -1;
}

}  // namespace syrof::firmware::kernel
