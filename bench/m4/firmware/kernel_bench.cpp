// Instructions per kernel operation of NvicPort (firmware/kernel) on the
// emulated Cortex-M4 (qemu mps2-an386, -icount shift=0: one counted cycle per
// executed instruction; qemu charges nothing for exception entry and return,
// which a real M4 adds, about 12 cycles each). Each figure is an average over
// many repetitions, so the counter's 40-instruction resolution vanishes.
#include <cstdint>
#include <cstdio>

#include "syrof/board/cycles.h"
#include "syrof/firmware/kernel/mps2_an386_hardware.h"
#include "syrof/firmware/kernel/nvic_port.h"

namespace {

using syrof::board::cycle_counter_read;
using syrof::firmware::kernel::kMaxTasks;
using syrof::firmware::kernel::Mps2An386Hardware;
using syrof::firmware::kernel::NvicPort;
using syrof::os::TaskId;
using syrof::os::Trigger;

class EmptyTask final : public syrof::os::Task {
 public:
  void Step(int64_t) override {}
};

// A task that, in its step, notifies a higher-level empty task `repeats`
// times and measures them: each Notify preempts it.
class PreemptedTask final : public syrof::os::Task {
 public:
  void Step(int64_t) override {
    const uint64_t begin = cycle_counter_read();
    for (int i = 0; i < repeats; ++i) port->Notify(target);
    cycles = cycle_counter_read() - begin;
  }
  NvicPort* port = nullptr;
  TaskId target = 0;
  int repeats = 0;
  uint64_t cycles = 0;
};

void Report(const char* what, uint64_t cycles, int count) {
  std::printf("  %-66s %6llu\n", what, static_cast<unsigned long long>((cycles + count / 2) / count));
}

}  // namespace

int main() {
  syrof::board::cycle_counter_start();
  Mps2An386Hardware hardware;
  std::printf("NvicPort on Cortex-M4 (qemu mps2-an386, -icount shift=0), instructions per operation\n");

  // Notify, dispatch and preemption, on one port with a task per slot.
  {
    constexpr int kLevelTasks = 24;
    constexpr int kRepeats = 400;
    NvicPort port(hardware);
    hardware.Attach(port);
    EmptyTask empty[kLevelTasks];
    for (EmptyTask& task : empty) (void)port.AddTask(task, {"empty", Trigger::notified(), 1}).value();
    EmptyTask high;
    const TaskId high_id = port.AddTask(high, {"high", Trigger::notified(), 6}).value();
    PreemptedTask low;
    low.port = &port;
    low.target = high_id;
    low.repeats = kRepeats;
    const TaskId low_id = port.AddTask(low, {"low", Trigger::notified(), 0}).value();
    (void)port.Start();

    // Notify with the kernel locked: the task becomes ready and its level is
    // pended, nothing runs.
    uint64_t notify = 0, coalesced = 0, one = 0, many = 0;
    for (int round = 0; round < 20; ++round) {
      port.Lock();
      uint64_t begin = cycle_counter_read();
      for (int t = 0; t < kLevelTasks; ++t) port.Notify(static_cast<TaskId>(t));
      notify += cycle_counter_read() - begin;
      begin = cycle_counter_read();
      for (int t = 0; t < kLevelTasks; ++t) port.Notify(static_cast<TaskId>(t));
      coalesced += cycle_counter_read() - begin;
      begin = cycle_counter_read();
      port.Unlock();  // one entry of level 1 runs all of them
      many += cycle_counter_read() - begin;

      port.Lock();
      port.Notify(0);
      begin = cycle_counter_read();
      port.Unlock();  // one entry, one task
      one += cycle_counter_read() - begin;
    }
    Report("Notify (ready + pend, kernel locked)", notify, 20 * kLevelTasks);
    Report("Notify of a task already ready (coalesced)", coalesced, 20 * kLevelTasks);
    Report("Unlock + level entry + one empty task + return", one, 20);
    Report("each further empty task in the same entry", many - one, 20 * (kLevelTasks - 1));

    // Thread mode notifies: ready, pend, preempt, dispatch, return.
    uint64_t begin = cycle_counter_read();
    for (int i = 0; i < kRepeats; ++i) port.Notify(0);
    Report("Notify from thread mode, preempt, empty step, return", cycle_counter_read() - begin, kRepeats);

    // A running task is preempted by a higher level.
    port.Notify(low_id);
    Report("Notify from a task, preempt by higher level, empty step, return", low.cycles, kRepeats);
    (void)port.Stop();
  }

  // Timer releases: the kernel is held locked past a release, then unlocked:
  // the timer interrupt releases the task (OnTimer, the alarm), its level
  // runs the empty step, and both return.
  for (const int periodic_tasks : {1, 8}) {
    constexpr int kReleases = 100;
    constexpr int64_t kPeriod = 200'000;
    NvicPort port(hardware);
    hardware.Attach(port);
    EmptyTask tasks[8];
    for (int t = 0; t < periodic_tasks; ++t) {
      // Only task 0 is released during the measurement; the others wait far ahead.
      const Trigger trigger = t == 0 ? Trigger::periodic(kPeriod, kPeriod) : Trigger::periodic(1'000'000'000, 900'000'000);
      (void)port.AddTask(tasks[t], {"periodic", trigger, 3}).value();
    }
    (void)port.Start();
    uint64_t total = 0;
    for (int k = 0; k < kReleases; ++k) {
      port.Lock();
      while (port.now_ns() < port.next_release_ns(0)) {
      }
      const uint64_t begin = cycle_counter_read();
      port.Unlock();
      total += cycle_counter_read() - begin;
    }
    char what[80];
    std::snprintf(what, sizeof(what), "timer release + empty step, %d periodic task%s", periodic_tasks,
                  periodic_tasks == 1 ? "" : "s");
    Report(what, total, kReleases);
    if (port.total_overruns() != 0) std::printf("  (unexpected overruns: %lu)\n", static_cast<unsigned long>(port.total_overruns()));
    (void)port.Stop();
  }
  std::printf("kernel state: %u bytes per port (%u task slots)\n", static_cast<unsigned>(sizeof(NvicPort)),
              static_cast<unsigned>(kMaxTasks));
  return 0;
}
