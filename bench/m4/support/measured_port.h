// An os::Port that counts the instructions of every step it runs, for the
// schedulability benchmarks on the emulated Cortex-M4 (docs/firmware.md,
// "Schedulability"). It wraps another port (SimPort: one robot's port on a
// SimScheduler, as in the lab) and forwards everything to it; AddTask
// registers a probe in the task's place, which reads the board's cycle
// counter around the task's own Step() and hands the count to an observer.
// So the code measured is the robot's, unchanged: runtime::Robot's round
// and motion tasks, the estimator's state and Kalman tasks, as they attach
// themselves. SimPort runs one step at a time (no preemption), so a count is
// the step's own work; it includes the counter's reads (about 40
// instructions, its resolution) and SimPort's Lock/Unlock in place of the
// kernel's BASEPRI writes.
#pragma once

#include <array>
#include <cstdint>

#include "syrof/os/port.h"

namespace syrof::bench {

/// Receives the instruction count of one step: `task` is the id the inner
/// port gave, `config` what the task was added with, `now_ns` the step's
/// activation time.
using StepObserver = void (*)(void* context, os::TaskId task, const os::TaskConfig& config, uint64_t instructions,
                              int64_t now_ns);

class MeasuredPort final : public os::Port {
 public:
  /// Most tasks one MeasuredPort measures.
  static constexpr uint16_t kMaxProbes = 16;

  /// `inner` and `observer`'s context must outlive this port.
  MeasuredPort(os::Port& inner, StepObserver observer, void* context)
      : inner_(inner), observer_(observer), context_(context) {}
  MeasuredPort(const MeasuredPort&) = delete;
  MeasuredPort& operator=(const MeasuredPort&) = delete;

  /// Adds a probe for `task` to the inner port and returns the inner port's
  /// id; kTooManyTasks after kMaxProbes tasks.
  base::Result<os::TaskId, os::PortError> AddTask(os::Task& task, const os::TaskConfig& config) override;
  os::PortError Start() override { return inner_.Start(); }
  os::PortError Stop() override { return inner_.Stop(); }
  void Notify(os::TaskId task) override { inner_.Notify(task); }
  int64_t now_ns() const override { return inner_.now_ns(); }
  os::PortError ShiftPeriodic(os::TaskId task, int64_t delta_ns) override {
    return inner_.ShiftPeriodic(task, delta_ns);
  }
  void Lock() override { inner_.Lock(); }
  void Unlock() override { inner_.Unlock(); }

 private:
  class Probe final : public os::Task {
   public:
    void Step(int64_t now_ns) override;
    MeasuredPort* port = nullptr;
    os::Task* task = nullptr;
    os::TaskConfig config{};
    os::TaskId id = 0;
  };

  os::Port& inner_;
  StepObserver observer_;
  void* context_;
  std::array<Probe, kMaxProbes> probes_{};
};

/// Worst and mean of a series of instruction counts.
struct StepStats {
  uint64_t count = 0;
  uint64_t total = 0;
  uint64_t worst = 0;

  void Add(uint64_t instructions) {
    ++count;
    total += instructions;
    if (instructions > worst) worst = instructions;
  }
  uint64_t mean() const { return count == 0 ? 0 : total / count; }
};

}  // namespace syrof::bench
