#include "syrof/os/posix_port.h"

#include <gtest/gtest.h>

#include <atomic>
#include <chrono>
#include <condition_variable>
#include <mutex>
#include <thread>
#include <vector>

#include "port_contract.h"

namespace syrof::os {
namespace {

using std::chrono::milliseconds;
constexpr auto kPatience = std::chrono::seconds(10);  // generous: only bounds a hang

// Records each activation's time and lets a test wait for a count.
class CountingTask final : public Task {
 public:
  void Step(int64_t now_ns) override {
    std::lock_guard<std::mutex> guard(mutex_);
    times_ns_.push_back(now_ns);
    changed_.notify_all();
  }
  bool wait_for_steps(size_t count) {
    std::unique_lock<std::mutex> lock(mutex_);
    return changed_.wait_for(lock, kPatience, [&] { return times_ns_.size() >= count; });
  }
  std::vector<int64_t> times_ns() {
    std::lock_guard<std::mutex> guard(mutex_);
    return times_ns_;
  }

 private:
  std::mutex mutex_;
  std::condition_variable changed_;
  std::vector<int64_t> times_ns_;
};

TEST(PosixPortTest, PeriodicActivationsNeverComeBeforeTheirAbsoluteDueTime) {
  PosixPort port;
  CountingTask task;
  constexpr int64_t kPeriod = 5'000'000;
  constexpr int64_t kOffset = 2'000'000;
  ASSERT_TRUE(port.AddTask(task, {"periodic", Trigger::periodic(kPeriod, kOffset), 0}));
  const int64_t before_start = port.now_ns();
  ASSERT_EQ(port.Start(), PortError::kOk);

  ASSERT_TRUE(task.wait_for_steps(4));
  ASSERT_EQ(port.Stop(), PortError::kOk);

  const std::vector<int64_t> times = task.times_ns();
  for (size_t k = 0; k < times.size(); ++k) {
    EXPECT_GE(times[k], before_start + kOffset + static_cast<int64_t>(k) * kPeriod) << "activation " << k;
  }
}

TEST(PosixPortTest, NotifyWakesANotifiedTask) {
  PosixPort port;
  CountingTask task;
  const TaskId id = port.AddTask(task, {"notified", Trigger::notified(), 0}).value();
  ASSERT_EQ(port.Start(), PortError::kOk);

  port.Notify(id);

  EXPECT_TRUE(task.wait_for_steps(1));
}

// Blocks inside its first step until released, so a test can notify while a
// step is in progress.
class GatedTask final : public Task {
 public:
  void Step(int64_t) override {
    std::unique_lock<std::mutex> lock(mutex_);
    ++steps_;
    changed_.notify_all();
    changed_.wait(lock, [&] { return released_; });
  }
  bool wait_for_steps(int count) {
    std::unique_lock<std::mutex> lock(mutex_);
    return changed_.wait_for(lock, kPatience, [&] { return steps_ >= count; });
  }
  void release() {
    std::lock_guard<std::mutex> guard(mutex_);
    released_ = true;
    changed_.notify_all();
  }
  int steps() {
    std::lock_guard<std::mutex> guard(mutex_);
    return steps_;
  }

 private:
  std::mutex mutex_;
  std::condition_variable changed_;
  int steps_ = 0;
  bool released_ = false;
};

TEST(PosixPortTest, NotificationsDuringAStepCoalesceIntoOneMoreActivation) {
  PosixPort port;
  GatedTask task;
  const TaskId id = port.AddTask(task, {"gated", Trigger::notified(), 0}).value();
  ASSERT_EQ(port.Start(), PortError::kOk);
  port.Notify(id);
  ASSERT_TRUE(task.wait_for_steps(1));

  for (int i = 0; i < 5; ++i) port.Notify(id);
  task.release();
  ASSERT_TRUE(task.wait_for_steps(2));
  ASSERT_EQ(port.Stop(), PortError::kOk);

  EXPECT_EQ(task.steps(), 2);
}

TEST(PosixPortTest, StopJoinsAndNoStepRunsAfterIt) {
  PosixPort port;
  CountingTask periodic, notified;
  ASSERT_TRUE(port.AddTask(periodic, {"periodic", Trigger::periodic(1'000'000), 0}));
  const TaskId notified_id = port.AddTask(notified, {"notified", Trigger::notified(), 0}).value();
  ASSERT_EQ(port.Start(), PortError::kOk);
  ASSERT_TRUE(periodic.wait_for_steps(2));

  ASSERT_EQ(port.Stop(), PortError::kOk);
  const size_t steps_at_stop = periodic.times_ns().size();
  port.Notify(notified_id);
  std::this_thread::sleep_for(milliseconds(20));

  EXPECT_EQ(periodic.times_ns().size(), steps_at_stop);
  EXPECT_TRUE(notified.times_ns().empty());
}

TEST(PosixPortTest, ReportsEachLifecycleError) {
  PosixPort port({.max_tasks = 1});

  testing::ExpectEachLifecycleError(port);
}

// Two periodic tasks increment a plain counter in a read-modify-write that is
// only correct under the port's critical section.
class ContendingTask final : public Task {
 public:
  ContendingTask(Port& port, long& counter, std::atomic<int>& steps) : port_(port), counter_(counter), steps_(steps) {}
  void Step(int64_t) override {
    for (int i = 0; i < 1000; ++i) {
      CriticalSection section(port_);
      const long value = counter_;
      counter_ = value + 1;
    }
    ++steps_;
  }

 private:
  Port& port_;
  long& counter_;
  std::atomic<int>& steps_;
};

TEST(PosixPortTest, CriticalSectionExcludesOtherTasks) {
  PosixPort port;
  long counter = 0;
  std::atomic<int> steps{0};
  ContendingTask a(port, counter, steps), b(port, counter, steps);
  ASSERT_TRUE(port.AddTask(a, {"a", Trigger::periodic(100'000), 0}));
  ASSERT_TRUE(port.AddTask(b, {"b", Trigger::periodic(100'000), 0}));
  ASSERT_EQ(port.Start(), PortError::kOk);
  const auto deadline = std::chrono::steady_clock::now() + kPatience;
  while (steps.load() < 40 && std::chrono::steady_clock::now() < deadline) std::this_thread::sleep_for(milliseconds(1));

  ASSERT_EQ(port.Stop(), PortError::kOk);

  EXPECT_EQ(counter, 1000L * steps.load());
}

// A periodic task that shifts its own grid once, from its first step.
class ShiftingTask final : public Task {
 public:
  ShiftingTask(Port& port, int64_t delta_ns) : port_(port), delta_ns_(delta_ns) {}
  void set_id(TaskId id) { id_ = id; }
  void Step(int64_t now_ns) override {
    if (!shifted_) {
      shifted_ = true;
      result_ = port_.ShiftPeriodic(id_, delta_ns_);
    }
    counter_.Step(now_ns);
  }
  CountingTask& counter() { return counter_; }
  PortError result() const { return result_; }

 private:
  Port& port_;
  int64_t delta_ns_;
  TaskId id_ = 0;
  bool shifted_ = false;
  PortError result_ = PortError::kSystemError;
  CountingTask counter_;
};

TEST(PosixPortTest, StartAtPutsActivationsOnTheOriginsGridNeverBeforeTheirPoint) {
  PosixPort port;
  CountingTask task;
  constexpr int64_t kPeriod = 5'000'000;
  ASSERT_TRUE(port.AddTask(task, {"periodic", Trigger::periodic(kPeriod), 0}));
  // An origin in the past, off the port's start: activations stay on its grid.
  const int64_t origin = port.now_ns() + 1'234'567;
  std::this_thread::sleep_for(milliseconds(12));
  const int64_t before_start = port.now_ns();
  ASSERT_EQ(port.StartAt(origin), PortError::kOk);
  ASSERT_TRUE(task.wait_for_steps(3));
  ASSERT_EQ(port.Stop(), PortError::kOk);

  const std::vector<int64_t> times = task.times_ns();
  // The first activation is the first grid point not before the start.
  const int64_t first_point = origin + ((before_start - origin + kPeriod - 1) / kPeriod) * kPeriod;
  for (size_t k = 0; k < times.size(); ++k) {
    EXPECT_GE(times[k], first_point + static_cast<int64_t>(k) * kPeriod) << "activation " << k;
  }
}

// A DDS robot started after the run began (a joiner) gets the world's
// origin before its own port existed: a negative port time. It must keep
// the world's grid; it used to be refused, and the robot then started at
// its port's own zero, off the others' rounds by a fraction of one, which
// left a swarm that had a joiner in mixed modes to the end of the run.
TEST(PosixPortTest, AnOriginBeforeThePortExistedKeepsItsGrid) {
  constexpr int64_t kPeriod = 5'000'000;
  const int64_t origin_monotonic = PosixPort::MonotonicNowNs() - 3 * kPeriod - 1'234'567;
  PosixPort port;
  const int64_t origin = port.MonotonicToPort(origin_monotonic);
  ASSERT_LT(origin, 0) << "the port began after the origin";
  CountingTask task;
  ASSERT_TRUE(port.AddTask(task, {"periodic", Trigger::periodic(kPeriod), 0}));
  ASSERT_EQ(port.StartAt(origin), PortError::kOk);
  ASSERT_TRUE(task.wait_for_steps(3));
  ASSERT_EQ(port.Stop(), PortError::kOk);
  for (const int64_t time : task.times_ns()) {
    EXPECT_EQ((port.PortToMonotonic(time) - origin_monotonic) % kPeriod, 0) << "an activation off the world's grid";
  }
}

// A step is given its release on the grid, not the moment its thread woke
// (always a little later): a beacon that arrives between the two belongs to
// the next round, and a DDS robot whose thread woke late counted such
// beacons one round early (docs/os.md).
TEST(PosixPortTest, APeriodicStepIsGivenItsReleaseOnTheGridNotTheTimeItsThreadWoke) {
  class ClockReadingTask final : public Task {
   public:
    explicit ClockReadingTask(const PosixPort& port) : port_(port) {}
    void Step(int64_t now_ns) override {
      const int64_t clock = port_.now_ns();
      std::lock_guard<std::mutex> guard(mutex_);
      given.push_back(now_ns);
      read.push_back(clock);
    }
    size_t steps() {
      std::lock_guard<std::mutex> guard(mutex_);
      return given.size();
    }
    std::vector<int64_t> given, read;

   private:
    const PosixPort& port_;
    std::mutex mutex_;
  };
  PosixPort port;
  ClockReadingTask task(port);
  constexpr int64_t kPeriod = 4'000'000;
  ASSERT_TRUE(port.AddTask(task, {"periodic", Trigger::periodic(kPeriod, kPeriod), 0}));
  const int64_t origin = port.now_ns() + 2'000'000;
  ASSERT_EQ(port.StartAt(origin), PortError::kOk);
  const auto deadline = std::chrono::steady_clock::now() + kPatience;
  while (task.steps() < 5 && std::chrono::steady_clock::now() < deadline) std::this_thread::sleep_for(milliseconds(1));
  ASSERT_EQ(port.Stop(), PortError::kOk);
  ASSERT_GE(task.given.size(), 5u);
  for (size_t k = 0; k < task.given.size(); ++k) {
    EXPECT_EQ((task.given[k] - origin - kPeriod) % kPeriod, 0) << "activation " << k << " is off the grid";
    EXPECT_GE(task.read[k], task.given[k]) << "activation " << k;
    if (k > 0) {
      EXPECT_GT(task.given[k], task.given[k - 1]);
    }
  }
}

TEST(PosixPortTest, TwoPortsStartedApartShareTheGridOfOneMonotonicOrigin) {
  PosixPort first;
  std::this_thread::sleep_for(milliseconds(3));
  PosixPort second;  // a later epoch: port times differ, monotonic times do not
  const int64_t origin_monotonic = PosixPort::MonotonicNowNs() + 20'000'000;
  EXPECT_EQ(first.PortToMonotonic(first.MonotonicToPort(origin_monotonic)), origin_monotonic);
  EXPECT_GT(first.MonotonicToPort(origin_monotonic), second.MonotonicToPort(origin_monotonic));
  CountingTask a, b;
  constexpr int64_t kPeriod = 10'000'000;
  ASSERT_TRUE(first.AddTask(a, {"a", Trigger::periodic(kPeriod), 0}));
  ASSERT_TRUE(second.AddTask(b, {"b", Trigger::periodic(kPeriod), 0}));
  ASSERT_EQ(first.StartAt(first.MonotonicToPort(origin_monotonic)), PortError::kOk);
  ASSERT_EQ(second.StartAt(second.MonotonicToPort(origin_monotonic)), PortError::kOk);
  ASSERT_TRUE(a.wait_for_steps(2));
  ASSERT_TRUE(b.wait_for_steps(2));
  ASSERT_EQ(first.Stop(), PortError::kOk);
  ASSERT_EQ(second.Stop(), PortError::kOk);
  // Neither runs before the shared origin's grid points (no upper bound: a
  // loaded machine may wake late).
  EXPECT_GE(first.PortToMonotonic(a.times_ns()[0]), origin_monotonic);
  EXPECT_GE(second.PortToMonotonic(b.times_ns()[0]), origin_monotonic);
  EXPECT_GE(first.PortToMonotonic(a.times_ns()[1]), origin_monotonic + kPeriod);
  EXPECT_GE(second.PortToMonotonic(b.times_ns()[1]), origin_monotonic + kPeriod);
}

TEST(PosixPortTest, ShiftPeriodicFromTheStepMovesTheNextActivation) {
  PosixPort port;
  constexpr int64_t kPeriod = 5'000'000;
  constexpr int64_t kShift = 40'000'000;  // eight periods later
  ShiftingTask task(port, kShift);
  const auto id = port.AddTask(task, {"periodic", Trigger::periodic(kPeriod), 0});
  ASSERT_TRUE(id);
  task.set_id(id.value());
  const int64_t before_start = port.now_ns();
  ASSERT_EQ(port.Start(), PortError::kOk);
  ASSERT_TRUE(task.counter().wait_for_steps(3));
  ASSERT_EQ(port.Stop(), PortError::kOk);

  EXPECT_EQ(task.result(), PortError::kOk);
  const std::vector<int64_t> times = task.counter().times_ns();
  for (size_t k = 1; k < times.size(); ++k) {
    EXPECT_GE(times[k], before_start + kShift + static_cast<int64_t>(k) * kPeriod) << "activation " << k;
  }
}

TEST(PosixPortTest, ShiftPeriodicNeverMovesBeforeNowAndRefusesNotifiedAndUnknownTasks) {
  PosixPort port;
  CountingTask periodic, notified;
  constexpr int64_t kPeriod = 2'000'000'000;  // far: only a shift can bring it near
  const auto periodic_id = port.AddTask(periodic, {"periodic", Trigger::periodic(kPeriod, kPeriod), 0});
  const auto notified_id = port.AddTask(notified, {"notified", Trigger::notified(), 0});
  ASSERT_TRUE(periodic_id);
  ASSERT_TRUE(notified_id);
  EXPECT_EQ(port.ShiftPeriodic(periodic_id.value(), 5), PortError::kOk);  // before Start: nothing to move
  ASSERT_EQ(port.Start(), PortError::kOk);
  const int64_t shifted_at = port.now_ns();
  // From another thread while the task waits: far into the past means now.
  EXPECT_EQ(port.ShiftPeriodic(periodic_id.value(), -100 * kPeriod), PortError::kOk);
  ASSERT_TRUE(periodic.wait_for_steps(1));
  EXPECT_EQ(port.ShiftPeriodic(notified_id.value(), 1), PortError::kInvalidTrigger);
  EXPECT_EQ(port.ShiftPeriodic(9, 1), PortError::kInvalidTrigger);
  ASSERT_EQ(port.Stop(), PortError::kOk);
  const std::vector<int64_t> times = periodic.times_ns();
  ASSERT_GE(times.size(), 1u);
  EXPECT_GE(times[0], shifted_at);
  EXPECT_LT(times[0], shifted_at + kPeriod);  // woke for the shift, not for the old due time
}

// A step that takes longer than several periods, as a stopped process does.
class SlowFirstStepTask final : public Task {
 public:
  void Step(int64_t now_ns) override {
    if (first_) {
      first_ = false;
      std::this_thread::sleep_for(milliseconds(32));
    }
    counter_.Step(now_ns);
  }
  CountingTask& counter() { return counter_; }

 private:
  bool first_ = true;
  CountingTask counter_;
};

TEST(PosixPortTest, AnActivationLateByPeriodsSkipsThePassedGridPointsInsteadOfRunningThemBackToBack) {
  PosixPort port;
  SlowFirstStepTask task;
  constexpr int64_t kPeriod = 5'000'000;
  ASSERT_TRUE(port.AddTask(task, {"periodic", Trigger::periodic(kPeriod), 0}));
  const int64_t before_start = port.now_ns();
  ASSERT_EQ(port.Start(), PortError::kOk);
  ASSERT_TRUE(task.counter().wait_for_steps(3));
  ASSERT_EQ(port.Stop(), PortError::kOk);
  const std::vector<int64_t> times = task.counter().times_ns();
  // The first step ends 32 ms in, six grid points late: the late point runs
  // once, right away, and the third activation is back on the grid after
  // the passed points (7 periods in), not one of a burst.
  EXPECT_GE(times[1], before_start + 6 * kPeriod);
  EXPECT_GE(times[2], before_start + 7 * kPeriod);
}

}  // namespace
}  // namespace syrof::os
