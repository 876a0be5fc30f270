#include "syrof/os/sim_port.h"

#include <gtest/gtest.h>

#include <algorithm>
#include <cstdint>
#include <memory>
#include <random>
#include <span>
#include <string>
#include <utility>
#include <vector>

#include "port_contract.h"

namespace syrof::os {
namespace {

constexpr int64_t kMillisecond = 1'000'000;

// Appends "<time_ms>:<label>" to a shared log each step.
class RecordingTask final : public Task {
 public:
  RecordingTask(std::vector<std::string>& log, std::string label) : log_(log), label_(std::move(label)) {}
  void Step(int64_t now_ns) override {
    log_.push_back(std::to_string(now_ns / kMillisecond) + ":" + label_);
    ++steps_;
  }
  int steps() const { return steps_; }

 private:
  std::vector<std::string>& log_;
  std::string label_;
  int steps_ = 0;
};

// Notifies a list of tasks, then records itself.
class NotifyingTask final : public Task {
 public:
  NotifyingTask(Port& port, std::vector<std::string>& log, std::string label)
      : port_(port), log_(log), label_(std::move(label)) {}
  void add_target(TaskId task) { targets_.push_back(task); }
  void Step(int64_t now_ns) override {
    for (const TaskId target : targets_) port_.Notify(target);
    log_.push_back(std::to_string(now_ns / kMillisecond) + ":" + label_);
  }

 private:
  Port& port_;
  std::vector<std::string>& log_;
  std::string label_;
  std::vector<TaskId> targets_;
};

TEST(SimPortTest, PeriodicTaskRunsAtOffsetPlusWholePeriods) {
  SimScheduler scheduler(4);
  SimPort port(scheduler);
  std::vector<std::string> log;
  RecordingTask task(log, "t");
  ASSERT_TRUE(port.AddTask(task, {"t", Trigger::periodic(10 * kMillisecond, 3 * kMillisecond), 0}));
  ASSERT_EQ(port.Start(), PortError::kOk);

  scheduler.RunUntil(33 * kMillisecond);

  EXPECT_EQ(log, (std::vector<std::string>{"3:t", "13:t", "23:t", "33:t"}));
  EXPECT_EQ(scheduler.now_ns(), 33 * kMillisecond);
  EXPECT_EQ(scheduler.next_activation_ns(), 43 * kMillisecond);
}

TEST(SimPortTest, RunUntilAdvancesTheClockEvenWhenIdle) {
  SimScheduler scheduler(1);

  scheduler.RunUntil(5 * kMillisecond);
  scheduler.RunUntil(2 * kMillisecond);  // never goes backwards

  EXPECT_EQ(scheduler.now_ns(), 5 * kMillisecond);
  EXPECT_FALSE(scheduler.RunNext());
  EXPECT_EQ(scheduler.next_activation_ns(), -1);
}

TEST(SimPortTest, SameInstantRunsHigherPriorityFirstThenRegistrationOrderAcrossPorts) {
  SimScheduler scheduler(8);
  SimPort robot_a(scheduler, "a");
  SimPort robot_b(scheduler, "b");
  std::vector<std::string> log;
  RecordingTask a_low(log, "a_low"), b_high(log, "b_high"), a_high(log, "a_high"), b_low(log, "b_low");
  const Trigger every_10ms = Trigger::periodic(10 * kMillisecond);
  ASSERT_TRUE(robot_a.AddTask(a_low, {"a_low", every_10ms, 1}));
  ASSERT_TRUE(robot_b.AddTask(b_high, {"b_high", every_10ms, 5}));
  ASSERT_TRUE(robot_a.AddTask(a_high, {"a_high", every_10ms, 5}));
  ASSERT_TRUE(robot_b.AddTask(b_low, {"b_low", every_10ms, 1}));
  ASSERT_EQ(robot_b.Start(), PortError::kOk);
  ASSERT_EQ(robot_a.Start(), PortError::kOk);

  scheduler.RunUntil(0);

  EXPECT_EQ(log, (std::vector<std::string>{"0:b_high", "0:a_high", "0:a_low", "0:b_low"}));
}

TEST(SimPortTest, NotifiedTaskRunsAfterTheNotifyingStepCompletesAtTheSameInstant) {
  SimScheduler scheduler(4);
  SimPort port(scheduler);
  std::vector<std::string> log;
  NotifyingTask publisher(port, log, "publisher");
  RecordingTask subscriber(log, "subscriber");
  ASSERT_TRUE(port.AddTask(publisher, {"publisher", Trigger::periodic(10 * kMillisecond, 7 * kMillisecond), 0}));
  const auto subscriber_id = port.AddTask(subscriber, {"subscriber", Trigger::notified(), 9});
  ASSERT_TRUE(subscriber_id);
  publisher.add_target(subscriber_id.value());
  ASSERT_EQ(port.Start(), PortError::kOk);

  scheduler.RunUntil(17 * kMillisecond);

  // The subscriber has the higher priority, yet the publisher's step runs to
  // completion before it.
  EXPECT_EQ(log, (std::vector<std::string>{"7:publisher", "7:subscriber", "17:publisher", "17:subscriber"}));
}

TEST(SimPortTest, NotificationsBeforeTheStepRunsCoalesce) {
  SimScheduler scheduler(4);
  SimPort port(scheduler);
  std::vector<std::string> log;
  NotifyingTask publisher(port, log, "publisher");
  RecordingTask subscriber(log, "subscriber");
  ASSERT_TRUE(port.AddTask(publisher, {"publisher", Trigger::periodic(10 * kMillisecond), 0}));
  const TaskId subscriber_id = port.AddTask(subscriber, {"subscriber", Trigger::notified(), 0}).value();
  for (int i = 0; i < 3; ++i) publisher.add_target(subscriber_id);
  ASSERT_EQ(port.Start(), PortError::kOk);

  scheduler.RunUntil(0);

  EXPECT_EQ(subscriber.steps(), 1);
}

TEST(SimPortTest, NotifyIgnoresPeriodicTasksUnknownIdsAndStoppedPorts) {
  SimScheduler scheduler(4);
  SimPort port(scheduler);
  std::vector<std::string> log;
  RecordingTask periodic(log, "periodic");
  RecordingTask notified(log, "notified");
  const TaskId periodic_id = port.AddTask(periodic, {"periodic", Trigger::periodic(10 * kMillisecond, 5), 0}).value();
  const TaskId notified_id = port.AddTask(notified, {"notified", Trigger::notified(), 0}).value();

  port.Notify(notified_id);  // not started yet
  ASSERT_EQ(port.Start(), PortError::kOk);
  port.Notify(periodic_id);
  port.Notify(static_cast<TaskId>(99));
  scheduler.RunUntil(1);

  EXPECT_TRUE(log.empty());
}

TEST(SimPortTest, StopDropsPendingActivationsOfThatPortOnly) {
  SimScheduler scheduler(4);
  SimPort crashed(scheduler, "crashed");
  SimPort survivor(scheduler, "survivor");
  std::vector<std::string> log;
  RecordingTask crashed_task(log, "crashed");
  RecordingTask survivor_task(log, "survivor");
  ASSERT_TRUE(crashed.AddTask(crashed_task, {"crashed", Trigger::periodic(10 * kMillisecond), 0}));
  ASSERT_TRUE(survivor.AddTask(survivor_task, {"survivor", Trigger::periodic(10 * kMillisecond), 0}));
  ASSERT_EQ(crashed.Start(), PortError::kOk);
  ASSERT_EQ(survivor.Start(), PortError::kOk);
  scheduler.RunUntil(10 * kMillisecond);

  ASSERT_EQ(crashed.Stop(), PortError::kOk);
  scheduler.RunUntil(30 * kMillisecond);

  EXPECT_EQ(crashed_task.steps(), 2);
  EXPECT_EQ(survivor_task.steps(), 4);
  EXPECT_FALSE(crashed.running());
}

TEST(SimPortTest, RestartedPortSchedulesFromTheRestartInstant) {
  SimScheduler scheduler(2);
  SimPort port(scheduler);
  std::vector<std::string> log;
  RecordingTask task(log, "t");
  ASSERT_TRUE(port.AddTask(task, {"t", Trigger::periodic(10 * kMillisecond, 2 * kMillisecond), 0}));
  ASSERT_EQ(port.Start(), PortError::kOk);
  scheduler.RunUntil(5 * kMillisecond);
  ASSERT_EQ(port.Stop(), PortError::kOk);
  scheduler.RunUntil(25 * kMillisecond);

  ASSERT_EQ(port.Start(), PortError::kOk);
  scheduler.RunUntil(40 * kMillisecond);

  EXPECT_EQ(log, (std::vector<std::string>{"2:t", "27:t", "37:t"}));
}

// A step that stops its own port (a robot deciding to crash) cancels its own
// next activation too.
class SelfStoppingTask final : public Task {
 public:
  explicit SelfStoppingTask(SimPort& port) : port_(port) {}
  void Step(int64_t) override {
    ++steps;
    (void)port_.Stop();
  }
  int steps = 0;

 private:
  SimPort& port_;
};

TEST(SimPortTest, StepThatStopsItsOwnPortCancelsItsNextActivation) {
  SimScheduler scheduler(1);
  SimPort port(scheduler);
  SelfStoppingTask task(port);
  ASSERT_TRUE(port.AddTask(task, {"self", Trigger::periodic(kMillisecond), 0}));
  ASSERT_EQ(port.Start(), PortError::kOk);

  scheduler.RunUntil(10 * kMillisecond);

  EXPECT_EQ(task.steps, 1);
  EXPECT_EQ(scheduler.next_activation_ns(), -1);
}

TEST(SimPortTest, ReportsEachLifecycleError) {
  SimScheduler scheduler(1);
  SimPort port(scheduler);

  testing::ExpectEachLifecycleError(port);
}

TEST(SimPortTest, CriticalSectionsMayFollowEachOther) {
  SimScheduler scheduler(1);
  SimPort port(scheduler);

  { CriticalSection first(port); }
  { CriticalSection second(port); }

  SUCCEED();
}

TEST(SimPortDeathTest, NestedCriticalSectionIsABug) {
  SimScheduler scheduler(1);
  SimPort port(scheduler);

  EXPECT_DEATH_IF_SUPPORTED(
      {
        CriticalSection outer(port);
        CriticalSection inner(port);
      },
      "SYROF_CHECK failed");
}

// Records every step the scheduler runs as one line of text.
class TextTrace final : public SimTraceSink {
 public:
  void OnStep(int64_t time_ns, const SimPort& port, TaskId task, const TaskConfig& config) override {
    text += std::to_string(time_ns) + " " + port.name() + "/" + std::to_string(task) + "/" + config.name + "\n";
  }
  std::string text;
};

// Notifies a random subset of a robot's tasks each step, drawn from a seeded
// generator: a busy little world whose trace must repeat exactly.
class RandomNotifier final : public Task {
 public:
  RandomNotifier(Port& port, std::mt19937& random, TaskId first_target, TaskId target_count)
      : port_(port), random_(random), first_target_(first_target), target_count_(target_count) {}
  void Step(int64_t) override {
    for (TaskId i = 0; i < target_count_; ++i) {
      if (random_() % 2 == 0) port_.Notify(static_cast<TaskId>(first_target_ + i));
    }
  }

 private:
  Port& port_;
  std::mt19937& random_;
  TaskId first_target_;
  TaskId target_count_;
};

class Idle final : public Task {
 public:
  void Step(int64_t) override {}
};

std::string run_random_world(uint32_t seed) {
  constexpr int kRobots = 4;
  constexpr int kListeners = 3;
  std::mt19937 random(seed);
  SimScheduler scheduler(kRobots * (1 + kListeners));
  TextTrace trace;
  scheduler.set_trace(&trace);
  const char* names[kRobots] = {"r0", "r1", "r2", "r3"};
  std::vector<std::unique_ptr<SimPort>> ports;
  std::vector<std::unique_ptr<RandomNotifier>> notifiers;
  std::vector<Idle> listeners(kRobots * kListeners);
  for (int robot = 0; robot < kRobots; ++robot) {
    ports.push_back(std::make_unique<SimPort>(scheduler, names[robot]));
    SimPort& port = *ports.back();
    notifiers.push_back(std::make_unique<RandomNotifier>(port, random, 1, kListeners));
    const int64_t period = (robot + 2) * kMillisecond;
    EXPECT_TRUE(port.AddTask(*notifiers.back(), {"notifier", Trigger::periodic(period, robot), 1}));
    for (int i = 0; i < kListeners; ++i) {
      const auto priority = static_cast<uint8_t>((robot + i) % 3);
      EXPECT_TRUE(port.AddTask(listeners[robot * kListeners + i], {"listener", Trigger::notified(), priority}));
    }
    EXPECT_EQ(port.Start(), PortError::kOk);
  }
  scheduler.RunUntil(200 * kMillisecond);
  return trace.text;
}

// Seeded periodic tasks of many periods, offsets and priorities on several
// ports: the trace is every activation up to the end, sorted by the
// documented order (time, then higher priority, then registration), which
// the activation heap must give whatever its layout.
TEST(SimPortTest, ManyPeriodicTasksRunInTheDocumentedOrder) {
  constexpr int kPorts = 6;
  constexpr int kTasksPerPort = 7;
  constexpr int64_t kEndNs = 300 * kMillisecond;
  std::mt19937 random(2026);
  SimScheduler scheduler(kPorts * kTasksPerPort);
  TextTrace trace;
  scheduler.set_trace(&trace);
  std::vector<std::unique_ptr<SimPort>> ports;
  std::vector<Idle> tasks(kPorts * kTasksPerPort);
  struct Expected {
    int64_t time_ns;
    int priority;
    int registration;
    std::string line;
  };
  std::vector<Expected> expected;
  for (int p = 0; p < kPorts; ++p) {
    ports.push_back(std::make_unique<SimPort>(scheduler, "p"));
    for (int t = 0; t < kTasksPerPort; ++t) {
      const int64_t period = static_cast<int64_t>(1 + random() % 7) * kMillisecond;
      const int64_t offset = static_cast<int64_t>(random() % 8) * kMillisecond;
      const auto priority = static_cast<uint8_t>(random() % 5);
      ASSERT_TRUE(ports.back()->AddTask(tasks[p * kTasksPerPort + t], {"t", Trigger::periodic(period, offset), priority}));
      for (int64_t time = offset; time <= kEndNs; time += period) {
        expected.push_back(Expected{time, priority, p * kTasksPerPort + t,
                                    std::to_string(time) + " p/" + std::to_string(t) + "/t\n"});
      }
    }
    ASSERT_EQ(ports.back()->Start(), PortError::kOk);
  }
  std::sort(expected.begin(), expected.end(), [](const Expected& a, const Expected& b) {
    if (a.time_ns != b.time_ns) return a.time_ns < b.time_ns;
    if (a.priority != b.priority) return a.priority > b.priority;
    return a.registration < b.registration;
  });
  std::string expected_text;
  for (const Expected& step : expected) expected_text += step.line;

  scheduler.RunUntil(kEndNs);

  EXPECT_GT(expected.size(), 2000u);
  EXPECT_EQ(trace.text, expected_text);
}

// ---- Runs (the queue keeps tasks due together as one heap entry) ----------

// One periodic task per port; what each port's task is, when it starts.
struct PeriodicPort {
  int64_t period_ms;
  int64_t offset_ms;
  uint8_t priority;
  int32_t drift_ppb = 0;
};

// Every activation up to `end_ms` in the documented order, as TextTrace
// lines, computed from the ports' grids alone (not by a scheduler).
std::string ExpectedPeriodicTrace(std::span<const PeriodicPort> specs, std::span<const std::unique_ptr<SimPort>> ports,
                                  int64_t end_ms) {
  struct Step {
    int64_t time_ns;
    int priority;
    size_t registration;
  };
  std::vector<Step> steps;
  for (size_t p = 0; p < specs.size(); ++p) {
    for (int64_t local_ms = specs[p].offset_ms;; local_ms += specs[p].period_ms) {
      const int64_t time_ns = ports[p]->TrueFromLocal(local_ms * kMillisecond);
      if (time_ns > end_ms * kMillisecond) break;
      steps.push_back(Step{time_ns, specs[p].priority, p});
    }
  }
  std::sort(steps.begin(), steps.end(), [](const Step& a, const Step& b) {
    if (a.time_ns != b.time_ns) return a.time_ns < b.time_ns;
    if (a.priority != b.priority) return a.priority > b.priority;
    return a.registration < b.registration;
  });
  std::string text;
  for (const Step& step : steps) {
    text += std::to_string(step.time_ns) + " p" + std::to_string(step.registration) + "/0/t\n";
  }
  return text;
}

// Runs one port per spec (named p0, p1, ...) to `end_ms` and returns the trace.
struct PeriodicWorld {
  explicit PeriodicWorld(std::span<const PeriodicPort> specs) : scheduler(specs.size()), tasks(specs.size()) {
    for (size_t p = 0; p < specs.size(); ++p) names.push_back("p" + std::to_string(p));
    scheduler.set_trace(&trace);
    for (size_t p = 0; p < specs.size(); ++p) {
      ports.push_back(std::make_unique<SimPort>(scheduler, names[p].c_str()));
      ports.back()->SetDriftPpb(specs[p].drift_ppb);
      const Trigger trigger = Trigger::periodic(specs[p].period_ms * kMillisecond, specs[p].offset_ms * kMillisecond);
      EXPECT_TRUE(ports.back()->AddTask(tasks[p], {"t", trigger, specs[p].priority}));
      EXPECT_EQ(ports.back()->Start(), PortError::kOk);
    }
  }
  SimScheduler scheduler;
  TextTrace trace;
  std::vector<std::string> names;
  std::vector<Idle> tasks;
  std::vector<std::unique_ptr<SimPort>> ports;
};

// Ports 0, 2, 4 run every 10 ms, ports 1, 3, 5 every 5 ms: at 10 ms, 20 ms,
// ... the even ports' run and the odd ports' run are due together and must
// come out merged (p0 p1 p2 ...), not one run after the other.
TEST(SimPortRunTest, RunsDueTogetherInterleaveByRegistration) {
  const std::vector<PeriodicPort> specs = {{10, 0, 1}, {5, 0, 1}, {10, 0, 1}, {5, 0, 1}, {10, 0, 1}, {5, 0, 1}};
  PeriodicWorld world(specs);

  world.scheduler.RunUntil(40 * kMillisecond);

  EXPECT_NE(world.trace.text.find("10000000 p0/0/t\n10000000 p1/0/t\n10000000 p2/0/t\n"), std::string::npos);
  EXPECT_EQ(world.trace.text, ExpectedPeriodicTrace(specs, world.ports, 40));
}

// Drifting ports fall due apart from the others (runs of one), two ports of
// the same clock still together; the order stays the documented one.
TEST(SimPortRunTest, DriftingPortsKeepTheDocumentedOrder) {
  const std::vector<PeriodicPort> specs = {{10, 0, 1}, {10, 0, 1, 30'000}, {10, 0, 1},
                                           {10, 0, 1, -20'000}, {10, 0, 1, 30'000}, {7, 3, 2}};
  PeriodicWorld world(specs);

  world.scheduler.RunUntil(500 * kMillisecond);

  EXPECT_EQ(world.trace.text, ExpectedPeriodicTrace(specs, world.ports, 500));
}

// A robot's periodic task (its port's task 0) that, when it runs at a given
// instant, stops a port or shifts its own next activation.
class ActingTask final : public Task {
 public:
  ActingTask(std::vector<std::string>& log, std::string label, SimPort& own_port)
      : log_(log), label_(std::move(label)), own_port_(own_port) {}
  void stop_at(int64_t at_ms, SimPort& port) { stops_.push_back({at_ms, &port}); }
  void shift_at(int64_t at_ms, int64_t delta_ms) { shifts_.push_back({at_ms, delta_ms}); }
  void Step(int64_t now_ns) override {
    log_.push_back(std::to_string(now_ns / kMillisecond) + ":" + label_);
    for (const auto& [at_ms, port] : stops_) {
      if (now_ns == at_ms * kMillisecond) {
        EXPECT_EQ(port->Stop(), PortError::kOk);
      }
    }
    for (const auto& [at_ms, delta_ms] : shifts_) {
      if (now_ns == at_ms * kMillisecond) {
        EXPECT_EQ(own_port_.ShiftPeriodic(0, delta_ms * kMillisecond), PortError::kOk);
      }
    }
  }

 private:
  std::vector<std::string>& log_;
  std::string label_;
  SimPort& own_port_;
  std::vector<std::pair<int64_t, SimPort*>> stops_;
  std::vector<std::pair<int64_t, int64_t>> shifts_;
};

// `robots` ports, each with one ActingTask "r<robot>" every 10 ms, priority 1.
struct ActingWorld {
  explicit ActingWorld(int robots) : scheduler(static_cast<size_t>(robots)) {
    for (int robot = 0; robot < robots; ++robot) {
      ports.push_back(std::make_unique<SimPort>(scheduler, "robot"));
      tasks.push_back(std::make_unique<ActingTask>(log, "r" + std::to_string(robot), *ports.back()));
      EXPECT_TRUE(ports.back()->AddTask(*tasks.back(), {"t", Trigger::periodic(10 * kMillisecond), 1}));
    }
  }
  void Start() {
    for (auto& port : ports) EXPECT_EQ(port->Start(), PortError::kOk);
  }
  SimScheduler scheduler;
  std::vector<std::string> log;
  std::vector<std::unique_ptr<SimPort>> ports;
  std::vector<std::unique_ptr<ActingTask>> tasks;
};

// Five robots every 10 ms form one run. At 20 ms robot 1's step stops robot
// 3 (in the middle of the run being taken) and its own port (the last task
// of the run queued for 30 ms so far, which robot 2's next activation must
// then not join); at 30 ms robot 2 stops robot 0 (the first task of the run
// queued for 40 ms). The others keep their order.
TEST(SimPortRunTest, StoppingPortsInsideARunKeepsTheOthersInOrder) {
  ActingWorld world(5);
  world.tasks[1]->stop_at(20, *world.ports[3]);
  world.tasks[1]->stop_at(20, *world.ports[1]);
  world.tasks[2]->stop_at(30, *world.ports[0]);
  world.Start();

  world.scheduler.RunUntil(50 * kMillisecond);

  EXPECT_EQ(world.log, (std::vector<std::string>{"0:r0",  "0:r1",  "0:r2",  "0:r3",  "0:r4",  "10:r0", "10:r1",
                                                 "10:r2", "10:r3", "10:r4", "20:r0", "20:r1", "20:r2", "20:r4",
                                                 "30:r0", "30:r2", "30:r4", "40:r2", "40:r4", "50:r2", "50:r4"}));
}

// At 10 ms robot 0 shifts its next activation 1 ms later, out of the run
// queued for 20 ms (its last task so far, which robots 1 and 2 must then
// join, not follow to 21 ms); at 20 ms robot 1 moves out of the middle of
// the run queued for 30 ms; at 21 ms robot 0 shifts back to 30 ms, ahead of
// robot 2 by registration.
TEST(SimPortRunTest, ShiftingATaskOutOfARunKeepsTheRunAndTheTask) {
  ActingWorld world(3);
  world.tasks[0]->shift_at(10, 1);
  world.tasks[1]->shift_at(20, 2);
  world.tasks[0]->shift_at(21, -1);
  world.Start();

  world.scheduler.RunUntil(40 * kMillisecond);

  EXPECT_EQ(world.log, (std::vector<std::string>{"0:r0", "0:r1", "0:r2", "10:r0", "10:r1", "10:r2", "20:r1", "20:r2",
                                                 "21:r0", "30:r0", "30:r2", "32:r1", "40:r0", "40:r2"}));
}

// Robot 1's task runs every 20 ms, robot 0's every 10 ms: at 10 ms robot 0's
// next activation (20 ms) is queued right after robot 1's, and must still
// run first.
TEST(SimPortRunTest, AnEarlierTaskQueuedAfterALaterOneRunsFirst) {
  const std::vector<PeriodicPort> specs = {{10, 0, 1}, {20, 0, 1}};
  PeriodicWorld world(specs);

  world.scheduler.RunUntil(60 * kMillisecond);

  EXPECT_NE(world.trace.text.find("20000000 p0/0/t\n20000000 p1/0/t\n"), std::string::npos);
  EXPECT_EQ(world.trace.text, ExpectedPeriodicTrace(specs, world.ports, 60));
}

// Each robot's periodic task notifies a listener of the same priority
// registered right after it: the notification lands inside the robots' run
// (between robot r's task and robot r + 1's) and runs there.
TEST(SimPortRunTest, NotificationInsideARunRunsInRegistrationOrder) {
  SimScheduler scheduler(6);
  std::vector<std::string> log;
  std::vector<std::unique_ptr<SimPort>> ports;
  std::vector<std::unique_ptr<NotifyingTask>> publishers;
  std::vector<std::unique_ptr<RecordingTask>> listeners;
  for (int robot = 0; robot < 3; ++robot) {
    ports.push_back(std::make_unique<SimPort>(scheduler, "robot"));
    publishers.push_back(std::make_unique<NotifyingTask>(*ports.back(), log, "p" + std::to_string(robot)));
    listeners.push_back(std::make_unique<RecordingTask>(log, "l" + std::to_string(robot)));
    ASSERT_TRUE(ports.back()->AddTask(*publishers.back(), {"p", Trigger::periodic(10 * kMillisecond), 1}));
    const auto listener = ports.back()->AddTask(*listeners.back(), {"l", Trigger::notified(), 1});
    ASSERT_TRUE(listener);
    if (robot != 1) publishers.back()->add_target(listener.value());
    ASSERT_EQ(ports.back()->Start(), PortError::kOk);
  }

  scheduler.RunUntil(10 * kMillisecond);

  EXPECT_EQ(log, (std::vector<std::string>{"0:p0", "0:l0", "0:p1", "0:p2", "0:l2", "10:p0", "10:l0", "10:p1",
                                           "10:p2", "10:l2"}));
}

// A world task that notifies a task on each of several ports, in the order given.
class NotifyingPortsTask final : public Task {
 public:
  NotifyingPortsTask(std::vector<std::string>& log, std::vector<std::pair<SimPort*, TaskId>> targets)
      : log_(log), targets_(std::move(targets)) {}
  void Step(int64_t now_ns) override {
    log_.push_back(std::to_string(now_ns / kMillisecond) + ":world");
    for (const auto& [port, task] : targets_) port->Notify(task);
  }

 private:
  std::vector<std::string>& log_;
  std::vector<std::pair<SimPort*, TaskId>> targets_;
};

// The world notifies robot 2's, 0's and 1's listeners (l0 and l1 form one
// run, l2 is alone); each listener notifies its echo, of the same priority,
// registered right after it. An echo notified after the last task of the
// run notified before it has run must not join that finished run.
TEST(SimPortRunTest, NotificationsFromOneStepRunByRegistration) {
  SimScheduler scheduler(7);
  std::vector<std::string> log;
  SimPort world_port(scheduler, "world");
  std::vector<std::unique_ptr<SimPort>> ports;
  std::vector<std::unique_ptr<NotifyingTask>> listeners;
  std::vector<std::unique_ptr<RecordingTask>> echoes;
  for (int robot = 0; robot < 3; ++robot) {
    ports.push_back(std::make_unique<SimPort>(scheduler, "robot"));
    listeners.push_back(std::make_unique<NotifyingTask>(*ports.back(), log, "l" + std::to_string(robot)));
    echoes.push_back(std::make_unique<RecordingTask>(log, "e" + std::to_string(robot)));
    ASSERT_TRUE(ports.back()->AddTask(*listeners.back(), {"l", Trigger::notified(), 1}));
    const auto echo = ports.back()->AddTask(*echoes.back(), {"e", Trigger::notified(), 1});
    ASSERT_TRUE(echo);
    listeners.back()->add_target(echo.value());
    ASSERT_EQ(ports.back()->Start(), PortError::kOk);
  }
  NotifyingPortsTask world(log, {{ports[2].get(), 0}, {ports[0].get(), 0}, {ports[1].get(), 0}});
  ASSERT_TRUE(world_port.AddTask(world, {"world", Trigger::periodic(10 * kMillisecond), 2}));
  ASSERT_EQ(world_port.Start(), PortError::kOk);

  scheduler.RunUntil(10 * kMillisecond);

  EXPECT_EQ(log, (std::vector<std::string>{"0:world", "0:l0", "0:e0", "0:l1", "0:e1", "0:l2", "0:e2", "10:world",
                                           "10:l0", "10:e0", "10:l1", "10:e1", "10:l2", "10:e2"}));
}

TEST(SimPortTest, SameProgramAndSeedGiveTheSameTrace) {
  const std::string first = run_random_world(7);
  const std::string second = run_random_world(7);
  const std::string other_seed = run_random_world(8);

  EXPECT_GT(first.size(), 1000u);
  EXPECT_EQ(first, second);
  EXPECT_NE(first, other_seed);
}

}  // namespace
}  // namespace syrof::os

namespace syrof::os {
namespace {

// Records the scheduler's (true) time of each step and the local time it got.
class ClockTask final : public Task {
 public:
  explicit ClockTask(const SimScheduler& scheduler) : scheduler_(scheduler) {}
  void Step(int64_t now_ns) override {
    true_ns.push_back(scheduler_.now_ns());
    local_ns.push_back(now_ns);
  }
  std::vector<int64_t> true_ns;
  std::vector<int64_t> local_ns;

 private:
  const SimScheduler& scheduler_;
};

TEST(SimPortClockTest, DriftingPortKeepsItsGridInLocalTime) {
  SimScheduler scheduler(4);
  SimPort port(scheduler);
  port.SetDriftPpb(1'000'000);  // 1000 ppm fast
  ClockTask task(scheduler);
  ASSERT_TRUE(port.AddTask(task, {"t", Trigger::periodic(kMillisecond * 50, kMillisecond * 50), 0}).ok());
  ASSERT_EQ(port.Start(), PortError::kOk);
  scheduler.RunUntil(kMillisecond * 1000);
  ASSERT_EQ(task.local_ns.size(), 20u);  // 20 local periods end before 1 s of true time
  for (size_t i = 0; i < task.local_ns.size(); ++i) {
    EXPECT_EQ(task.local_ns[i], static_cast<int64_t>(i + 1) * 50 * kMillisecond);
    EXPECT_EQ(task.true_ns[i], port.TrueFromLocal(task.local_ns[i]));
    EXPECT_GE(port.LocalFromTrue(task.true_ns[i]), task.local_ns[i]);
    EXPECT_LT(port.LocalFromTrue(task.true_ns[i] - 1), task.local_ns[i]);
  }
  EXPECT_EQ(task.true_ns[19], port.TrueFromLocal(kMillisecond * 1000));
  EXPECT_LT(task.true_ns[19], kMillisecond * 1000);  // fast: earlier in true time
  EXPECT_NEAR(static_cast<double>(task.true_ns[19]), 1e9 / 1.001, 1.0);
}

TEST(SimPortClockTest, StartAfterDelaysTheGridAndShiftMovesIt) {
  SimScheduler scheduler(4);
  SimPort port(scheduler);
  ClockTask task(scheduler);
  const auto id = port.AddTask(task, {"t", Trigger::periodic(kMillisecond * 50, kMillisecond * 50), 0});
  ASSERT_TRUE(id.ok());
  ASSERT_EQ(port.StartAfter(kMillisecond * 7), PortError::kOk);
  scheduler.RunUntil(kMillisecond * 60);
  ASSERT_EQ(task.true_ns.size(), 1u);
  EXPECT_EQ(task.true_ns[0], kMillisecond * 57);
  EXPECT_EQ(port.ShiftPeriodic(id.value(), -kMillisecond * 5), PortError::kOk);
  scheduler.RunUntil(kMillisecond * 200);
  ASSERT_EQ(task.true_ns.size(), 3u);
  EXPECT_EQ(task.true_ns[1], kMillisecond * 102);
  EXPECT_EQ(task.true_ns[2], kMillisecond * 152);
  EXPECT_EQ(port.ShiftPeriodic(7, 1), PortError::kInvalidTrigger);
}

TEST(SimPortClockTest, ShiftNeverMovesBeforeNow) {
  SimScheduler scheduler(4);
  SimPort port(scheduler);
  ClockTask task(scheduler);
  const auto id = port.AddTask(task, {"t", Trigger::periodic(kMillisecond * 50, kMillisecond * 50), 0});
  ASSERT_TRUE(id.ok());
  ASSERT_EQ(port.Start(), PortError::kOk);
  scheduler.RunUntil(kMillisecond * 10);
  EXPECT_EQ(port.ShiftPeriodic(id.value(), -kMillisecond * 500), PortError::kOk);
  scheduler.RunUntil(kMillisecond * 10);
  ASSERT_EQ(task.true_ns.size(), 1u);
  EXPECT_EQ(task.true_ns[0], kMillisecond * 10);
}

}  // namespace
}  // namespace syrof::os

namespace syrof::os {
namespace {

// ---- Batches (SimScheduler::set_batch_runner) -------------------------------

// Runs a batch's steps last to first, as a runner on threads may.
class ReversingRunner final : public SimBatchRunner {
 public:
  void RunBatch(std::span<const SimStep> steps) override {
    largest = std::max(largest, steps.size());
    for (size_t i = steps.size(); i-- > 0;) steps[i].task->Step(steps[i].now_ns);
  }
  size_t largest = 0;
};

// A robot's round task: logs to its port's own log, notifies its port's
// listener (lower priority), shifts itself by 1 ms every third step, and
// stops its port at `stop_ms`.
class RoundTask final : public Task {
 public:
  RoundTask(SimPort& port, std::vector<std::string>& log, int64_t stop_ms) : port_(port), log_(log), stop_ms_(stop_ms) {}
  void Step(int64_t now_ns) override {
    log_.push_back(std::to_string(now_ns) + ":round");
    port_.Notify(1);
    if (++steps_ % 3 == 0) {
      EXPECT_EQ(port_.ShiftPeriodic(0, kMillisecond), PortError::kOk);
    }
    if (now_ns >= stop_ms_ * kMillisecond) {
      EXPECT_EQ(port_.Stop(), PortError::kOk);
    }
  }

 private:
  SimPort& port_;
  std::vector<std::string>& log_;
  int64_t stop_ms_;
  int steps_ = 0;
};

struct BatchWorld {
  std::vector<std::vector<std::string>> logs;
  uint64_t steps = 0;
  uint64_t batches = 0;
  size_t largest = 0;
};

BatchWorld RunBatchWorld(bool batches, uint8_t listener_priority = 1) {
  constexpr int kRobots = 5;
  SimScheduler scheduler(kRobots * 2);
  ReversingRunner runner;
  if (batches) scheduler.set_batch_runner(&runner);
  BatchWorld world;
  world.logs.resize(kRobots);
  std::vector<std::unique_ptr<SimPort>> ports;
  std::vector<std::unique_ptr<RoundTask>> rounds;
  std::vector<std::unique_ptr<RecordingTask>> listeners;
  for (int robot = 0; robot < kRobots; ++robot) {
    ports.push_back(std::make_unique<SimPort>(scheduler, "robot"));
    rounds.push_back(std::make_unique<RoundTask>(*ports.back(), world.logs[robot], robot == 2 ? 40 : 1000));
    listeners.push_back(std::make_unique<RecordingTask>(world.logs[robot], "listener"));
    EXPECT_TRUE(ports.back()->AddTask(*rounds.back(), {"round", Trigger::periodic(10 * kMillisecond), 2}));
    EXPECT_TRUE(ports.back()->AddTask(*listeners.back(), {"listener", Trigger::notified(), listener_priority}));
    EXPECT_EQ(ports.back()->Start(), PortError::kOk);
  }
  scheduler.RunUntil(100 * kMillisecond);
  world.steps = scheduler.steps_run();
  world.batches = scheduler.batches_run();
  world.largest = runner.largest;
  return world;
}

// A world task that acts on every robot's port each step (notifies its
// listener, shifts its periodic task every other step, stops robot 1 at
// 30 ms), one robot at a time or side by side in reverse order.
class WorldTask final : public Task {
 public:
  WorldTask(SimScheduler& scheduler, std::vector<std::unique_ptr<SimPort>>& ports, bool side_by_side)
      : scheduler_(scheduler), ports_(ports), side_by_side_(side_by_side) {
    for (auto& port : ports_) raw_ports_.push_back(port.get());
  }
  void Step(int64_t now_ns) override {
    ++steps_;
    if (!side_by_side_) {
      for (size_t robot = 0; robot < ports_.size(); ++robot) Act(robot, now_ns);
      return;
    }
    scheduler_.BeginSideBySide(raw_ports_);
    for (size_t robot = ports_.size(); robot-- > 0;) Act(robot, now_ns);
    scheduler_.EndSideBySide();
  }

 private:
  void Act(size_t robot, int64_t now_ns) {
    SimPort& port = *ports_[robot];
    if (!port.running()) return;
    port.Notify(1);
    if (steps_ % 2 == 0) {
      EXPECT_EQ(port.ShiftPeriodic(0, kMillisecond), PortError::kOk);
    }
    if (robot == 1 && now_ns >= 30 * kMillisecond) {
      EXPECT_EQ(port.Stop(), PortError::kOk);
    }
  }
  SimScheduler& scheduler_;
  std::vector<std::unique_ptr<SimPort>>& ports_;
  std::vector<SimPort*> raw_ports_;
  bool side_by_side_;
  int steps_ = 0;
};

std::vector<std::string> RunSideBySideWorld(bool side_by_side) {
  constexpr int kRobots = 4;
  SimScheduler scheduler(kRobots * 2 + 1);
  TextTrace trace;
  scheduler.set_trace(&trace);
  SimPort world_port(scheduler, "world");
  std::vector<std::unique_ptr<SimPort>> ports;
  std::vector<std::string> log;
  std::vector<std::unique_ptr<RecordingTask>> tasks;
  for (int robot = 0; robot < kRobots; ++robot) {
    ports.push_back(std::make_unique<SimPort>(scheduler, "robot"));
    tasks.push_back(std::make_unique<RecordingTask>(log, "tick" + std::to_string(robot)));
    EXPECT_TRUE(ports.back()->AddTask(*tasks.back(), {"tick", Trigger::periodic(7 * kMillisecond), 1}));
    tasks.push_back(std::make_unique<RecordingTask>(log, "heard" + std::to_string(robot)));
    EXPECT_TRUE(ports.back()->AddTask(*tasks.back(), {"heard", Trigger::notified(), 2}));
  }
  WorldTask world(scheduler, ports, side_by_side);
  EXPECT_TRUE(world_port.AddTask(world, {"world", Trigger::periodic(5 * kMillisecond), 6}));
  EXPECT_EQ(world_port.Start(), PortError::kOk);
  for (auto& port : ports) EXPECT_EQ(port->Start(), PortError::kOk);
  scheduler.RunUntil(60 * kMillisecond);
  log.push_back(trace.text);
  return log;
}

TEST(SimPortBatchTest, SideBySideGivesTheSameStepsAsOneAtATime) {
  const std::vector<std::string> one_at_a_time = RunSideBySideWorld(false);
  const std::vector<std::string> side_by_side = RunSideBySideWorld(true);

  EXPECT_GT(one_at_a_time.size(), 40u);
  EXPECT_EQ(side_by_side, one_at_a_time);
}

// Touching a port outside the side-by-side set is a bug (what it asked for
// would never be applied).
TEST(SimPortBatchDeathTest, SideBySideRefusesAPortOutsideItsSet) {
  SimScheduler scheduler(2);
  SimPort inside(scheduler, "inside");
  SimPort outside(scheduler, "outside");
  Idle idle;
  EXPECT_TRUE(outside.AddTask(idle, {"heard", Trigger::notified(), 1}));
  EXPECT_EQ(outside.Start(), PortError::kOk);
  SimPort* const set[] = {&inside};

  scheduler.BeginSideBySide(set);
  EXPECT_DEATH_IF_SUPPORTED(outside.Notify(0), "SYROF_CHECK failed");
  scheduler.EndSideBySide();
}

TEST(SimPortBatchTest, BatchesRunInAnyOrderGiveTheSameSteps) {
  // Act: the same world one step at a time, and in batches run backwards.
  const BatchWorld serial = RunBatchWorld(false);
  const BatchWorld batched = RunBatchWorld(true);

  // Assert: every port ran the same steps at the same times: notifications,
  // shifts and a stop made inside a batch took effect as if made one at a time.
  EXPECT_EQ(serial.batches, 0u);
  EXPECT_GT(batched.batches, 5u);
  EXPECT_EQ(batched.largest, 5u);
  EXPECT_EQ(batched.steps, serial.steps);
  EXPECT_EQ(batched.logs, serial.logs);
  EXPECT_LT(serial.logs[2].size(), serial.logs[1].size());  // robot 2 stopped
}

// The same world against its grid worked out by hand: rounds every 10 ms,
// each third one shifted 1 ms later (the shifts move tasks out of the runs
// queued for the next instant), robot 2 stopped by its round at 41 ms (its
// listener, notified by that step, never runs).
TEST(SimPortBatchTest, BatchesWithDeferredShiftsAndStopsFollowTheGrid) {
  const int64_t round_ms[] = {0, 10, 20, 31, 41, 51, 62, 72, 82, 93};
  const auto expected = [&](int robot) {
    std::vector<std::string> log;
    for (const int64_t ms : round_ms) {
      if (robot == 2 && ms > 41) break;
      log.push_back(std::to_string(ms * kMillisecond) + ":round");
      if (robot != 2 || ms < 41) log.push_back(std::to_string(ms) + ":listener");
    }
    return log;
  };

  const BatchWorld serial = RunBatchWorld(false);
  const BatchWorld batched = RunBatchWorld(true);

  for (int robot = 0; robot < 5; ++robot) {
    EXPECT_EQ(serial.logs[robot], expected(robot)) << "robot " << robot;
    EXPECT_EQ(batched.logs[robot], expected(robot)) << "robot " << robot;
  }
  EXPECT_EQ(batched.batches, 20u);  // at each round instant, the rounds, then the listeners
}

// Runs a batch's steps in order, so that a shared log reads as one at a time.
class InOrderRunner final : public SimBatchRunner {
 public:
  void RunBatch(std::span<const SimStep> steps) override {
    for (const SimStep& step : steps) step.task->Step(step.now_ns);
  }
};

// A shift made in a batch applies after the batch's next activations are
// queued as one run: robot 1 moves out of the middle of it.
TEST(SimPortBatchTest, ShiftInABatchMovesATaskOutOfTheMiddleOfARun) {
  ActingWorld world(3);
  InOrderRunner runner;
  world.scheduler.set_batch_runner(&runner);
  world.tasks[1]->shift_at(10, 1);
  world.Start();

  world.scheduler.RunUntil(31 * kMillisecond);

  EXPECT_EQ(world.log, (std::vector<std::string>{"0:r0", "0:r1", "0:r2", "10:r0", "10:r1", "10:r2", "20:r0", "20:r2",
                                                 "21:r1", "30:r0", "30:r2", "31:r1"}));
  EXPECT_EQ(world.scheduler.batches_run(), 4u);  // 21 ms and 31 ms are robot 1 alone
}

// A step that stops its own port and asks for nothing else: the stop still
// takes effect after the batch (the scheduler looks only at the ports that
// asked for something, so a stop alone must count as asking).
class StoppingTask final : public Task {
 public:
  StoppingTask(SimPort& port, std::vector<std::string>& log, std::string name, int64_t stop_ms)
      : port_(port), log_(log), name_(std::move(name)), stop_ms_(stop_ms) {}
  void Step(int64_t now_ns) override {
    log_.push_back(std::to_string(now_ns / kMillisecond) + ":" + name_);
    if (now_ns >= stop_ms_ * kMillisecond) {
      EXPECT_EQ(port_.Stop(), PortError::kOk);
    }
  }

 private:
  SimPort& port_;
  std::vector<std::string>& log_;
  std::string name_;
  int64_t stop_ms_;
};

TEST(SimPortBatchTest, AStopAloneInABatchStopsThePort) {
  SimScheduler scheduler(3);
  InOrderRunner runner;
  scheduler.set_batch_runner(&runner);
  std::vector<std::string> log;
  std::vector<std::unique_ptr<SimPort>> ports;
  std::vector<std::unique_ptr<StoppingTask>> tasks;
  for (int robot = 0; robot < 3; ++robot) {
    ports.push_back(std::make_unique<SimPort>(scheduler, "robot"));
    tasks.push_back(std::make_unique<StoppingTask>(*ports.back(), log, "r" + std::to_string(robot), robot == 1 ? 10 : 1000));
    EXPECT_TRUE(ports.back()->AddTask(*tasks.back(), {"round", Trigger::periodic(10 * kMillisecond), 2}));
    EXPECT_EQ(ports.back()->Start(), PortError::kOk);
  }

  scheduler.RunUntil(25 * kMillisecond);

  EXPECT_EQ(log, (std::vector<std::string>{"0:r0", "0:r1", "0:r2", "10:r0", "10:r1", "10:r2", "20:r0", "20:r2"}));
  EXPECT_FALSE(ports[1]->running());
  EXPECT_EQ(scheduler.batches_run(), 3u);
}

TEST(SimPortBatchDeathTest, AnActivationThatWouldHaveRunInsideTheBatchStops) {
  // A listener above the round task's priority would run before the next
  // robot's round step one at a time: a batch cannot keep that order.
  EXPECT_DEATH_IF_SUPPORTED(RunBatchWorld(true, 3), "SYROF_CHECK failed");
}

}  // namespace
}  // namespace syrof::os
