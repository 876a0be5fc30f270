#include "syrof/sim_dds/beacon_radio.h"

#include <gtest/gtest.h>

#include <algorithm>
#include <array>
#include <atomic>
#include <chrono>
#include <map>
#include <mutex>
#include <thread>
#include <vector>

#include "syrof/app/app.h"
#include "syrof/base/split_mix64.h"
#include "syrof/estimation/topics.h"
#include "syrof/os/posix_port.h"
#include "syrof/pubsub/broker.h"
#include "syrof/pubsub/topic.h"
#include "syrof/runtime/robot.h"
#include "syrof/sim_dds/topics.h"
#include "syrof/wire/beacon_codec.h"
#include "test_domain.h"

namespace syrof::sim_dds {
namespace {

using lab::world::Channel;
using lab::world::ChannelModel;
using lab::world::ChannelSpec;

// Waits (polling) until `done` holds; false after 5 s. Not a timing
// assertion: it only bounds how long a broken test hangs.
template <typename Predicate>
bool WaitFor(Predicate done) {
  const auto deadline = std::chrono::steady_clock::now() + std::chrono::seconds(5);
  while (!done()) {
    if (std::chrono::steady_clock::now() > deadline) return false;
    std::this_thread::sleep_for(std::chrono::milliseconds(1));
  }
  return true;
}

// What a sink saw: (sender, round, decoded robot id) per frame.
struct Heard {
  std::mutex mutex;
  std::vector<std::tuple<uint16_t, uint32_t, uint16_t>> frames;
  uint16_t swarm_size;

  explicit Heard(uint16_t swarm) : swarm_size(swarm) {}
  BeaconSink Sink() {
    return [this](std::span<const uint8_t> frame, uint16_t sender, uint32_t round) {
      const auto beacon = wire::Decode(frame, swarm_size);
      std::lock_guard<std::mutex> lock(mutex);
      frames.emplace_back(sender, round, beacon.ok() ? beacon.value().robot_id : uint16_t{0xFFFF});
    };
  }
  size_t size() {
    std::lock_guard<std::mutex> lock(mutex);
    return frames.size();
  }
};

wire::Beacon BeaconOf(uint16_t robot) {
  wire::Beacon beacon;
  beacon.robot_id = robot;
  beacon.epoch = 1;
  return beacon;
}

BeaconRadioOptions Options(uint16_t self, uint16_t swarm, std::atomic<int64_t>& round) {
  BeaconRadioOptions options;
  options.self = self;
  options.swarm_size = swarm;
  options.seed = 11;
  options.current_round = [&round] { return round.load(); };
  return options;
}

struct Pair {
  std::unique_ptr<Participant> a_participant, b_participant;
  std::unique_ptr<BeaconRadio> a, b;
};

TEST(BeaconRadio, TwoParticipantsExchangeBeacons) {
  const uint32_t domain = testing::FreshDomainId();
  ParticipantOrError pa = Participant::Create(domain, CycloneOptions{});
  ParticipantOrError pb = Participant::Create(domain, CycloneOptions{});
  ASSERT_TRUE(pa.ok() && pb.ok());
  std::atomic<int64_t> round{0};
  Heard heard_a(3), heard_b(3);
  BeaconRadioOrError a = BeaconRadio::Create(*pa.participant, Options(0, 3, round), heard_a.Sink());
  BeaconRadioOrError b = BeaconRadio::Create(*pb.participant, Options(1, 3, round), heard_b.Sink());
  ASSERT_TRUE(a.ok()) << a.error->ToString();
  ASSERT_TRUE(b.ok()) << b.error->ToString();
  ASSERT_TRUE(WaitFor([&] { return a.radio->matched_readers() >= 1 && b.radio->matched_readers() >= 1; }));

  for (int64_t r = 0; r < 20; ++r) {
    round = r;
    a.radio->Broadcast(BeaconOf(0));
    b.radio->Broadcast(BeaconOf(1));
    ASSERT_TRUE(WaitFor([&] { return heard_b.size() == static_cast<size_t>(r + 1) && heard_a.size() == static_cast<size_t>(r + 1); }))
        << "round " << r;
  }
  for (uint32_t r = 0; r < 20; ++r) {
    EXPECT_EQ(heard_b.frames[r], std::make_tuple(uint16_t{0}, r, uint16_t{0}));
    EXPECT_EQ(heard_a.frames[r], std::make_tuple(uint16_t{1}, r, uint16_t{1}));
  }
  EXPECT_EQ(a.radio->counters().sent, 20u);
  EXPECT_EQ(b.radio->counters().delivered, 20u);
  EXPECT_EQ(b.radio->counters().rejected, 0u);  // its own beacons are not even taken
  EXPECT_EQ(b.radio->sample_counters().count(SampleVerdict::kFromSelf), 0u);
}

// Two runs that land on one domain (1 in 231 pairs of concurrent runs, more
// on a machine running many): each radio hears only its own run's robots,
// though the other run's robot 0 writes under the same key (issue 46).
TEST(BeaconRadio, HearsOnlyItsOwnRunOnASharedDomain) {
  const uint32_t domain = testing::FreshDomainId();
  ParticipantOrError pa = Participant::Create(domain, CycloneOptions{});
  ParticipantOrError pb = Participant::Create(domain, CycloneOptions{});
  ParticipantOrError pc = Participant::Create(domain, CycloneOptions{});
  ASSERT_TRUE(pa.ok() && pb.ok() && pc.ok());
  std::atomic<int64_t> round{0};
  BeaconRadioOptions ours = Options(0, 3, round);
  ours.run_id = 1001;
  BeaconRadioOptions listener = Options(1, 3, round);
  listener.run_id = 1001;
  BeaconRadioOptions theirs = Options(0, 3, round);  // the other run's robot 0
  theirs.run_id = 2002;
  std::mutex mutex;
  std::vector<uint16_t> epochs;  // of every frame delivered to robot 1
  BeaconRadioOrError a = BeaconRadio::Create(*pa.participant, ours);
  BeaconRadioOrError b = BeaconRadio::Create(*pb.participant, listener,
                                             [&](std::span<const uint8_t> frame, uint16_t, uint32_t) {
                                               const auto beacon = wire::Decode(frame, 3);
                                               std::lock_guard<std::mutex> lock(mutex);
                                               epochs.push_back(beacon.ok() ? beacon.value().epoch : 0xFFFF);
                                             });
  BeaconRadioOrError c = BeaconRadio::Create(*pc.participant, theirs);
  ASSERT_TRUE(a.ok() && b.ok() && c.ok());
  ASSERT_TRUE(WaitFor([&] { return a.radio->matched_readers() >= 1 && c.radio->matched_readers() >= 1; }));

  for (int64_t r = 0; r < 10; ++r) {
    round = r;
    wire::Beacon other = BeaconOf(0);
    other.epoch = 9;  // another swarm's epoch
    // One at a time: both write under key 0, and keep last 1 would let the
    // second replace the first before the listener takes it.
    c.radio->Broadcast(other);
    ASSERT_TRUE(WaitFor([&] { return b.radio->counters().received == static_cast<uint64_t>(2 * r + 1); }))
        << "round " << r;
    a.radio->Broadcast(BeaconOf(0));
    ASSERT_TRUE(WaitFor([&] { return b.radio->counters().received == static_cast<uint64_t>(2 * r + 2); }))
        << "round " << r;
  }
  {
    std::lock_guard<std::mutex> lock(mutex);
    EXPECT_EQ(epochs, std::vector<uint16_t>(10, 1));  // robot 0 of this run, every round, nothing of the other
  }
  EXPECT_EQ(b.radio->sample_counters().count(SampleVerdict::kOtherRun), 10u);
  EXPECT_EQ(b.radio->counters().delivered, 10u);
  EXPECT_EQ(b.radio->counters().received, 20u);
  EXPECT_EQ(b.radio->counters().rejected, 10u);
}

class IdleApp final : public app::App {
 public:
  const char* name() const override { return "idle"; }
  app::CallStatus Init(const syrof_app_info&, app::Platform&, uint8_t& global_state) override {
    global_state = 0;
    return app::CallStatus::Ok();
  }
  app::CallStatus NewRound(syrof_car_command&, const syrof_ldmap&, uint8_t&, uint32_t) override {
    return app::CallStatus::Ok();
  }
  app::CallStatus EndOfRound(const syrof_ldmap&, uint8_t&, uint32_t) override { return app::CallStatus::Ok(); }
};

// The wiring of a robot process: the radio first (the Robot takes it), then
// receiving into the Robot.
TEST(BeaconRadio, DeliversIntoARobot) {
  constexpr uint16_t kRobots = 4;
  const uint32_t domain = testing::FreshDomainId();
  ParticipantOrError pr = Participant::Create(domain, CycloneOptions{});
  ParticipantOrError ps = Participant::Create(domain, CycloneOptions{});
  ASSERT_TRUE(pr.ok() && ps.ok());
  std::atomic<int64_t> round{0};
  BeaconRadioOrError radio = BeaconRadio::Create(*pr.participant, Options(0, kRobots, round));
  ASSERT_TRUE(radio.ok()) << radio.error->ToString();

  os::PosixPort port;
  pubsub::StaticBroker<8, 12> broker{port};
  pubsub::Publisher<estimation::ImuReading> imu;
  pubsub::Publisher<estimation::FlowReading> flow;
  pubsub::Publisher<estimation::UwbReading> uwb;
  ASSERT_EQ(imu.Advertise(broker, estimation::kImuTopic), pubsub::BrokerError::kOk);
  ASSERT_EQ(flow.Advertise(broker, estimation::kFlowTopic), pubsub::BrokerError::kOk);
  ASSERT_EQ(uwb.Advertise(broker, estimation::kUwbTopic), pubsub::BrokerError::kOk);
  runtime::RobotConfig config;
  config.sync = sync::SyncConfig::ForSwarm(kRobots, 0);
  config.radio_round_ns = 1'000'000'000;  // the port does not run: nothing is stepped
  IdleApp app;
  std::array<wire::Beacon, runtime::Robot::kReceiveBanks * kRobots> storage{};
  runtime::Robot robot(config, app, *radio.radio, storage);
  ASSERT_EQ(robot.Attach(port, broker), runtime::RobotSetupError::kOk);
  ASSERT_FALSE(radio.radio->StartReceiving(robot).has_value());
  const std::optional<Error> again = radio.radio->StartReceiving(robot);
  ASSERT_TRUE(again.has_value());
  EXPECT_EQ(again->ToString(), "rt/syrof/beacon: this radio already receives");

  Heard unused(kRobots);
  BeaconRadioOrError sender = BeaconRadio::Create(*ps.participant, Options(2, kRobots, round), unused.Sink());
  ASSERT_TRUE(sender.ok());
  ASSERT_TRUE(WaitFor([&] { return sender.radio->matched_readers() >= 1; }));
  for (int64_t r = 0; r < 3; ++r) {
    round = r;
    sender.radio->Broadcast(BeaconOf(2));
    ASSERT_TRUE(WaitFor([&] { return radio.radio->counters().delivered == static_cast<uint64_t>(r + 1); }));
  }
  EXPECT_EQ(robot.counters().beacons_received, 3u);
  EXPECT_EQ(robot.counters().beacons_malformed, 0u);
  // Each beacon arrived in the round it was sent for: heard in-round.
  for (int64_t r = 0; r < 3; ++r) {
    const wire::MemberSet heard = radio.radio->HeardInRound(r);
    EXPECT_TRUE(heard.test(2)) << "round " << r;
    EXPECT_EQ(heard.count(), 1) << "round " << r;
  }
  EXPECT_TRUE(radio.radio->HeardInRound(3).empty());
  // A beacon of round 3 that arrives in round 4 is delivered, not in-round.
  round = 4;
  BeaconRadioOptions late = Options(2, kRobots, round);
  late.current_round = [] { return int64_t{3}; };
  BeaconRadioOrError late_sender = BeaconRadio::Create(*ps.participant, late);
  ASSERT_TRUE(late_sender.ok());
  ASSERT_TRUE(WaitFor([&] { return late_sender.radio->matched_readers() >= 1; }));
  late_sender.radio->Broadcast(BeaconOf(2));
  ASSERT_TRUE(WaitFor([&] { return radio.radio->counters().delivered == 4u; }));
  EXPECT_TRUE(radio.radio->HeardInRound(3).empty());
  EXPECT_TRUE(radio.radio->HeardInRound(4).empty());
  late_sender.radio.reset();
  sender.radio.reset();
  radio.radio.reset();  // stops receiving before the robot goes
}

TEST(BeaconRadio, RefusesBadOptionsWithTheirName) {
  ParticipantOrError made = Participant::Create(testing::FreshDomainId(), CycloneOptions{});
  ASSERT_TRUE(made.ok());
  std::atomic<int64_t> round{0};
  Heard heard(3);
  BeaconRadioOptions options = Options(3, 3, round);
  EXPECT_EQ(BeaconRadio::Create(*made.participant, options, heard.Sink()).error->where, "self");
  options = Options(0, 3, round);
  options.channel.loss = 1.5;
  const BeaconRadioOrError bad_loss = BeaconRadio::Create(*made.participant, options, heard.Sink());
  ASSERT_FALSE(bad_loss.ok());
  EXPECT_EQ(bad_loss.error->ToString(), "channel: loss must be in [0, 1], not 1.500000");
  options = Options(0, 3, round);
  options.channel.links = {{.from = 0, .to = 7, .loss = 0.5}};
  EXPECT_EQ(BeaconRadio::Create(*made.participant, options, heard.Sink()).error->where, "channel link 0 -> 7");
  options = Options(0, 0, round);
  EXPECT_EQ(BeaconRadio::Create(*made.participant, options, heard.Sink()).error->where, "swarm_size");
  options = Options(0, 3, round);
  options.current_round = nullptr;
  EXPECT_EQ(BeaconRadio::Create(*made.participant, options, heard.Sink()).error->where, "current_round");
  EXPECT_EQ(BeaconRadio::Create(*made.participant, Options(0, 3, round), BeaconSink{}).error->where, "sink");
}

// A channel with every feature: Gilbert-Elliott, a per-link override and a
// partition.
ChannelSpec BurstyChannel() {
  ChannelSpec spec;
  spec.model = ChannelModel::kGilbertElliott;
  spec.good_to_bad = 0.1;
  spec.bad_to_good = 0.3;
  spec.loss_good = 0.05;
  spec.loss_bad = 0.9;
  spec.links = {{.from = 2, .to = 1, .loss = 0.5}};
  spec.partitions = {{.start_s = 2.0, .end_s = 3.0, .groups = {{0, 1}}}};
  return spec;
}

TEST(BeaconRadioLoss, AReceiverOnlyChannelDecidesAsTheLabs) {
  constexpr uint16_t kRobots = 6;
  constexpr int64_t kRounds = 300;
  constexpr uint64_t kSeed = 2026;
  const ChannelSpec spec = BurstyChannel();
  // The lab: one channel asked about every link, round by round.
  Channel lab(spec, kRobots, kSeed);
  std::map<std::tuple<uint16_t, uint16_t, int64_t>, bool> decided;
  for (int64_t round = 0; round < kRounds; ++round) {
    for (uint16_t from = 0; from < kRobots; ++from) {
      for (uint16_t to = 0; to < kRobots; ++to) {
        if (from != to) decided[{from, to, round}] = lab.Delivers(from, to, round, static_cast<double>(round) * 0.05);
      }
    }
  }
  // Each robot: a channel of its own asked only about its incoming links,
  // senders in a shuffled order and some rounds skipped (a crashed sender, a
  // lost sample), as a robot process asks.
  for (uint16_t self = 0; self < kRobots; ++self) {
    Channel own(spec, kRobots, kSeed);
    base::SplitMix64 random(self + 1);
    for (int64_t round = 0; round < kRounds; ++round) {
      std::vector<uint16_t> senders;
      for (uint16_t from = 0; from < kRobots; ++from) {
        if (from != self && random.Next() % 4 != 0) senders.push_back(from);
      }
      for (size_t i = senders.size(); i > 1; --i) std::swap(senders[i - 1], senders[random.Below(static_cast<uint32_t>(i))]);
      for (const uint16_t from : senders) {
        ASSERT_EQ(own.Delivers(from, self, round, static_cast<double>(round) * 0.05), (decided[{from, self, round}]))
            << from << " -> " << self << " round " << round;
      }
    }
  }
}

TEST(BeaconRadioLoss, DeliversExactlyWhatTheLabsChannelDelivers) {
  const uint32_t domain = testing::FreshDomainId();
  constexpr uint16_t kRobots = 3;
  ParticipantOrError pa = Participant::Create(domain, CycloneOptions{});
  ParticipantOrError pb = Participant::Create(domain, CycloneOptions{});
  ASSERT_TRUE(pa.ok() && pb.ok());
  std::atomic<int64_t> round{0};
  Heard heard_b(kRobots), unused(kRobots);
  BeaconRadioOptions a_options = Options(2, kRobots, round);
  BeaconRadioOptions b_options = Options(1, kRobots, round);
  b_options.channel = BurstyChannel();
  b_options.seed = 77;
  BeaconRadioOrError a = BeaconRadio::Create(*pa.participant, a_options, unused.Sink());
  BeaconRadioOrError b = BeaconRadio::Create(*pb.participant, b_options, heard_b.Sink());
  ASSERT_TRUE(a.ok() && b.ok());
  ASSERT_TRUE(WaitFor([&] { return a.radio->matched_readers() >= 1; }));

  // Robot 2 -> robot 1 is the per-link override, and the partition (rounds
  // 40 to 59 at 50 ms) cuts it: 2 is in the unlisted group, 1 in {0, 1}.
  constexpr int64_t kRounds = 120;
  for (int64_t r = 0; r < kRounds; ++r) {
    round = r;
    const uint64_t before = b.radio->counters().received;
    a.radio->Broadcast(BeaconOf(2));
    ASSERT_TRUE(WaitFor([&] { return b.radio->counters().received == before + 1; })) << "round " << r;
  }
  Channel lab(BurstyChannel(), kRobots, 77);
  std::vector<uint32_t> expected;
  for (int64_t r = 0; r < kRounds; ++r) {
    for (uint16_t from = 0; from < kRobots; ++from) {
      for (uint16_t to = 0; to < kRobots; ++to) {
        if (from == to) continue;
        const bool delivered = lab.Delivers(from, to, r, static_cast<double>(r) * 0.05);
        if (from == 2 && to == 1 && delivered) expected.push_back(static_cast<uint32_t>(r));
      }
    }
  }
  std::vector<uint32_t> got;
  for (const auto& [sender, frame_round, id] : heard_b.frames) got.push_back(frame_round);
  EXPECT_EQ(got, expected);
  EXPECT_GT(expected.size(), 20u);    // the loss is not total
  EXPECT_LT(expected.size(), 100u);   // nor absent
  EXPECT_EQ(b.radio->counters().lost, kRounds - expected.size());
}

// Writes raw Beacon_ samples, as a rogue participant would.
class RogueWriter {
 public:
  explicit RogueWriter(const Participant& participant) {
    const EntityOrError made = CreateWriter(participant, TopicKind::kBeacon);
    EXPECT_TRUE(made.ok());
    writer_ = made.entity;
  }
  dds_return_t Write(uint16_t sender, uint32_t round, std::vector<uint8_t> bytes) {
    syrof_msg_dds__Beacon_ sample{};
    sample.sender = sender;
    sample.round = round;
    sample.wire._maximum = static_cast<uint32_t>(bytes.size());
    sample.wire._length = static_cast<uint32_t>(bytes.size());
    sample.wire._buffer = bytes.data();
    sample.wire._release = false;
    return dds_write(writer_, &sample);
  }
  dds_entity_t writer() const { return writer_; }

 private:
  dds_entity_t writer_ = 0;
};

std::vector<uint8_t> Encoded(uint16_t robot, uint16_t swarm) {
  std::vector<uint8_t> bytes(wire::EncodedSize(swarm));
  EXPECT_TRUE(wire::Encode(BeaconOf(robot), swarm, bytes).ok());
  return bytes;
}

TEST(BeaconRadioRogue, RejectedAndCountedWhileGoodBeaconsArrive) {
  const uint32_t domain = testing::FreshDomainId();
  constexpr uint16_t kRobots = 4;
  ParticipantOrError pg = Participant::Create(domain, CycloneOptions{});
  ParticipantOrError pr = Participant::Create(domain, CycloneOptions{});
  ParticipantOrError pv = Participant::Create(domain, CycloneOptions{});
  ASSERT_TRUE(pg.ok() && pr.ok() && pv.ok());
  std::atomic<int64_t> round{0};
  Heard heard(kRobots), unused(kRobots);
  BeaconRadioOrError good = BeaconRadio::Create(*pg.participant, Options(1, kRobots, round), unused.Sink());
  BeaconRadioOrError victim = BeaconRadio::Create(*pv.participant, Options(0, kRobots, round), heard.Sink());
  ASSERT_TRUE(good.ok() && victim.ok());
  RogueWriter rogue(*pr.participant);
  ASSERT_TRUE(WaitFor([&] {
    dds_publication_matched_status_t status{};
    dds_get_publication_matched_status(rogue.writer(), &status);
    return good.radio->matched_readers() >= 1 && status.current_count >= 2;
  }));

  base::SplitMix64 random(5);
  auto rogue_write = [&](uint16_t sender, uint32_t r, std::vector<uint8_t> bytes) {
    const uint64_t before = victim.radio->counters().received;
    ASSERT_EQ(rogue.Write(sender, r, std::move(bytes)), DDS_RETCODE_OK);
    ASSERT_TRUE(WaitFor([&] { return victim.radio->counters().received == before + 1; }));
  };
  for (int64_t r = 10; r < 40; ++r) {
    round = r;
    const auto ur = static_cast<uint32_t>(r);
    // Garbage bytes of the right length, claiming robot 2.
    std::vector<uint8_t> garbage(wire::EncodedSize(kRobots));
    for (uint8_t& byte : garbage) byte = static_cast<uint8_t>(random.Next());
    garbage[0] = 0x7F;  // never the version
    rogue_write(2, ur, garbage);
    rogue_write(2, ur, std::vector<uint8_t>(100, 0x02));      // oversized for 4 robots
    rogue_write(3, ur, Encoded(2, kRobots));                   // wrong sender
    rogue_write(9, ur, Encoded(2, kRobots));                   // not in the swarm
    rogue_write(0, ur, Encoded(0, kRobots));                   // the victim itself
    rogue_write(2, ur - 5, Encoded(2, kRobots));               // an old round
    rogue_write(2, ur, Encoded(2, kRobots));                   // a forged but valid beacon of robot 2 ...
    rogue_write(2, ur, Encoded(2, kRobots));                   // ... replayed
    // A sequence beyond BEACON_MAX_BYTES: Cyclone's writer refuses it (a
    // writer of another stack would see it dropped when Cyclone's reader
    // checks incoming data against the type's bounds).
    EXPECT_EQ(rogue.Write(2, ur, std::vector<uint8_t>(2000, 0x02)), DDS_RETCODE_BAD_PARAMETER);
    const uint64_t before = heard.size();
    good.radio->Broadcast(BeaconOf(1));
    ASSERT_TRUE(WaitFor([&] { return heard.size() >= before + 1; })) << "round " << r;
  }
  const SampleCounters& counted = victim.radio->sample_counters();
  EXPECT_EQ(counted.count(SampleVerdict::kMalformed), 30u);
  EXPECT_EQ(counted.count(SampleVerdict::kOversized), 30u);
  EXPECT_EQ(counted.count(SampleVerdict::kSenderMismatch), 30u);
  EXPECT_EQ(counted.count(SampleVerdict::kSenderOutOfSwarm), 30u);
  EXPECT_EQ(counted.count(SampleVerdict::kFromSelf), 30u);
  EXPECT_EQ(counted.count(SampleVerdict::kRoundOutOfWindow), 30u);
  EXPECT_EQ(counted.count(SampleVerdict::kDuplicate), 30u);
  // Every good beacon of robot 1 arrived, and the forged ones of robot 2
  // (valid bytes: a receiver cannot tell them from robot 2's own) once per round.
  std::lock_guard<std::mutex> lock(heard.mutex);
  size_t from_good = 0;
  for (const auto& [sender, r, id] : heard.frames) {
    EXPECT_EQ(sender, id);
    from_good += sender == 1 ? 1 : 0;
  }
  EXPECT_EQ(from_good, 30u);
  EXPECT_EQ(heard.frames.size(), 60u);
}

}  // namespace
}  // namespace syrof::sim_dds
