// NvicPort on qemu's mps2-an386 with real interrupts: the NVIC pends and
// preempts, BASEPRI masks, CMSDK timers release periodic tasks. Run under
// -icount shift=0 (make test-m4), so every figure is the same on every run.
#include <gtest/gtest.h>

#include <array>
#include <cstdint>
#include <cstdio>

#include "syrof/firmware/kernel/mps2_an386_hardware.h"
#include "syrof/firmware/kernel/nvic_port.h"

namespace syrof::firmware::kernel {
namespace {

using os::PortError;
using os::TaskId;
using os::Trigger;

constexpr int64_t kMicrosecond = 1'000;
constexpr int64_t kMillisecond = 1'000'000;

Mps2An386Hardware& hardware() {
  static Mps2An386Hardware instance;
  return instance;
}

uint32_t ActiveException() {
  uint32_t ipsr;
  asm volatile("mrs %0, ipsr" : "=r"(ipsr));
  return ipsr;
}

uint32_t BasePriority() {
  uint32_t basepri;
  asm volatile("mrs %0, basepri" : "=r"(basepri));
  return basepri;
}

// Waits (busy, so -icount keeps virtual time exact) until the port's clock
// reaches `time_ns`. Reads the clock only every few hundred instructions:
// under -icount each device read costs qemu far more host time than an
// instruction.
void WaitUntil(const NvicPort& port, int64_t time_ns) {
  while (port.now_ns() < time_ns) {
    for (int i = 0; i < 200; ++i) asm volatile("nop");
  }
}

// The start of a port's grid, from a periodic task's first release (offset
// > 0, so the timer has not released it yet when Start returns).
int64_t GridStart(const NvicPort& port, TaskId task, int64_t offset_ns) {
  return port.next_release_ns(task) - offset_ns;
}

// Appends its mark to a shared trace when its step begins and ends, and
// notes the exception it runs in.
class TraceTask final : public os::Task {
 public:
  static constexpr int kCapacity = 16;
  struct Trace {
    std::array<char, kCapacity> marks{};
    int size = 0;
    void Add(char mark) {
      if (size < kCapacity) marks[size++] = mark;
    }
    bool Equals(const char* expected) const {
      int i = 0;
      for (; expected[i] != '\0'; ++i) {
        if (i >= size || marks[i] != expected[i]) return false;
      }
      return i == size;
    }
  };

  TraceTask(Trace& trace, char begin, char end) : trace_(trace), begin_(begin), end_(end) {}
  void Step(int64_t) override {
    trace_.Add(begin_);
    exception = ActiveException();
    for (int i = 0; i < notify_count; ++i) port->Notify(notify);
    trace_.Add(end_);
  }

  NvicPort* port = nullptr;
  TaskId notify = 0;
  int notify_count = 0;
  uint32_t exception = 0;

 private:
  Trace& trace_;
  char begin_;
  char end_;
};

class NvicPortM4Test : public ::testing::Test {
 protected:
  NvicPortM4Test() { hardware().Attach(port); }
  ~NvicPortM4Test() override {
    if (port.running()) (void)port.Stop();
  }

  NvicPort port{hardware()};
};

TEST_F(NvicPortM4Test, HigherLevelPreemptsInTheMiddleOfAStepAndLowerWaits) {
  TraceTask::Trace trace;
  TraceTask low(trace, 'l', 'L'), high(trace, 'h', 'H'), lowest(trace, 'z', 'Z');
  const TaskId low_id = port.AddTask(low, {"low", Trigger::notified(), 2}).value();
  const TaskId high_id = port.AddTask(high, {"high", Trigger::notified(), 7}).value();
  const TaskId lowest_id = port.AddTask(lowest, {"lowest", Trigger::notified(), 0}).value();
  low.port = &port;
  low.notify = high_id;
  low.notify_count = 1;
  high.port = &port;
  high.notify = lowest_id;
  high.notify_count = 1;
  ASSERT_EQ(port.Start(), PortError::kOk);

  port.Notify(low_id);

  // low is preempted by high at once; lowest waits for both to return.
  EXPECT_TRUE(trace.Equals("lhHLzZ")) << trace.marks.data();
  EXPECT_EQ(low.exception, 16u + kLevelIrq[2]);
  EXPECT_EQ(high.exception, 16u + kLevelIrq[7]);
  EXPECT_EQ(lowest.exception, 16u + kLevelIrq[0]);
  EXPECT_EQ(ActiveException(), 0u);  // back in thread mode
}

TEST_F(NvicPortM4Test, NotificationsCoalesce) {
  TraceTask::Trace trace;
  TraceTask publisher(trace, 'p', 'P'), subscriber(trace, 's', 'S');
  const TaskId publisher_id = port.AddTask(publisher, {"publisher", Trigger::notified(), 6}).value();
  const TaskId subscriber_id = port.AddTask(subscriber, {"subscriber", Trigger::notified(), 1}).value();
  publisher.port = &port;
  publisher.notify = subscriber_id;
  publisher.notify_count = 5;
  ASSERT_EQ(port.Start(), PortError::kOk);

  port.Notify(publisher_id);
  port.Lock();
  port.Notify(publisher_id);
  port.Notify(publisher_id);
  port.Unlock();

  EXPECT_TRUE(trace.Equals("pPsSpPsS")) << trace.marks.data();
  EXPECT_EQ(port.steps(subscriber_id), 2u);
}

TEST_F(NvicPortM4Test, BasepriMasksTheKernelUntilUnlock) {
  TraceTask::Trace trace;
  TraceTask task(trace, 't', 'T');
  const TaskId id = port.AddTask(task, {"t", Trigger::notified(), 9}).value();
  ASSERT_EQ(port.Start(), PortError::kOk);

  port.Lock();
  EXPECT_EQ(BasePriority(), kKernelMask);
  port.Notify(id);
  WaitUntil(port, port.now_ns() + 50 * kMicrosecond);  // time enough to dispatch, were it not masked
  const uint32_t steps_while_locked = port.steps(id);
  const uint32_t irq = kLevelIrq[9];
  const bool pending = (reinterpret_cast<volatile uint32_t*>(0xE000E200u)[irq >> 5] & (1u << (irq & 31))) != 0;
  port.Unlock();

  EXPECT_EQ(steps_while_locked, 0u);
  EXPECT_TRUE(pending);
  EXPECT_EQ(port.steps(id), 1u);
  EXPECT_EQ(BasePriority(), 0u);
}

// Records, at every step, the time it was given (its release) and the
// clock when it ran.
class StampTask final : public os::Task {
 public:
  static constexpr int kCapacity = 400;
  explicit StampTask(NvicPort& port) : port_(port) {}
  void Step(int64_t now_ns) override {
    if (count < kCapacity) {
      given_ns[count] = now_ns;
      stamps_ns[count] = port_.now_ns();
    }
    ++count;
  }
  std::array<int64_t, kCapacity> given_ns{};
  std::array<int64_t, kCapacity> stamps_ns{};
  int count = 0;

 private:
  NvicPort& port_;
};

TEST_F(NvicPortM4Test, PeriodicReleasesNeverDriftOverManyPeriods) {
  constexpr int kPeriods = 300;
  constexpr int64_t kPeriod = kMillisecond + 7 * kMicrosecond + 40;  // not a multiple of anything tidy
  StampTask fast(port), slow(port);
  const TaskId fast_id = port.AddTask(fast, {"fast", Trigger::periodic(kPeriod, 200 * kMicrosecond), 5}).value();
  ASSERT_TRUE(port.AddTask(slow, {"slow", Trigger::periodic(3 * kPeriod, 200 * kMicrosecond), 2}));
  ASSERT_EQ(port.Start(), PortError::kOk);
  const int64_t start_ns = GridStart(port, fast_id, 200 * kMicrosecond);

  WaitUntil(port, start_ns + 200 * kMicrosecond + (kPeriods - 1) * kPeriod + kPeriod / 2);
  ASSERT_EQ(port.Stop(), PortError::kOk);

  ASSERT_EQ(fast.count, kPeriods);
  int64_t worst_latency_ns = 0;
  for (int k = 0; k < kPeriods; ++k) {
    const int64_t release = start_ns + 200 * kMicrosecond + k * kPeriod;
    ASSERT_EQ(fast.given_ns[k], release) << k;  // each step is given its release on the grid
    const int64_t latency = fast.stamps_ns[k] - release;
    ASSERT_GE(latency, 0) << k;
    if (latency > worst_latency_ns) worst_latency_ns = latency;
  }
  // The latency is the interrupt path, a few hundred instructions; it does
  // not grow with k (no drift), and never reaches a tenth of a period.
  EXPECT_LT(worst_latency_ns, 10 * kMicrosecond);
  EXPECT_EQ(slow.count, kPeriods / 3);
  EXPECT_EQ(port.total_overruns(), 0u);
  std::printf("fast task: %d releases of %lld ns, worst release-to-step latency %lld ns\n", kPeriods,
              static_cast<long long>(kPeriod), static_cast<long long>(worst_latency_ns));
}

// Busy for `first_step_ns` in its first step, empty afterwards.
class OverrunningTask final : public os::Task {
 public:
  explicit OverrunningTask(const NvicPort& port) : port_(port) {}
  void Step(int64_t now_ns) override {
    if (steps++ == 0) WaitUntil(port_, now_ns + first_step_ns);
  }
  int64_t first_step_ns = 0;
  int steps = 0;

 private:
  const NvicPort& port_;
};

TEST_F(NvicPortM4Test, AnOverrunningTaskIsReportedByTheDeadlineMissCounter) {
  OverrunningTask slow(port);
  slow.first_step_ns = 2 * kMillisecond + 500 * kMicrosecond;  // over the releases at 1 and 2 ms
  StampTask fine(port);
  const TaskId slow_id = port.AddTask(slow, {"slow", Trigger::periodic(kMillisecond, kMicrosecond), 3}).value();
  const TaskId fine_id = port.AddTask(fine, {"fine", Trigger::periodic(kMillisecond, kMicrosecond), 8}).value();
  ASSERT_EQ(port.Start(), PortError::kOk);
  const int64_t start_ns = GridStart(port, slow_id, kMicrosecond);

  WaitUntil(port, start_ns + 5 * kMillisecond + 500 * kMicrosecond);
  ASSERT_EQ(port.Stop(), PortError::kOk);

  EXPECT_EQ(port.overruns(slow_id), 2u);
  EXPECT_EQ(port.overruns(fine_id), 0u);
  EXPECT_EQ(fine.count, 6);      // preempted slow at 1 and 2 ms: releases 0..5
  EXPECT_EQ(slow.steps, 5);      // 0, once for 1-2 ms, 3, 4, 5
}

TEST_F(NvicPortM4Test, ShiftPeriodicMovesTheGrid) {
  StampTask task(port);
  const TaskId id = port.AddTask(task, {"round", Trigger::periodic(kMillisecond, kMicrosecond), 4}).value();
  ASSERT_EQ(port.Start(), PortError::kOk);
  const int64_t start_ns = GridStart(port, id, kMicrosecond);
  WaitUntil(port, start_ns + 1500 * kMicrosecond);  // ran at 0 and 1 ms

  ASSERT_EQ(port.ShiftPeriodic(id, 300 * kMicrosecond), PortError::kOk);
  WaitUntil(port, start_ns + 3500 * kMicrosecond);
  ASSERT_EQ(port.Stop(), PortError::kOk);

  ASSERT_EQ(task.count, 4);  // 0, 1, 2.3, 3.3 ms
  EXPECT_LT(task.stamps_ns[1] - (start_ns + 1000 * kMicrosecond), 10 * kMicrosecond);
  EXPECT_GE(task.stamps_ns[2], start_ns + 2300 * kMicrosecond);
  EXPECT_LT(task.stamps_ns[2] - (start_ns + 2300 * kMicrosecond), 10 * kMicrosecond);
  EXPECT_GE(task.stamps_ns[3], start_ns + 3300 * kMicrosecond);
  EXPECT_LT(task.stamps_ns[3] - (start_ns + 3300 * kMicrosecond), 10 * kMicrosecond);
}

}  // namespace
}  // namespace syrof::firmware::kernel
