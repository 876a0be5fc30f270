// lab/sim/src/robot_chunks.h: how --threads cuts the robots into chunks,
// and the batches run chunk by chunk with the observer calls kept and
// handed back in the order of a one-thread run.
#include "robot_chunks.h"

#include <gtest/gtest.h>

#include <atomic>
#include <cstdint>
#include <memory>
#include <vector>

namespace syrof::lab::sim {
namespace {

constexpr int64_t kChunksTestPeriodNs = 1'000'000;

TEST(ChunkPlanTest, OneThreadOneRobotOrClocksGiveOneChunk) {
  EXPECT_EQ(ChunkPlan(100, 1, false).chunks(), 1u);
  EXPECT_EQ(ChunkPlan(1, 4, false).workers(), 1);
  const ChunkPlan clocks(100, 4, true);
  EXPECT_EQ(clocks.workers(), 1);
  EXPECT_EQ(clocks.chunks(), 1u);
  EXPECT_EQ(clocks.begin(0), 0u);
  EXPECT_EQ(clocks.end(0), 100u);
}

TEST(ChunkPlanTest, ChunksAreContiguousNonEmptyAndCoverEveryRobot) {
  for (const size_t robots : {2u, 3u, 15u, 16u, 33u, 100u, 257u, 1000u}) {
    for (const int threads : {2, 3, 4, 64}) {
      const ChunkPlan plan(robots, threads, false);
      SCOPED_TRACE(testing::Message() << robots << " robots, " << threads << " threads");
      EXPECT_EQ(plan.workers(), std::min<int>(threads, static_cast<int>(robots)));
      ASSERT_GE(plan.chunks(), static_cast<size_t>(plan.workers()));
      EXPECT_EQ(plan.begin(0), 0u);
      EXPECT_EQ(plan.end(plan.chunks() - 1), robots);
      for (size_t chunk = 0; chunk < plan.chunks(); ++chunk) {
        EXPECT_LT(plan.begin(chunk), plan.end(chunk));
        if (chunk > 0) {
          EXPECT_EQ(plan.begin(chunk), plan.end(chunk - 1));
        }
        for (size_t robot = plan.begin(chunk); robot < plan.end(chunk); ++robot) EXPECT_EQ(plan.ChunkOf(robot), chunk);
      }
    }
  }
}

TEST(ChunkPlanTest, FourChunksPerWorkerOfAtLeastEightRobots) {
  EXPECT_EQ(ChunkPlan(1000, 2, false).chunks(), 8u);
  EXPECT_EQ(ChunkPlan(40, 2, false).chunks(), 5u);  // 40 / 8
  EXPECT_EQ(ChunkPlan(10, 2, false).chunks(), 2u);  // never fewer than the workers
  const std::vector<uint16_t> first = ChunkPlan(40, 2, false).FirstRobots();
  EXPECT_EQ(first, (std::vector<uint16_t>{0, 8, 16, 24, 32}));
}

// One robot's task: counts its steps; its first step of every instant
// reports a call, kept during a batch, handled at once otherwise.
class ReportingTask final : public os::Task {
 public:
  ReportingTask(uint16_t robot, RobotChunks*& chunks, ObserverCallHandler& handler)
      : robot_(robot), chunks_(chunks), handler_(handler) {}
  void Step(int64_t /*now_ns*/) override {
    steps.fetch_add(1, std::memory_order_relaxed);
    ObserverCall call{robot_, 0, wire::Mode::kCooperative, ObserverCall::BecameJoiner{}};
    if (chunks_ != nullptr && chunks_->in_batch()) {
      chunks_->Keep(call);
    } else {
      handler_.Handle(call);
    }
  }
  std::atomic<int> steps{0};

 private:
  uint16_t robot_;
  RobotChunks*& chunks_;
  ObserverCallHandler& handler_;
};

class OrderHandler final : public ObserverCallHandler {
 public:
  void Handle(const ObserverCall& call) override { robots.push_back(call.robot); }
  std::vector<uint16_t> robots;
};

// The robots' calls, in the order they are handled, over `instants`
// periods of `robots` robots whose tasks are due together, run with
// `threads` threads (1: no batches).
std::vector<uint16_t> HandledOrder(size_t robots, int threads, int instants, std::vector<int>* steps) {
  os::SimScheduler scheduler(robots);
  std::vector<std::unique_ptr<os::SimPort>> ports;
  OrderHandler handler;
  RobotChunks* chunks_seen = nullptr;
  std::vector<std::unique_ptr<ReportingTask>> tasks;
  // The ports made last robot first, so that the scheduler's order of a
  // batch (by port) is not the robots' (by id) nor the chunks'.
  ports.resize(robots);
  tasks.resize(robots);
  for (size_t robot = robots; robot-- > 0;) {
    ports[robot] = std::make_unique<os::SimPort>(scheduler);
    tasks[robot] = std::make_unique<ReportingTask>(static_cast<uint16_t>(robot), chunks_seen, handler);
    EXPECT_TRUE(ports[robot]->AddTask(*tasks[robot], {"robot", os::Trigger::periodic(kChunksTestPeriodNs), 0}));
  }
  const ChunkPlan plan(robots, threads, false);
  std::unique_ptr<RobotChunks> chunks;
  if (plan.workers() > 1) {
    std::vector<os::SimPort*> robot_ports;
    for (const auto& port : ports) robot_ports.push_back(port.get());
    chunks = std::make_unique<RobotChunks>(plan, std::move(robot_ports), handler);
    chunks_seen = chunks.get();
    scheduler.set_batch_runner(chunks.get());
  }
  for (size_t robot = robots; robot-- > 0;) EXPECT_EQ(ports[robot]->Start(), os::PortError::kOk);
  scheduler.RunUntil((instants - 1) * kChunksTestPeriodNs);
  if (chunks != nullptr) {
    EXPECT_EQ(scheduler.batches_run(), static_cast<uint64_t>(instants));
  }
  if (steps != nullptr) {
    for (const auto& task : tasks) steps->push_back(task->steps.load());
  }
  return handler.robots;
}

TEST(RobotChunksTest, KeptCallsAreHandledInTheOrderOfAOneThreadRun) {
  const std::vector<uint16_t> serial = HandledOrder(100, 1, 5, nullptr);
  ASSERT_EQ(serial.size(), 500u);
  ASSERT_EQ(serial.front(), 99) << "a batch runs its steps by port, here the robots' ids backwards";
  for (const int threads : {2, 3, 4}) {
    std::vector<int> steps;
    EXPECT_EQ(HandledOrder(100, threads, 5, &steps), serial) << threads << " threads";
    EXPECT_EQ(steps, std::vector<int>(100, 5)) << "every robot's step runs once an instant";
  }
}

TEST(RobotChunksTest, ABatchOfFewerThanSixteenStepsRunsOnTheCallingThreadInOrder) {
  const std::vector<uint16_t> serial = HandledOrder(kMinParallelSteps - 1, 1, 3, nullptr);
  EXPECT_EQ(HandledOrder(kMinParallelSteps - 1, 2, 3, nullptr), serial);
}

}  // namespace
}  // namespace syrof::lab::sim
