// The broker across threads (PosixPort): tuples arrive whole, in order, and
// every tuple is either read or counted as overwritten.
#include <gtest/gtest.h>

#include <atomic>
#include <chrono>
#include <cstdint>
#include <thread>

#include "syrof/os/posix_port.h"
#include "syrof/pubsub/topic.h"

namespace syrof::pubsub {
namespace {

// A tuple whose halves must always agree: a torn copy would show.
struct Sequence {
  uint64_t number;
  uint64_t check;  // ~number
};
constexpr Topic<Sequence> kSequenceTopic{1, "sequence"};
constexpr uint64_t kTuples = 20000;

class ProducerTask final : public os::Task {
 public:
  void Step(int64_t) override {
    for (int i = 0; i < 100 && next_ < kTuples; ++i, ++next_) {
      EXPECT_EQ(publisher.Publish(Sequence{next_, ~next_}), BrokerError::kOk);
    }
    if (next_ == kTuples) done = true;
  }
  Publisher<Sequence> publisher;
  std::atomic<bool> done{false};

 private:
  uint64_t next_ = 0;
};

class ConsumerTask final : public os::Task {
 public:
  void Step(int64_t) override {
    Sequence tuple{};
    while (subscriber.Take(tuple)) {
      if (tuple.check != ~tuple.number) torn = true;
      if (received > 0 && tuple.number <= last) out_of_order = true;
      last = tuple.number;
      ++received;
    }
  }
  Subscriber<Sequence, 16> subscriber;
  std::atomic<uint64_t> received{0};
  uint64_t last = 0;
  bool torn = false;
  bool out_of_order = false;
};

TEST(BrokerThreadsTest, TuplesCrossThreadsWholeInOrderAndAccountedFor) {
  os::PosixPort port;
  StaticBroker<1, 1> broker(port);
  ProducerTask producer;
  ConsumerTask consumer;
  ASSERT_TRUE(port.AddTask(producer, {"producer", os::Trigger::periodic(100'000), 0}));
  const os::TaskId consumer_id = port.AddTask(consumer, {"consumer", os::Trigger::notified(), 0}).value();
  ASSERT_EQ(producer.publisher.Advertise(broker, kSequenceTopic), BrokerError::kOk);
  ASSERT_EQ(consumer.subscriber.Subscribe(broker, kSequenceTopic, consumer_id), BrokerError::kOk);
  ASSERT_EQ(port.Start(), os::PortError::kOk);

  const auto deadline = std::chrono::steady_clock::now() + std::chrono::seconds(20);
  while (!producer.done && std::chrono::steady_clock::now() < deadline) {
    std::this_thread::sleep_for(std::chrono::milliseconds(1));
  }
  const auto drained = [&] {
    return consumer.received + consumer.subscriber.overwritten() == kTuples;
  };
  while (!drained() && std::chrono::steady_clock::now() < deadline) {
    std::this_thread::sleep_for(std::chrono::milliseconds(1));
  }
  ASSERT_EQ(port.Stop(), os::PortError::kOk);

  EXPECT_TRUE(producer.done);
  EXPECT_FALSE(consumer.torn);
  EXPECT_FALSE(consumer.out_of_order);
  EXPECT_EQ(consumer.received + consumer.subscriber.overwritten(), kTuples);
  EXPECT_EQ(broker.published(producer.publisher.index()), kTuples);
}

}  // namespace
}  // namespace syrof::pubsub
