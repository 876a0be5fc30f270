// BeaconRadioOptions::hold_ns (the stress's late beacons, lab/sim/stress.h):
// a held sample arrives later, as a late network delivers it, and goes
// through the sample checks then: a newer beacon of its sender that overtook
// it makes it a duplicate, a round that moved on puts it out of the window,
// and otherwise it is delivered. The holds are long (1.5 s) so that the
// order of events, not a duration, is what the tests look at.
#include <gtest/gtest.h>

#include <atomic>
#include <chrono>
#include <mutex>
#include <thread>
#include <vector>

#include "syrof/sim_dds/beacon_radio.h"
#include "syrof/wire/beacon_codec.h"
#include "test_domain.h"

namespace syrof::sim_dds {
namespace {

constexpr int64_t kLongHoldNs = 1'500'000'000;

// Waits (polling) until `done` holds; false after 10 s (it only bounds how
// long a broken test hangs).
template <typename Predicate>
bool WaitUntil(Predicate done) {
  const auto deadline = std::chrono::steady_clock::now() + std::chrono::seconds(10);
  while (!done()) {
    if (std::chrono::steady_clock::now() > deadline) return false;
    std::this_thread::sleep_for(std::chrono::milliseconds(1));
  }
  return true;
}

// The rounds of the frames a sink was handed, in order.
struct Rounds {
  std::mutex mutex;
  std::vector<uint32_t> rounds;
  BeaconSink Sink() {
    return [this](std::span<const uint8_t>, uint16_t, uint32_t round) {
      std::lock_guard<std::mutex> lock(mutex);
      rounds.push_back(round);
    };
  }
  std::vector<uint32_t> Get() {
    std::lock_guard<std::mutex> lock(mutex);
    return rounds;
  }
};

struct LatePair {
  std::unique_ptr<Participant> sender_participant, receiver_participant;
  std::unique_ptr<BeaconRadio> sender, receiver;
};

// Robot 0 sends; robot 1 holds robot 0's beacon of `held_round` for
// kLongHoldNs and takes every other one at once.
LatePair MakePair(std::atomic<int64_t>& round, Rounds& heard, uint32_t held_round) {
  LatePair pair;
  const uint32_t domain = testing::FreshDomainId();
  ParticipantOrError a = Participant::Create(domain, CycloneOptions{});
  ParticipantOrError b = Participant::Create(domain, CycloneOptions{});
  EXPECT_TRUE(a.ok() && b.ok());
  if (!a.ok() || !b.ok()) return pair;
  pair.sender_participant = std::move(a.participant);
  pair.receiver_participant = std::move(b.participant);
  BeaconRadioOptions options;
  options.swarm_size = 2;
  options.seed = 3;
  options.current_round = [&round] { return round.load(); };
  options.self = 0;
  BeaconRadioOrError sender = BeaconRadio::Create(*pair.sender_participant, options);
  options.self = 1;
  options.hold_ns = [held_round](uint16_t from, uint32_t r) { return from == 0 && r == held_round ? kLongHoldNs : 0; };
  BeaconRadioOrError receiver = BeaconRadio::Create(*pair.receiver_participant, options, heard.Sink());
  EXPECT_TRUE(sender.ok() && receiver.ok());
  if (!sender.ok() || !receiver.ok()) return pair;
  pair.sender = std::move(sender.radio);
  pair.receiver = std::move(receiver.radio);
  EXPECT_TRUE(WaitUntil([&] { return pair.sender->matched_readers() >= 1; }));
  return pair;
}

wire::Beacon BeaconOfRobot0() {
  wire::Beacon beacon;
  beacon.robot_id = 0;
  beacon.epoch = 1;
  return beacon;
}

TEST(LateBeacon, AHeldBeaconOvertakenByItsSendersNextIsADuplicateWhenItArrives) {
  std::atomic<int64_t> round{0};
  Rounds heard;
  LatePair pair = MakePair(round, heard, 1);
  ASSERT_NE(pair.receiver, nullptr);
  for (int64_t r = 0; r < 3; ++r) {
    round = r;
    pair.sender->Broadcast(BeaconOfRobot0());
    if (r == 1) continue;  // held
    ASSERT_TRUE(WaitUntil([&] { return heard.Get().size() == (r == 0 ? 1u : 2u); })) << "round " << r;
  }
  // Round 1's beacon arrives after round 2's: the checks refuse it then.
  ASSERT_TRUE(WaitUntil([&] { return pair.receiver->sample_counters().count(SampleVerdict::kDuplicate) == 1; }));
  EXPECT_EQ(heard.Get(), (std::vector<uint32_t>{0, 2}));
  EXPECT_EQ(pair.receiver->counters().received, 3u);
  EXPECT_EQ(pair.receiver->counters().held, 1u);
  EXPECT_EQ(pair.receiver->counters().delivered, 2u);
}

TEST(LateBeacon, AHeldBeaconIsJudgedByTheRoundInWhichItArrives) {
  std::atomic<int64_t> round{1};
  Rounds heard;
  LatePair pair = MakePair(round, heard, 1);
  ASSERT_NE(pair.receiver, nullptr);
  pair.sender->Broadcast(BeaconOfRobot0());
  ASSERT_TRUE(WaitUntil([&] { return pair.receiver->counters().held == 1; }));
  round = 1 + 10 * kRoundWindow;  // the receiver moved on while the beacon was on its way
  ASSERT_TRUE(WaitUntil([&] { return pair.receiver->sample_counters().count(SampleVerdict::kRoundOutOfWindow) == 1; }));
  EXPECT_TRUE(heard.Get().empty());
  EXPECT_EQ(pair.receiver->counters().delivered, 0u);
}

TEST(LateBeacon, AHeldBeaconNothingOvertookIsDeliveredLate) {
  std::atomic<int64_t> round{1};
  Rounds heard;
  LatePair pair = MakePair(round, heard, 1);
  ASSERT_NE(pair.receiver, nullptr);
  pair.sender->Broadcast(BeaconOfRobot0());
  ASSERT_TRUE(WaitUntil([&] { return pair.receiver->counters().held == 1; }));
  EXPECT_TRUE(heard.Get().empty());  // held: not yet arrived
  ASSERT_TRUE(WaitUntil([&] { return heard.Get().size() == 1; }));
  EXPECT_EQ(heard.Get(), (std::vector<uint32_t>{1}));
  EXPECT_EQ(pair.receiver->counters().delivered, 1u);
}

}  // namespace
}  // namespace syrof::sim_dds
