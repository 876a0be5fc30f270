// The broker's raw interface (the paper's registerPublisher / subscribe /
// publish): every error, fan-out, ordering and queue semantics.
#include "syrof/pubsub/broker.h"

#include <gtest/gtest.h>

#include <cstdint>

#include "recording_port.h"

namespace syrof::pubsub {
namespace {

using testing::RecordingPort;

struct Reading {
  int32_t value;
  uint16_t sensor;
};
struct WideReading {
  int64_t value[2];
};
static_assert(sizeof(WideReading) != sizeof(Reading));

class BrokerTest : public ::testing::Test {
 protected:
  RecordingPort port_;
  StaticBroker<2, 3> broker_{port_};
};

TEST_F(BrokerTest, RegisterPublisherReturnsIndicesInRegistrationOrder) {
  Queue<Reading> first, second;

  const auto first_index = broker_.RegisterPublisher(7, sizeof(Reading), first);
  const auto second_index = broker_.RegisterPublisher(3, sizeof(Reading), second);

  ASSERT_TRUE(first_index);
  ASSERT_TRUE(second_index);
  EXPECT_EQ(first_index.value(), 0);
  EXPECT_EQ(second_index.value(), 1);
  EXPECT_EQ(broker_.publisher_count(), 2u);
  EXPECT_TRUE(first.attached());
}

TEST_F(BrokerTest, DuplicatePublisherIdIsRejected) {
  Queue<Reading> first, second;
  ASSERT_TRUE(broker_.RegisterPublisher(7, sizeof(Reading), first));

  EXPECT_EQ(broker_.RegisterPublisher(7, sizeof(Reading), second).error(), BrokerError::kDuplicatePublisher);
  EXPECT_FALSE(second.attached());
}

TEST_F(BrokerTest, SubscribeToUnknownIdIsRejected) {
  Queue<Reading> queue;

  EXPECT_EQ(broker_.Subscribe(9, 0, queue), BrokerError::kUnknownTopic);
}

TEST_F(BrokerTest, TupleSizeMismatchIsRejectedOnRegisterSubscribeStageAndReceive) {
  Queue<Reading> publisher_queue;
  Queue<WideReading> wrong_queue;
  Queue<Reading> subscriber_queue;
  const Reading reading{1, 2};
  WideReading wrong_out{};

  EXPECT_EQ(broker_.RegisterPublisher(1, sizeof(Reading) + 1, publisher_queue).error(), BrokerError::kSizeMismatch);
  const PublisherIndex index = broker_.RegisterPublisher(1, sizeof(Reading), publisher_queue).value();
  EXPECT_EQ(broker_.Subscribe(1, 0, wrong_queue), BrokerError::kSizeMismatch);
  ASSERT_EQ(broker_.Subscribe(1, 0, subscriber_queue), BrokerError::kOk);
  EXPECT_EQ(broker_.Stage(index, &reading, sizeof(Reading) - 1), BrokerError::kSizeMismatch);
  EXPECT_EQ(broker_.Receive(subscriber_queue, &wrong_out, sizeof(wrong_out)), BrokerError::kSizeMismatch);
}

TEST_F(BrokerTest, PublisherTableCapacityExhausted) {
  Queue<Reading> a, b, c;
  ASSERT_TRUE(broker_.RegisterPublisher(1, sizeof(Reading), a));
  ASSERT_TRUE(broker_.RegisterPublisher(2, sizeof(Reading), b));

  EXPECT_EQ(broker_.RegisterPublisher(3, sizeof(Reading), c).error(), BrokerError::kCapacityExhausted);
}

TEST_F(BrokerTest, SubscriptionTableCapacityExhausted) {
  Queue<Reading> publisher_queue, s1, s2, s3, s4;
  ASSERT_TRUE(broker_.RegisterPublisher(1, sizeof(Reading), publisher_queue));
  ASSERT_EQ(broker_.Subscribe(1, 0, s1), BrokerError::kOk);
  ASSERT_EQ(broker_.Subscribe(1, 1, s2), BrokerError::kOk);
  ASSERT_EQ(broker_.Subscribe(1, 2, s3), BrokerError::kOk);

  EXPECT_EQ(broker_.Subscribe(1, 3, s4), BrokerError::kCapacityExhausted);
}

TEST_F(BrokerTest, PublishOnAnIndexNeverRegisteredIsRejected) {
  Queue<Reading> queue;
  const Reading reading{1, 2};
  ASSERT_TRUE(broker_.RegisterPublisher(1, sizeof(Reading), queue));

  EXPECT_EQ(broker_.Publish(1), BrokerError::kUnregisteredIndex);
  EXPECT_EQ(broker_.Publish(255), BrokerError::kUnregisteredIndex);
  EXPECT_EQ(broker_.Stage(1, &reading, sizeof(Reading)), BrokerError::kUnregisteredIndex);
}

TEST_F(BrokerTest, AQueueServesOnlyOneRegistration) {
  Queue<Reading> shared, other;
  ASSERT_TRUE(broker_.RegisterPublisher(1, sizeof(Reading), shared));

  EXPECT_EQ(broker_.Subscribe(1, 0, shared), BrokerError::kInvalidQueue);
  EXPECT_EQ(broker_.RegisterPublisher(2, sizeof(Reading), shared).error(), BrokerError::kInvalidQueue);
  ASSERT_EQ(broker_.Subscribe(1, 0, other), BrokerError::kOk);
  EXPECT_EQ(broker_.Subscribe(1, 1, other), BrokerError::kInvalidQueue);
}

TEST_F(BrokerTest, EveryErrorHasADistinctName) {
  const BrokerError errors[] = {BrokerError::kOk,           BrokerError::kDuplicatePublisher,
                                BrokerError::kUnknownTopic, BrokerError::kSizeMismatch,
                                BrokerError::kCapacityExhausted, BrokerError::kUnregisteredIndex,
                                BrokerError::kInvalidQueue, BrokerError::kEmpty};
  for (const BrokerError a : errors) {
    for (const BrokerError b : errors) {
      if (a != b) {
        EXPECT_STRNE(ToString(a), ToString(b));
      }
    }
  }
}

TEST_F(BrokerTest, PublishFansOutToEverySubscriberAndNotifiesEachInSubscriptionOrder) {
  Queue<Reading> publisher_queue, to_task_5, to_task_2, to_task_9;
  const PublisherIndex index = broker_.RegisterPublisher(4, sizeof(Reading), publisher_queue).value();
  ASSERT_EQ(broker_.Subscribe(4, 5, to_task_5), BrokerError::kOk);
  ASSERT_EQ(broker_.Subscribe(4, 2, to_task_2), BrokerError::kOk);
  ASSERT_EQ(broker_.Subscribe(4, 9, to_task_9), BrokerError::kOk);
  const Reading sent{-42, 3};

  ASSERT_EQ(broker_.Stage(index, &sent, sizeof(sent)), BrokerError::kOk);
  ASSERT_EQ(broker_.Publish(index), BrokerError::kOk);

  EXPECT_EQ(port_.notified, (std::vector<os::TaskId>{5, 2, 9}));
  for (QueueBase* queue : {static_cast<QueueBase*>(&to_task_5), static_cast<QueueBase*>(&to_task_2),
                           static_cast<QueueBase*>(&to_task_9)}) {
    Reading received{};
    ASSERT_EQ(broker_.Receive(*queue, &received, sizeof(received)), BrokerError::kOk);
    EXPECT_EQ(received.value, -42);
    EXPECT_EQ(received.sensor, 3);
  }
  EXPECT_EQ(publisher_queue.size(), 0);
  EXPECT_EQ(broker_.published(index), 1u);
  EXPECT_EQ(port_.depth, 0);
}

TEST_F(BrokerTest, PublishDeliversEveryStagedTupleInOrderAndNotifiesOnce) {
  Queue<Reading, 4> publisher_queue;
  Queue<Reading, 4> subscriber_queue;
  const PublisherIndex index = broker_.RegisterPublisher(1, sizeof(Reading), publisher_queue).value();
  ASSERT_EQ(broker_.Subscribe(1, 6, subscriber_queue), BrokerError::kOk);

  for (int32_t i = 0; i < 3; ++i) {
    const Reading reading{i, 0};
    ASSERT_EQ(broker_.Stage(index, &reading, sizeof(reading)), BrokerError::kOk);
  }
  ASSERT_EQ(broker_.Publish(index), BrokerError::kOk);

  EXPECT_EQ(port_.notified, (std::vector<os::TaskId>{6}));
  for (int32_t i = 0; i < 3; ++i) {
    Reading received{};
    ASSERT_EQ(broker_.Receive(subscriber_queue, &received, sizeof(received)), BrokerError::kOk);
    EXPECT_EQ(received.value, i);
  }
  Reading none{};
  EXPECT_EQ(broker_.Receive(subscriber_queue, &none, sizeof(none)), BrokerError::kEmpty);
}

TEST_F(BrokerTest, PublishingAnEmptyQueueNotifiesNobody) {
  Queue<Reading> publisher_queue, subscriber_queue;
  const PublisherIndex index = broker_.RegisterPublisher(1, sizeof(Reading), publisher_queue).value();
  ASSERT_EQ(broker_.Subscribe(1, 0, subscriber_queue), BrokerError::kOk);

  EXPECT_EQ(broker_.Publish(index), BrokerError::kOk);

  EXPECT_TRUE(port_.notified.empty());
}

TEST_F(BrokerTest, FullSubscriberQueueOverwritesTheOldestAndCountsIt) {
  Queue<Reading> publisher_queue;
  Queue<Reading, 2> subscriber_queue;
  const PublisherIndex index = broker_.RegisterPublisher(1, sizeof(Reading), publisher_queue).value();
  ASSERT_EQ(broker_.Subscribe(1, 0, subscriber_queue), BrokerError::kOk);

  for (int32_t i = 1; i <= 5; ++i) {
    const Reading reading{i, 0};
    ASSERT_EQ(broker_.Stage(index, &reading, sizeof(reading)), BrokerError::kOk);
    ASSERT_EQ(broker_.Publish(index), BrokerError::kOk);
  }

  EXPECT_EQ(subscriber_queue.overwritten(), 3u);
  Reading received{};
  ASSERT_EQ(broker_.Receive(subscriber_queue, &received, sizeof(received)), BrokerError::kOk);
  EXPECT_EQ(received.value, 4);
  ASSERT_EQ(broker_.Receive(subscriber_queue, &received, sizeof(received)), BrokerError::kOk);
  EXPECT_EQ(received.value, 5);
}

TEST_F(BrokerTest, ReceiveLatestKeepsOnlyTheNewestTuple) {
  Queue<Reading> publisher_queue;
  Queue<Reading, 4> subscriber_queue;
  const PublisherIndex index = broker_.RegisterPublisher(1, sizeof(Reading), publisher_queue).value();
  ASSERT_EQ(broker_.Subscribe(1, 0, subscriber_queue), BrokerError::kOk);
  for (int32_t i = 1; i <= 3; ++i) {
    const Reading reading{i, 0};
    ASSERT_EQ(broker_.Stage(index, &reading, sizeof(reading)), BrokerError::kOk);
    ASSERT_EQ(broker_.Publish(index), BrokerError::kOk);
  }

  Reading latest{};
  ASSERT_EQ(broker_.ReceiveLatest(subscriber_queue, &latest, sizeof(latest)), BrokerError::kOk);

  EXPECT_EQ(latest.value, 3);
  EXPECT_EQ(subscriber_queue.size(), 0);
  EXPECT_EQ(broker_.ReceiveLatest(subscriber_queue, &latest, sizeof(latest)), BrokerError::kEmpty);
}

TEST_F(BrokerTest, TopicsAreIndependent) {
  Queue<Reading> imu_out, flow_out, imu_in, flow_in;
  const PublisherIndex imu = broker_.RegisterPublisher(10, sizeof(Reading), imu_out).value();
  ASSERT_TRUE(broker_.RegisterPublisher(20, sizeof(Reading), flow_out));
  ASSERT_EQ(broker_.Subscribe(10, 1, imu_in), BrokerError::kOk);
  ASSERT_EQ(broker_.Subscribe(20, 2, flow_in), BrokerError::kOk);
  const Reading reading{5, 10};

  ASSERT_EQ(broker_.Stage(imu, &reading, sizeof(reading)), BrokerError::kOk);
  ASSERT_EQ(broker_.Publish(imu), BrokerError::kOk);

  EXPECT_EQ(imu_in.size(), 1);
  EXPECT_EQ(flow_in.size(), 0);
  EXPECT_EQ(port_.notified, (std::vector<os::TaskId>{1}));
}

}  // namespace
}  // namespace syrof::pubsub
