// The lab's radio network: outbox, one delivery per broadcast, encode and
// decode once, delivery only to listening receivers through the channel.
#include "syrof/lab/sim/radio_network.h"

#include <gtest/gtest.h>

#include <array>
#include <vector>

namespace syrof::lab::sim {
namespace {

constexpr uint16_t kRobots = 4;

struct Delivery {
  uint16_t receiver;
  const wire::Beacon* beacon;
};

class RecordingReceivers final : public BeaconReceivers {
 public:
  bool Listening(uint16_t robot) const override { return listening[robot]; }
  void Receive(uint16_t robot, std::span<const wire::Beacon* const> beacons) override {
    EXPECT_FALSE(beacons.empty());
    for (const wire::Beacon* beacon : beacons) deliveries.push_back({robot, beacon});
  }
  void ReceiveAt(uint16_t robot, const wire::Beacon& beacon, int64_t arrival_ns) override {
    deliveries.push_back({robot, &beacon});
    arrivals.push_back(arrival_ns);
  }

  std::array<bool, kRobots> listening{true, true, true, true};
  std::vector<Delivery> deliveries;
  std::vector<int64_t> arrivals;
};

wire::Beacon BeaconFrom(uint16_t id, uint16_t epoch) {
  wire::Beacon beacon;
  beacon.robot_id = id;
  beacon.epoch = epoch;
  beacon.snapshot.x_mm = static_cast<int16_t>(100 * id + 7);
  const uint8_t payload[2] = {static_cast<uint8_t>(id), 0x5A};
  EXPECT_EQ(beacon.snapshot.SetPayload(payload), wire::WireError::kOk);
  return beacon;
}

TEST(RadioNetworkTest, ABroadcastReachesEveryOtherListeningRobotOnceAsSent) {
  RadioNetwork network(world::ChannelSpec{}, kRobots, 1);
  RecordingReceivers receivers;
  receivers.listening[3] = false;  // crashed
  const wire::Beacon sent = BeaconFrom(1, 9);

  network.radio(1).Broadcast(sent);
  EXPECT_TRUE(network.waiting(1));
  network.Deliver(0, 0.0, receivers);

  ASSERT_EQ(receivers.deliveries.size(), 2u);
  EXPECT_EQ(receivers.deliveries[0].receiver, 0);
  EXPECT_EQ(receivers.deliveries[1].receiver, 2);
  EXPECT_EQ(*receivers.deliveries[0].beacon, sent);  // through the codec unchanged
  EXPECT_EQ(receivers.deliveries[0].beacon, receivers.deliveries[1].beacon);  // decoded once
  EXPECT_FALSE(network.waiting(1));
  EXPECT_EQ(network.beacons_malformed(), 0u);
}

TEST(RadioNetworkTest, ABeaconIsDeliveredOnlyInTheRoundAfterItsBroadcast) {
  RadioNetwork network(world::ChannelSpec{}, kRobots, 1);
  RecordingReceivers receivers;

  network.radio(0).Broadcast(BeaconFrom(0, 1));
  network.radio(0).Broadcast(BeaconFrom(0, 2));  // replaces the first
  network.Deliver(0, 0.0, receivers);
  const size_t first = receivers.deliveries.size();
  network.Deliver(1, 0.05, receivers);

  EXPECT_EQ(first, kRobots - 1u);
  EXPECT_EQ(receivers.deliveries.size(), first);  // nothing new was sent
  EXPECT_EQ(receivers.deliveries[0].beacon->epoch, 2);
}

// What the engine relies on: each receiver's inbox fills in sender order.
// The calls come receiver by receiver (one inbox touched at a time).
TEST(RadioNetworkTest, EachReceiverGetsItsBeaconsTogetherInSenderOrder) {
  RadioNetwork network(world::ChannelSpec{}, kRobots, 1);
  RecordingReceivers receivers;

  for (uint16_t id = kRobots; id-- > 0;) network.radio(id).Broadcast(BeaconFrom(id, 3));
  network.Deliver(0, 0.0, receivers);

  ASSERT_EQ(receivers.deliveries.size(), kRobots * (kRobots - 1u));
  size_t k = 0;
  for (uint16_t receiver = 0; receiver < kRobots; ++receiver) {
    for (uint16_t sender = 0; sender < kRobots; ++sender) {
      if (receiver == sender) continue;
      EXPECT_EQ(receivers.deliveries[k].receiver, receiver);
      EXPECT_EQ(receivers.deliveries[k].beacon->robot_id, sender);
      ++k;
    }
  }
}

TEST(RadioNetworkTest, TheChannelDecidesWithTheSameDrawsForTheSameSeed) {
  world::ChannelSpec lossy;
  lossy.loss = 0.5;
  auto run = [&](uint64_t seed) {
    RadioNetwork network(lossy, kRobots, seed);
    RecordingReceivers receivers;
    std::vector<uint16_t> heard;
    for (int64_t round = 0; round < 50; ++round) {
      for (uint16_t id = 0; id < kRobots; ++id) network.radio(id).Broadcast(BeaconFrom(id, 1));
      receivers.deliveries.clear();
      network.Deliver(round, static_cast<double>(round) * 0.05, receivers);
      for (const Delivery& delivery : receivers.deliveries) {
        heard.push_back(static_cast<uint16_t>(delivery.beacon->robot_id * kRobots + delivery.receiver));
      }
      heard.push_back(0xFFFF);
    }
    return heard;
  };

  const std::vector<uint16_t> first = run(7);
  const std::vector<uint16_t> again = run(7);
  const std::vector<uint16_t> other = run(8);

  EXPECT_EQ(first, again);
  EXPECT_NE(first, other);
  const size_t delivered = first.size() - 50;
  EXPECT_GT(delivered, 50u * 12 * 3 / 10);  // about half of 600 links
  EXPECT_LT(delivered, 50u * 12 * 7 / 10);
}

// The thread mode's way (simulation.cpp): blocks of receivers, each
// encoding its own senders' beacons and then delivering to its own
// receivers, in any order of blocks: per receiver, the same beacons in the
// same order as one Deliver, with the same losses, and a mute robot's
// beacon still decoded but heard by nobody.
TEST(RadioNetworkTest, BlocksEncodingAndDeliveringApartGiveTheSameDeliveries) {
  world::ChannelSpec lossy;
  lossy.loss = 0.3;
  const std::vector<scenario::FaultSpec> faults = {
      scenario::FaultSpec{.kind = scenario::FaultKind::kMute, .robot = 2, .at_s = 0.5, .until_s = 1.0}};
  RadioNetwork whole(lossy, kRobots, 5);
  RadioNetwork split(lossy, kRobots, 5);
  whole.SetRadioFaults(faults);
  split.SetRadioFaults(faults);
  const std::array<uint16_t, 3> starts{0, 1, 3};
  split.SplitReceivers(starts);
  RecordingReceivers one;
  RecordingReceivers blocks;
  one.listening[1] = blocks.listening[1] = false;
  std::vector<uint16_t> heard_whole;
  std::vector<uint16_t> heard_split;
  const auto heard = [](const RecordingReceivers& receivers, std::vector<uint16_t>& out) {
    for (const Delivery& delivery : receivers.deliveries) {
      out.push_back(static_cast<uint16_t>(delivery.beacon->robot_id * kRobots + delivery.receiver));
    }
  };

  for (int64_t round = 0; round < 30; ++round) {
    const double sent_at_s = static_cast<double>(round) * 0.05;
    for (uint16_t id = 0; id < kRobots; ++id) {
      if ((id + round) % 3 == 0) continue;  // some robots skip a round
      whole.radio(id).Broadcast(BeaconFrom(id, static_cast<uint16_t>(round)));
      split.radio(id).Broadcast(BeaconFrom(id, static_cast<uint16_t>(round)));
    }
    one.deliveries.clear();
    blocks.deliveries.clear();
    whole.Deliver(round, sent_at_s, one);
    split.BeginDelivery(round, sent_at_s, blocks);
    for (size_t block = split.blocks(); block-- > 0;) split.EncodeBlock(block);
    split.EndEncoding();
    std::vector<std::vector<uint16_t>> per_block(split.blocks());
    for (size_t block = split.blocks(); block-- > 0;) {
      blocks.deliveries.clear();
      split.DeliverToBlock(block, blocks);
      heard(blocks, per_block[block]);
    }
    heard(one, heard_whole);
    for (const std::vector<uint16_t>& block : per_block) heard_split.insert(heard_split.end(), block.begin(), block.end());
    heard_whole.push_back(0xFFFF);
    heard_split.push_back(0xFFFF);
  }

  EXPECT_EQ(heard_split, heard_whole);
  EXPECT_EQ(split.blocks(), 3u);
  EXPECT_GT(heard_whole.size(), 30u * 3);
  EXPECT_EQ(split.beacons_malformed(), 0u);
}

TEST(RadioNetworkTest, FullLossDeliversNothing) {
  world::ChannelSpec deaf;
  deaf.loss = 1.0;
  RadioNetwork network(deaf, kRobots, 1);
  RecordingReceivers receivers;

  network.radio(2).Broadcast(BeaconFrom(2, 1));
  network.Deliver(0, 0.0, receivers);

  EXPECT_TRUE(receivers.deliveries.empty());
  EXPECT_FALSE(network.waiting(2));
}

}  // namespace
}  // namespace syrof::lab::sim

namespace syrof::lab::sim {
namespace {

TEST(RadioNetworkClocksTest, ABroadcastTravelsAtOnceWithItsSeededJitter) {
  RadioNetwork network(world::ChannelSpec{}, kRobots, 1);
  RecordingReceivers receivers;
  int64_t now_ns = 1'234'000'000;
  network.UseClocks([&] { return now_ns; }, receivers, 50'000'000, 200'000, 9);
  network.radio(1).Broadcast(BeaconFrom(1, 5));
  ASSERT_EQ(receivers.deliveries.size(), 3u);  // at once, to 0, 2 and 3
  EXPECT_FALSE(network.waiting(1));
  for (size_t i = 0; i < 3; ++i) {
    EXPECT_EQ(receivers.deliveries[i].beacon->epoch, 5);
    EXPECT_GE(receivers.arrivals[i], now_ns + 25'000'000);  // its slot: half a round later
    EXPECT_LE(receivers.arrivals[i], now_ns + 25'200'000);
    EXPECT_EQ(receivers.arrivals[i], receivers.arrivals[0]);  // one transmission
  }
  // The decoded beacon stays valid while the sender sends again.
  const wire::Beacon* first = receivers.deliveries[0].beacon;
  now_ns += 50'000'000;
  network.radio(1).Broadcast(BeaconFrom(1, 6));
  EXPECT_EQ(first->epoch, 5);
  EXPECT_EQ(receivers.deliveries.back().beacon->epoch, 6);
}

}  // namespace
}  // namespace syrof::lab::sim
