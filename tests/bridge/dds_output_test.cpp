#include "syrof/bridge/dds_output.h"

#include <gtest/gtest.h>
#include <unistd.h>

#include <chrono>
#include <functional>
#include <mutex>
#include <string>
#include <thread>
#include <tuple>
#include <vector>

#include "bridge_test_support.h"
#include "syrof/sim_dds/beacon_radio.h"
#include "syrof/sim_dds/participant.h"

namespace syrof::bridge {
namespace {

using namespace testing;

// A domain of this test and process alone (tests/sim_dds/test_domain.h's rule).
uint32_t FreshDomainId() {
  const ::testing::TestInfo* test = ::testing::UnitTest::GetInstance()->current_test_info();
  const std::string name = std::string(test->test_suite_name()) + "." + test->name();
  return sim_dds::DomainIdForRun(std::hash<std::string>{}(name) ^ (static_cast<uint64_t>(getpid()) << 32));
}

// Bounds how long a broken test waits; not a timing assertion.
template <typename Predicate>
bool WaitFor(Predicate done) {
  const auto deadline = std::chrono::steady_clock::now() + std::chrono::seconds(10);
  while (!done()) {
    if (std::chrono::steady_clock::now() > deadline) return false;
    std::this_thread::sleep_for(std::chrono::milliseconds(2));
  }
  return true;
}

TEST(DdsBeaconOutputTest, ARobotsDdsRadioReceivesTheBeaconsTheBridgePublished) {
  const uint32_t domain = FreshDomainId();
  DdsOutputOrError output = DdsBeaconOutput::Create(domain, "lo");
  ASSERT_TRUE(output.ok()) << output.error->ToString();

  // sim_dds's own reader: robot 3's BeaconRadio, which checks every sample
  // (size, sender, decode, duplicates) before its sink sees it.
  sim_dds::ParticipantOrError reader_participant = sim_dds::Participant::Create(domain, sim_dds::CycloneOptions{});
  ASSERT_TRUE(reader_participant.ok()) << reader_participant.error->ToString();
  std::mutex mutex;
  std::vector<std::tuple<uint16_t, uint32_t, std::vector<uint8_t>>> heard;
  sim_dds::BeaconRadioOptions options;
  options.self = 3;
  options.swarm_size = kSwarm;
  options.current_round = [] { return int64_t{-1}; };  // not started: no round window
  sim_dds::BeaconRadioOrError radio = sim_dds::BeaconRadio::Create(
      *reader_participant.participant, options, [&](std::span<const uint8_t> wire, uint16_t sender, uint32_t round) {
        std::lock_guard<std::mutex> lock(mutex);
        heard.emplace_back(sender, round, std::vector<uint8_t>(wire.begin(), wire.end()));
      });
  ASSERT_TRUE(radio.ok()) << radio.error->ToString();
  ASSERT_TRUE(WaitFor([&] { return output.output->matched_readers() >= 1; }));

  RecordingOutput published;
  BaseStation station(StationConfig{}, HeaderFor(kSwarm), {}, {output.output.get(), &published});
  std::vector<uint8_t> stream;
  for (uint16_t robot = 0; robot < 3; ++robot) Append(stream, ReceivedFrame(EncodeBeacon(MakeBeacon(robot, 5))));
  Append(stream, {0x00, 0x17, 0x42, 0x00});  // garbage: counted, not published
  station.EndRound(50'000'000);
  station.EndRound(100'000'000);
  station.Push(stream);

  ASSERT_TRUE(WaitFor([&] {
    std::lock_guard<std::mutex> lock(mutex);
    return heard.size() >= 3;
  }));
  std::lock_guard<std::mutex> lock(mutex);
  ASSERT_EQ(heard.size(), 3u);
  ASSERT_EQ(published.beacons.size(), 3u);
  for (size_t i = 0; i < heard.size(); ++i) {
    const auto& [sender, round, wire] = heard[i];
    EXPECT_EQ(sender, std::get<0>(published.beacons[i]));
    EXPECT_EQ(round, 2u) << "stamped with the station's round";
    EXPECT_EQ(wire, std::get<1>(published.beacons[i])) << "the bytes as heard";
  }
  EXPECT_EQ(output.output->published(), 3u);
  EXPECT_EQ(output.output->failed(), 0u);
  EXPECT_EQ(radio.radio->sample_counters().rejected(), 0u);
  EXPECT_GT(station.rejections().total(), 0u);
}

}  // namespace
}  // namespace syrof::bridge
