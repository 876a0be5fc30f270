// NvicPort's dispatch logic on the host, over a model of the NVIC
// (fake_hardware.h): priorities, preemption, the release calendar, overruns,
// coalescing, the kernel mask, and the port contract.
#include "syrof/firmware/kernel/nvic_port.h"

#include <gtest/gtest.h>

#include <cstdint>
#include <string>
#include <vector>

#include "../../core/os/port_contract.h"
#include "fake_hardware.h"

namespace syrof::firmware::kernel {
namespace {

using os::PortError;
using os::TaskId;
using os::Trigger;
using testing::FakeHardware;

constexpr int64_t kMillisecond = 1'000'000;

// Logs "<time_ms>:<label>" when its step begins (and "<label>/" when it ends,
// if asked), optionally spends time and notifies other tasks mid-step.
class ScriptedTask final : public os::Task {
 public:
  ScriptedTask(FakeHardware& hardware, std::vector<std::string>& log, std::string label)
      : hardware_(hardware), log_(log), label_(std::move(label)) {}
  void Step(int64_t now_ns) override {
    log_.push_back(std::to_string(now_ns / kMillisecond) + ":" + label_);
    step_times_ns.push_back(now_ns);
    const int64_t spend = first_step_ns >= 0 && step_times_ns.size() == 1 ? first_step_ns : step_ns;
    if (spend > 0) hardware_.Spend(spend);
    for (const TaskId target : notify) port->Notify(target);
    if (log_end) log_.push_back(label_ + "/");
  }

  NvicPort* port = nullptr;
  std::vector<TaskId> notify;
  int64_t step_ns = 0;
  int64_t first_step_ns = -1;
  bool log_end = false;
  std::vector<int64_t> step_times_ns;

 private:
  FakeHardware& hardware_;
  std::vector<std::string>& log_;
  std::string label_;
};

class NvicPortTest : public ::testing::Test {
 protected:
  NvicPortTest() { hardware.Attach(port); }

  TaskId Add(ScriptedTask& task, const Trigger& trigger, uint8_t priority) {
    task.port = &port;
    const auto id = port.AddTask(task, {"task", trigger, priority});
    EXPECT_TRUE(id.ok());
    return id.value();
  }

  FakeHardware hardware;
  NvicPort port{hardware};
  std::vector<std::string> log;
};

TEST_F(NvicPortTest, PeriodicTaskRunsAtStartPlusOffsetPlusWholePeriods) {
  ScriptedTask task(hardware, log, "t");
  const TaskId id = Add(task, Trigger::periodic(10 * kMillisecond, 3 * kMillisecond), 0);
  hardware.AdvanceTo(100 * kMillisecond);
  ASSERT_EQ(port.Start(), PortError::kOk);

  hardware.AdvanceTo(133 * kMillisecond);

  EXPECT_EQ(log, (std::vector<std::string>{"103:t", "113:t", "123:t", "133:t"}));
  EXPECT_EQ(port.next_release_ns(id), 143 * kMillisecond);
  EXPECT_EQ(hardware.alarm_ns(), 143 * kMillisecond);
  EXPECT_EQ(port.overruns(id), 0u);
  EXPECT_FALSE(hardware.unmasked_clock_reads);
}

// The emulated robot's Start frame: its grid begins when the frame's first
// byte came in, though the rest of the frame took up to 27 ms to arrive.
TEST_F(NvicPortTest, StartAtPutsTheGridOnAnInstantAlreadyPast) {
  ScriptedTask task(hardware, log, "t");
  const TaskId id = Add(task, Trigger::periodic(10 * kMillisecond, 3 * kMillisecond), 0);
  hardware.AdvanceTo(126 * kMillisecond);
  EXPECT_EQ(port.StartAt(127 * kMillisecond), PortError::kUnsupported);  // not yet
  ASSERT_EQ(port.StartAt(100 * kMillisecond), PortError::kOk);

  hardware.AdvanceTo(144 * kMillisecond);

  // 103, 113 and 123 were due at the start: one step for them, then the grid.
  ASSERT_FALSE(log.empty());
  EXPECT_EQ(log.back(), "143:t");
  EXPECT_EQ(std::vector<std::string>(log.end() - 2, log.end()), (std::vector<std::string>{"133:t", "143:t"}));
  EXPECT_EQ(port.next_release_ns(id), 153 * kMillisecond);
  EXPECT_EQ(port.StartAt(100 * kMillisecond), PortError::kAlreadyStarted);
  EXPECT_FALSE(hardware.unmasked_clock_reads);
}

TEST_F(NvicPortTest, LateTimerCatchesUpOnTheGridAndCountsTheMissedReleases) {
  ScriptedTask task(hardware, log, "t");
  const TaskId id = Add(task, Trigger::periodic(10 * kMillisecond, 3 * kMillisecond), 0);
  ASSERT_EQ(port.Start(), PortError::kOk);

  hardware.AdvanceTo(35 * kMillisecond, /*timer_late=*/true);  // releases 3, 13, 23, 33 merged
  hardware.AdvanceTo(54 * kMillisecond);

  EXPECT_EQ(log, (std::vector<std::string>{"33:t", "43:t", "53:t"}));  // each step given its release
  EXPECT_EQ(port.overruns(id), 3u);
  EXPECT_EQ(port.next_release_ns(id), 63 * kMillisecond);
}

TEST_F(NvicPortTest, ThousandsOfPeriodsNeverDrift) {
  ScriptedTask task(hardware, log, "t");
  task.step_ns = 3 * kMillisecond + 7;  // steps take time; releases must not slide
  const TaskId id = Add(task, Trigger::periodic(10 * kMillisecond + 1, kMillisecond), 2);
  ASSERT_EQ(port.Start(), PortError::kOk);

  hardware.AdvanceTo(10'000 * (10 * kMillisecond + 1));

  ASSERT_EQ(task.step_times_ns.size(), 10'000u);
  for (size_t k = 0; k < task.step_times_ns.size(); ++k) {
    ASSERT_EQ(task.step_times_ns[k], kMillisecond + static_cast<int64_t>(k) * (10 * kMillisecond + 1)) << k;
  }
  EXPECT_EQ(port.overruns(id), 0u);
}

// The lower task runs 2 ms after its release (the higher level's step
// first) and is given its release, not the time it ran: a frame that arrived
// in those 2 ms belongs to its next activation.
TEST_F(NvicPortTest, APeriodicStepKeptWaitingByAHigherLevelIsGivenItsRelease) {
  ScriptedTask low(hardware, log, "low"), high(hardware, log, "high");
  high.step_ns = 2 * kMillisecond;
  Add(low, Trigger::periodic(10 * kMillisecond, 10 * kMillisecond), 1);
  Add(high, Trigger::periodic(10 * kMillisecond, 10 * kMillisecond), 5);
  ASSERT_EQ(port.Start(), PortError::kOk);

  hardware.AdvanceTo(25 * kMillisecond);

  EXPECT_EQ(log, (std::vector<std::string>{"10:high", "10:low", "20:high", "20:low"}));
  EXPECT_EQ(low.step_times_ns, (std::vector<int64_t>{10 * kMillisecond, 20 * kMillisecond}));
}

TEST_F(NvicPortTest, HigherLevelPreemptsALowerStepAtOnce) {
  ScriptedTask low(hardware, log, "low"), high(hardware, log, "high");
  low.log_end = true;
  high.log_end = true;
  const TaskId low_id = Add(low, Trigger::notified(), 1);
  const TaskId high_id = Add(high, Trigger::notified(), 5);
  low.notify = {high_id};
  ASSERT_EQ(port.Start(), PortError::kOk);

  port.Notify(low_id);

  EXPECT_EQ(log, (std::vector<std::string>{"0:low", "0:high", "high/", "low/"}));
  EXPECT_EQ(hardware.entries, (std::vector<std::string>{"L1", "L5"}));
}

// The robot images swap priorities 1 and 2 (motion above the round task),
// so that an epoch start's long round step no longer holds motion back.
TEST_F(NvicPortTest, AMappedPriorityRunsAtItsLevelAndPreemptsWhatItNowOutranks) {
  ASSERT_EQ(port.MapPriority(1, 2), PortError::kOk);
  ASSERT_EQ(port.MapPriority(2, 1), PortError::kOk);
  ScriptedTask round(hardware, log, "round"), motion(hardware, log, "motion");
  round.log_end = true;
  motion.log_end = true;
  const TaskId round_id = Add(round, Trigger::notified(), 2);
  const TaskId motion_id = Add(motion, Trigger::notified(), 1);
  EXPECT_EQ(port.level(round_id), 1);
  EXPECT_EQ(port.level(motion_id), 2);
  round.notify = {motion_id};
  ASSERT_EQ(port.Start(), PortError::kOk);
  EXPECT_EQ(port.MapPriority(3, 4), PortError::kAlreadyStarted);

  port.Notify(round_id);

  EXPECT_EQ(log, (std::vector<std::string>{"0:round", "0:motion", "motion/", "round/"}));
  EXPECT_EQ(hardware.entries, (std::vector<std::string>{"L1", "L2"}));
}

TEST_F(NvicPortTest, MapPriorityRefusesLevelsPastTheLast) {
  EXPECT_EQ(port.MapPriority(kLevelCount, 0), PortError::kUnsupported);
  EXPECT_EQ(port.MapPriority(0, kLevelCount), PortError::kUnsupported);
}

TEST_F(NvicPortTest, EqualOrLowerLevelRunsAfterTheNotifyingStep) {
  ScriptedTask high(hardware, log, "high"), same(hardware, log, "same"), low(hardware, log, "low");
  high.log_end = true;
  const TaskId high_id = Add(high, Trigger::notified(), 5);
  const TaskId same_id = Add(same, Trigger::notified(), 5);
  const TaskId low_id = Add(low, Trigger::notified(), 1);
  high.notify = {low_id, same_id};
  ASSERT_EQ(port.Start(), PortError::kOk);

  port.Notify(high_id);

  EXPECT_EQ(log, (std::vector<std::string>{"0:high", "high/", "0:same", "0:low"}));
}

TEST_F(NvicPortTest, ReadyTasksOfOneLevelRunInRegistrationOrderInOneEntry) {
  ScriptedTask first(hardware, log, "first"), second(hardware, log, "second"), third(hardware, log, "third");
  const TaskId first_id = Add(first, Trigger::notified(), 3);
  const TaskId second_id = Add(second, Trigger::notified(), 3);
  const TaskId third_id = Add(third, Trigger::notified(), 3);
  ASSERT_EQ(port.Start(), PortError::kOk);

  port.Lock();
  port.Notify(third_id);
  port.Notify(first_id);
  port.Notify(second_id);
  port.Unlock();

  EXPECT_EQ(log, (std::vector<std::string>{"0:first", "0:second", "0:third"}));
  EXPECT_EQ(hardware.entries, (std::vector<std::string>{"L3"}));
}

TEST_F(NvicPortTest, SimultaneousReleasesRunHighestLevelFirst) {
  ScriptedTask low(hardware, log, "low"), high(hardware, log, "high"), middle(hardware, log, "middle");
  Add(low, Trigger::periodic(10 * kMillisecond), 0);
  Add(high, Trigger::periodic(10 * kMillisecond), 9);
  Add(middle, Trigger::periodic(5 * kMillisecond), 4);
  ASSERT_EQ(port.Start(), PortError::kOk);

  hardware.AdvanceTo(10 * kMillisecond);

  EXPECT_EQ(log, (std::vector<std::string>{"0:high", "0:middle", "0:low", "5:middle", "10:high", "10:middle",
                                           "10:low"}));
}

TEST_F(NvicPortTest, NotificationsBeforeTheStepRunsCoalesce) {
  ScriptedTask publisher(hardware, log, "publisher"), subscriber(hardware, log, "subscriber");
  const TaskId publisher_id = Add(publisher, Trigger::notified(), 6);
  const TaskId subscriber_id = Add(subscriber, Trigger::notified(), 2);
  publisher.notify = {subscriber_id, subscriber_id, subscriber_id};
  ASSERT_EQ(port.Start(), PortError::kOk);

  port.Notify(publisher_id);

  EXPECT_EQ(port.steps(subscriber_id), 1u);
  EXPECT_EQ(hardware.entries, (std::vector<std::string>{"L6", "L2"}));
}

// Notifies itself during its first step only.
class SelfNotifyingTask final : public os::Task {
 public:
  void Step(int64_t) override {
    if (steps++ == 0) port->Notify(id);
  }
  NvicPort* port = nullptr;
  TaskId id = 0;
  int steps = 0;
};

TEST_F(NvicPortTest, NotifyDuringItsOwnStepRunsItOnceMoreInTheSameEntry) {
  SelfNotifyingTask task;
  task.port = &port;
  task.id = port.AddTask(task, {"self", Trigger::notified(), 2}).value();
  ASSERT_EQ(port.Start(), PortError::kOk);

  port.Notify(task.id);

  EXPECT_EQ(task.steps, 2);
  EXPECT_EQ(port.steps(task.id), 2u);
}

TEST_F(NvicPortTest, LockMasksTheTimerAndEveryLevelUntilUnlock) {
  ScriptedTask periodic(hardware, log, "periodic"), notified(hardware, log, "notified");
  Add(periodic, Trigger::periodic(10 * kMillisecond, 10 * kMillisecond), 9);
  const TaskId notified_id = Add(notified, Trigger::notified(), 9);
  ASSERT_EQ(port.Start(), PortError::kOk);

  port.Lock();
  port.Notify(notified_id);
  hardware.Spend(12 * kMillisecond);  // past the release at 10
  EXPECT_TRUE(log.empty());
  EXPECT_EQ(hardware.timer_interrupts, 0);
  port.Unlock();

  // Both run at 12; the periodic step is given its release at 10.
  EXPECT_EQ(log, (std::vector<std::string>{"10:periodic", "12:notified"}));
  EXPECT_EQ(hardware.entries, (std::vector<std::string>{"T", "L9"}));
  EXPECT_EQ(port.next_release_ns(0), 20 * kMillisecond);
}

TEST_F(NvicPortTest, APeriodicTaskStillRunningAtItsNextReleaseIsAnOverrun) {
  ScriptedTask slow(hardware, log, "slow"), fine(hardware, log, "fine");
  slow.first_step_ns = 25 * kMillisecond;  // covers the releases at 10 and 20
  const TaskId slow_id = Add(slow, Trigger::periodic(10 * kMillisecond), 1);
  const TaskId fine_id = Add(fine, Trigger::periodic(10 * kMillisecond), 8);
  ASSERT_EQ(port.Start(), PortError::kOk);

  hardware.AdvanceTo(35 * kMillisecond);

  // The release at 10 finds slow running (one miss, queued once); the one at
  // 20 finds it running and already queued (another miss, nothing more
  // queued). It runs again at 25, given its latest release (20), then keeps
  // the grid.
  EXPECT_EQ(slow.step_times_ns,
            (std::vector<int64_t>{0, 20 * kMillisecond, 30 * kMillisecond}));
  EXPECT_EQ(port.overruns(slow_id), 2u);
  EXPECT_EQ(port.overruns(fine_id), 0u);
  EXPECT_EQ(port.steps(fine_id), 4u);  // preempted slow at 10, 20, 30
  EXPECT_EQ(port.total_overruns(), 2u);
}

TEST_F(NvicPortTest, ShiftPeriodicMovesTheGridFromTheNextReleaseAndNeverBeforeNow) {
  ScriptedTask task(hardware, log, "t");
  const TaskId id = Add(task, Trigger::periodic(10 * kMillisecond), 3);
  ASSERT_EQ(port.Start(), PortError::kOk);
  hardware.AdvanceTo(12 * kMillisecond);  // ran at 0 and 10

  EXPECT_EQ(port.ShiftPeriodic(id, 3 * kMillisecond), PortError::kOk);
  hardware.AdvanceTo(34 * kMillisecond);
  EXPECT_EQ(port.ShiftPeriodic(id, -30 * kMillisecond), PortError::kOk);  // would be 13: clamped to 34
  hardware.AdvanceTo(50 * kMillisecond);

  EXPECT_EQ(log, (std::vector<std::string>{"0:t", "10:t", "23:t", "33:t", "34:t", "44:t"}));
  EXPECT_EQ(port.overruns(id), 0u);
}

TEST_F(NvicPortTest, ShiftPeriodicRejectsNotifiedTasksAndUnknownIds) {
  ScriptedTask task(hardware, log, "t");
  const TaskId id = Add(task, Trigger::notified(), 3);

  EXPECT_EQ(port.ShiftPeriodic(id, 1), PortError::kInvalidTrigger);
  EXPECT_EQ(port.ShiftPeriodic(static_cast<TaskId>(7), 1), PortError::kInvalidTrigger);
}

TEST_F(NvicPortTest, NotifyIgnoresPeriodicTasksUnknownIdsAndAStoppedPort) {
  ScriptedTask periodic(hardware, log, "periodic"), notified(hardware, log, "notified");
  const TaskId periodic_id = Add(periodic, Trigger::periodic(10 * kMillisecond, 5 * kMillisecond), 0);
  const TaskId notified_id = Add(notified, Trigger::notified(), 0);

  port.Notify(notified_id);  // not started yet
  ASSERT_EQ(port.Start(), PortError::kOk);
  port.Notify(periodic_id);
  port.Notify(static_cast<TaskId>(99));
  hardware.AdvanceTo(1);

  EXPECT_TRUE(log.empty());
  EXPECT_EQ(hardware.pend_calls, 0);
}

TEST_F(NvicPortTest, StopDropsReadyTasksAndARestartBeginsANewGrid) {
  ScriptedTask periodic(hardware, log, "periodic"), notified(hardware, log, "notified");
  Add(periodic, Trigger::periodic(10 * kMillisecond, 2 * kMillisecond), 4);
  const TaskId notified_id = Add(notified, Trigger::notified(), 4);
  ASSERT_EQ(port.Start(), PortError::kOk);
  hardware.AdvanceTo(5 * kMillisecond);

  port.Lock();
  port.Notify(notified_id);  // ready, but dropped by Stop
  ASSERT_EQ(port.Stop(), PortError::kOk);
  port.Unlock();
  hardware.AdvanceTo(25 * kMillisecond);
  EXPECT_EQ(hardware.alarm_ns(), -1);
  ASSERT_EQ(port.Start(), PortError::kOk);
  hardware.AdvanceTo(40 * kMillisecond);

  EXPECT_EQ(log, (std::vector<std::string>{"2:periodic", "27:periodic", "37:periodic"}));
  EXPECT_TRUE(port.running());
}

TEST_F(NvicPortTest, PriorityBeyondTheLevelsIsUnsupported) {
  ScriptedTask task(hardware, log, "t");

  EXPECT_EQ(port.AddTask(task, {"t", Trigger::notified(), kLevelCount}).error(), PortError::kUnsupported);
  EXPECT_TRUE(port.AddTask(task, {"t", Trigger::notified(), kLevelCount - 1}).ok());
}

TEST_F(NvicPortTest, KernelCallsRestoreTheMaskTheyFound) {
  ScriptedTask task(hardware, log, "t");
  const TaskId id = Add(task, Trigger::notified(), 0);
  ASSERT_EQ(port.Start(), PortError::kOk);

  port.Lock();
  port.Notify(id);
  (void)port.now_ns();
  EXPECT_TRUE(hardware.masked());
  port.Unlock();

  EXPECT_FALSE(hardware.masked());
  EXPECT_EQ(port.steps(id), 1u);
}

TEST(NvicPortContractTest, ReportsEachLifecycleError) {
  FakeHardware hardware;
  NvicPort port(hardware, 1);
  hardware.Attach(port);

  os::testing::ExpectEachLifecycleError(port);
}

TEST(NvicPortContractTest, HoldsAtMostKMaxTasks) {
  FakeHardware hardware;
  NvicPort port(hardware, 1000);
  os::testing::IdleTask task;
  for (uint16_t i = 0; i < kMaxTasks; ++i) ASSERT_TRUE(port.AddTask(task, {"t", Trigger::notified(), 0}).ok());

  EXPECT_EQ(port.AddTask(task, {"t", Trigger::notified(), 0}).error(), PortError::kTooManyTasks);
}

TEST(NvicPortDeathTest, NestedLockIsABug) {
  FakeHardware hardware;
  NvicPort port(hardware);

  EXPECT_DEATH_IF_SUPPORTED(
      {
        os::CriticalSection outer(port);
        os::CriticalSection inner(port);
      },
      "SYROF_CHECK failed");
}

}  // namespace
}  // namespace syrof::firmware::kernel
