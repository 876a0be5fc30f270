// Cost of one publish against the number of subscribers.
//
// BM_Publish measures the broker alone (a port whose Notify only sets a
// pending bit, as a FreeRTOS task notification does); BM_PublishAndDeliver
// adds the simulation port: each publish wakes every subscriber task and the
// scheduler runs their steps, each taking its tuple. The "BigO" rows give the
// per-subscriber cost (the slope) and "RMS" how well a line fits.
#include <benchmark/benchmark.h>

#include <array>
#include <cstdint>
#include <memory>
#include <vector>

#include "syrof/os/sim_port.h"
#include "syrof/pubsub/topic.h"

namespace syrof::pubsub {
namespace {

// A 32-byte tuple, the size of a typical state estimate.
struct Tuple {
  std::array<float, 8> values;
};
constexpr Topic<Tuple> kTopic{1, "bench"};
constexpr size_t kMaxSubscribers = 64;

class PendingBitsPort final : public os::Port {
 public:
  base::Result<os::TaskId, os::PortError> AddTask(os::Task&, const os::TaskConfig&) override {
    return os::PortError::kTooManyTasks;
  }
  os::PortError Start() override { return os::PortError::kOk; }
  os::PortError Stop() override { return os::PortError::kOk; }
  void Notify(os::TaskId task) override { pending_[task % 64] = true; }
  int64_t now_ns() const override { return 0; }
  void Lock() override {}
  void Unlock() override {}

 private:
  std::array<bool, 64> pending_{};
};

void BM_Publish(benchmark::State& state) {
  const auto subscriber_count = static_cast<size_t>(state.range(0));
  PendingBitsPort port;
  StaticBroker<1, kMaxSubscribers> broker(port);
  Publisher<Tuple> publisher;
  std::vector<std::unique_ptr<Subscriber<Tuple>>> subscribers;
  if (publisher.Advertise(broker, kTopic) != BrokerError::kOk) state.SkipWithError("advertise failed");
  for (size_t i = 0; i < subscriber_count; ++i) {
    subscribers.push_back(std::make_unique<Subscriber<Tuple>>());
    if (subscribers.back()->Subscribe(broker, kTopic, static_cast<os::TaskId>(i)) != BrokerError::kOk) {
      state.SkipWithError("subscribe failed");
    }
  }
  Tuple tuple{};
  for (auto _ : state) {
    tuple.values[0] += 1.0f;
    benchmark::DoNotOptimize(publisher.Publish(tuple));
  }
  state.SetComplexityN(static_cast<int64_t>(subscriber_count));
  state.counters["publishes_per_s"] = benchmark::Counter(static_cast<double>(state.iterations()),
                                                         benchmark::Counter::kIsRate);
}
BENCHMARK(BM_Publish)->Arg(1)->Arg(2)->Arg(4)->Arg(8)->Arg(16)->Arg(32)->Arg(64)->Complexity(benchmark::oN);

class TakingTask final : public os::Task {
 public:
  void Step(int64_t) override {
    Tuple tuple{};
    while (subscriber.Take(tuple)) benchmark::DoNotOptimize(tuple);
  }
  Subscriber<Tuple> subscriber;
};

void BM_PublishAndDeliver(benchmark::State& state) {
  const auto subscriber_count = static_cast<size_t>(state.range(0));
  os::SimScheduler scheduler(kMaxSubscribers);
  os::SimPort port(scheduler);
  StaticBroker<1, kMaxSubscribers> broker(port);
  Publisher<Tuple> publisher;
  std::vector<std::unique_ptr<TakingTask>> tasks;
  if (publisher.Advertise(broker, kTopic) != BrokerError::kOk) state.SkipWithError("advertise failed");
  for (size_t i = 0; i < subscriber_count; ++i) {
    tasks.push_back(std::make_unique<TakingTask>());
    const auto id = port.AddTask(*tasks.back(), {"subscriber", os::Trigger::notified(), 0});
    if (!id || tasks.back()->subscriber.Subscribe(broker, kTopic, id.value()) != BrokerError::kOk) {
      state.SkipWithError("subscribe failed");
    }
  }
  (void)port.Start();
  Tuple tuple{};
  for (auto _ : state) {
    tuple.values[0] += 1.0f;
    benchmark::DoNotOptimize(publisher.Publish(tuple));
    while (scheduler.RunNext()) {
    }
  }
  state.SetComplexityN(static_cast<int64_t>(subscriber_count));
}
BENCHMARK(BM_PublishAndDeliver)->Arg(1)->Arg(2)->Arg(4)->Arg(8)->Arg(16)->Arg(32)->Arg(64)->Complexity(benchmark::oN);

}  // namespace
}  // namespace syrof::pubsub

BENCHMARK_MAIN();
