#include "syrof/bridge/base_station.h"

#include <gtest/gtest.h>

#include <random>
#include <sstream>
#include <vector>

#include "bridge_test_support.h"
#include "syrof/bridge/replay_sink.h"
#include "syrof/bridge/summary.h"

namespace syrof::bridge {
namespace {

using namespace testing;
namespace drivers = firmware::drivers;
namespace replay = lab::replay;

// Three rounds of a swarm of 4: every robot's beacon each round, epoch 1
// then 2 from round 2 on, plus a Hello and a SendDone (ignored kinds).
struct CleanRun {
  std::vector<std::vector<uint8_t>> frames;  // each frame's wire bytes, in order
  std::vector<uint8_t> stream;               // all of them
};

CleanRun MakeCleanRun() {
  CleanRun run;
  uint8_t sequence = 0;
  for (uint16_t round = 0; round < 3; ++round) {
    for (uint16_t robot = 0; robot < kSwarm; ++robot) {
      const uint16_t epoch = round < 2 ? 1 : 2;
      const wire::Phase phase = round == 1 ? wire::Phase::kVote : wire::Phase::kProgress;
      run.frames.push_back(ReceivedFrame(EncodeBeacon(MakeBeacon(robot, epoch, phase)), sequence++));
    }
  }
  run.frames.insert(run.frames.begin() + 2, FrameBytes(drivers::MakeHello(sequence++)));
  run.frames.push_back(FrameBytes(drivers::MakeSendDone(sequence++, drivers::SendStatus::kSent)));
  for (const auto& frame : run.frames) Append(run.stream, frame);
  return run;
}

// What a station fed `chunks` made: the sink's calls and the output's.
struct Outcome {
  RecordingSink sink;
  RecordingOutput output;
  Rejections rejections;
  StationCounts counts;
};

void Feed(const std::vector<std::vector<uint8_t>>& chunks, Outcome& outcome) {
  StationConfig config;
  config.rounds_from_stream = true;
  BaseStation station(config, HeaderFor(kSwarm), {&outcome.sink}, {&outcome.output});
  for (const auto& chunk : chunks) station.Push(chunk);
  station.Finish(true);
  outcome.rejections = station.rejections();
  outcome.counts = station.counts();
}

TEST(BaseStationTest, ACleanStreamGivesOneRoundPerBeaconRoundAndAnEpochStartPerRobot) {
  const CleanRun run = MakeCleanRun();
  Outcome outcome;
  Feed({run.stream}, outcome);

  ASSERT_EQ(outcome.sink.headers.size(), 1u);
  ASSERT_EQ(outcome.sink.rounds.size(), 3u);
  EXPECT_EQ(outcome.sink.finishes, std::vector<bool>{true});
  EXPECT_EQ(outcome.output.beacons.size(), 12u);
  EXPECT_EQ(outcome.rejections.total(), 0u);
  EXPECT_EQ(outcome.counts.by_kind[static_cast<size_t>(drivers::FrameKind::kHello)], 1u);
  EXPECT_EQ(outcome.counts.by_kind[static_cast<size_t>(drivers::FrameKind::kSendDone)], 1u);
  const replay::Round& last = outcome.sink.rounds.back();
  EXPECT_EQ(last.time_ns, 3 * 50'000'000);
  ASSERT_EQ(last.robots.size(), kSwarm);
  for (const replay::RobotFrame& frame : last.robots) {
    EXPECT_EQ(frame.presence, replay::Presence::kRunning);
    EXPECT_EQ(frame.epoch, 2);
    EXPECT_FLOAT_EQ(frame.est_x_m, static_cast<float>(100 * frame.id + 2) / 1000.0f);
    EXPECT_EQ(frame.true_x_m, frame.est_x_m) << "no ground truth: the true pose repeats the estimate";
  }
  ASSERT_EQ(last.events.size(), kSwarm);
  for (const replay::Event& event : last.events) {
    EXPECT_EQ(event.kind, replay::EventKind::kEpochStart);
    EXPECT_EQ(event.epoch, 2);
    EXPECT_EQ(event.mode, 0);
  }
}

TEST(BaseStationTest, GoodFramesSplitAtEveryByteBoundaryGiveTheSameRecording) {
  const CleanRun run = MakeCleanRun();
  Outcome whole;
  Feed({run.stream}, whole);
  for (size_t split = 0; split <= run.stream.size(); ++split) {
    Outcome parts;
    Feed({std::vector<uint8_t>(run.stream.begin(), run.stream.begin() + split),
          std::vector<uint8_t>(run.stream.begin() + split, run.stream.end())},
         parts);
    ASSERT_EQ(parts.sink.rounds, whole.sink.rounds) << "split at byte " << split;
    ASSERT_EQ(parts.output.beacons, whole.output.beacons) << "split at byte " << split;
    ASSERT_EQ(parts.counts, whole.counts) << "split at byte " << split;
  }
  std::vector<std::vector<uint8_t>> bytes;
  for (uint8_t byte : run.stream) bytes.push_back({byte});
  Outcome one_at_a_time;
  Feed(bytes, one_at_a_time);
  EXPECT_EQ(one_at_a_time.sink.rounds, whole.sink.rounds);
  EXPECT_EQ(one_at_a_time.output.beacons, whole.output.beacons);
}

// The damage a garbage stream holds, each next to the reason it must be counted under.
std::vector<uint8_t> Damaged(const std::vector<uint8_t>& good_frame, std::mt19937& random, int which) {
  switch (which % 7) {
    case 0: {  // random bytes, some of them zero
      std::vector<uint8_t> bytes(1 + random() % 60);
      for (uint8_t& byte : bytes) byte = static_cast<uint8_t>(random() % 5 == 0 ? 0 : random());
      return bytes;
    }
    case 1:  // a frame cut short: no closing delimiter, the next frame's opening one ends it
      return std::vector<uint8_t>(good_frame.begin(), good_frame.begin() + 1 + random() % (good_frame.size() - 2));
    case 2: {  // a corrupted byte inside the body: the CRC (or the stuffing) refuses it
      std::vector<uint8_t> bytes = good_frame;
      uint8_t& byte = bytes[2 + random() % (bytes.size() - 4)];
      byte = static_cast<uint8_t>(byte ^ (1u << (random() % 8)));
      if (byte == 0) byte = 0x55;
      return bytes;
    }
    case 3: {  // a valid frame whose beacon is of another version
      std::vector<uint8_t> beacon = EncodeBeacon(MakeBeacon(1, 1));
      beacon[0] = 7;
      return ReceivedFrame(beacon);
    }
    case 4: {  // a valid frame whose beacon names robot 6 in a swarm of 4
      wire::Beacon beacon = MakeBeacon(0, 1);
      beacon.robot_id = 6;
      beacon.waiting = wire::MemberSet{};
      return ReceivedFrame(EncodeBeacon(beacon, 8));
    }
    case 5:  // a valid frame with 3 bytes where a beacon of a swarm of 4 has 1 (a swarm of 20's length)
      return ReceivedFrame(std::vector<uint8_t>(wire::EncodedSize(20), 0x03));
    default: {  // far too long: 80 non-zero bytes after a delimiter
      std::vector<uint8_t> bytes(80, 0x41);
      bytes[0] = 0;
      return bytes;
    }
  }
}

TEST(BaseStationTest, GarbageBetweenFramesChangesNothingButTheRejectionCounts) {
  const CleanRun run = MakeCleanRun();
  Outcome clean;
  Feed({run.stream}, clean);

  for (uint32_t seed = 1; seed <= 20; ++seed) {
    std::mt19937 random(seed);
    std::vector<uint8_t> dirty;
    int damage = static_cast<int>(seed);
    for (const auto& frame : run.frames) {
      for (int k = 0; k < 1 + static_cast<int>(random() % 3); ++k) Append(dirty, Damaged(frame, random, damage++));
      Append(dirty, frame);
    }
    Append(dirty, Damaged(run.frames[0], random, damage++));  // garbage at the end, too
    // Pushed in random pieces, as reads from a device return them.
    std::vector<std::vector<uint8_t>> chunks;
    for (size_t at = 0; at < dirty.size();) {
      const size_t length = std::min<size_t>(dirty.size() - at, 1 + random() % 50);
      chunks.emplace_back(dirty.begin() + at, dirty.begin() + at + length);
      at += length;
    }
    Outcome outcome;
    Feed(chunks, outcome);

    EXPECT_EQ(outcome.sink.rounds, clean.sink.rounds) << "seed " << seed;
    EXPECT_EQ(outcome.output.beacons, clean.output.beacons) << "seed " << seed;
    EXPECT_GT(outcome.rejections.total(), 0u) << "seed " << seed;
    StationCounts counts = outcome.counts;
    counts.bytes = clean.counts.bytes;
    // A damaged ReceivedBeacon frame is still a valid frame of its kind:
    // only its beacon is refused, and counted there.
    const uint64_t refused_beacons = [&] {
      uint64_t sum = 0;
      for (uint64_t count : outcome.rejections.beacons) sum += count;
      return sum;
    }();
    counts.frames -= refused_beacons;
    counts.by_kind[static_cast<size_t>(drivers::FrameKind::kReceivedBeacon)] -= refused_beacons;
    EXPECT_EQ(counts, clean.counts) << "seed " << seed;
  }
}

TEST(BaseStationTest, EachKindOfDamageIsCountedUnderItsReason) {
  Outcome outcome;
  std::vector<uint8_t> stream;
  std::vector<uint8_t> good = ReceivedFrame(EncodeBeacon(MakeBeacon(1, 1)));
  std::vector<uint8_t> bad_crc = good;
  bad_crc[bad_crc.size() - 2] ^= 0x10;  // the CRC's last byte
  if (bad_crc[bad_crc.size() - 2] == 0) bad_crc[bad_crc.size() - 2] = 0x42;
  Append(stream, bad_crc);
  std::vector<uint8_t> version = EncodeBeacon(MakeBeacon(1, 1));
  version[0] = 9;
  Append(stream, ReceivedFrame(version));
  wire::Beacon stranger = MakeBeacon(0, 1);
  stranger.robot_id = 7;
  stranger.waiting = wire::MemberSet{};
  Append(stream, ReceivedFrame(EncodeBeacon(stranger, 8)));
  std::vector<uint8_t> short_beacon = EncodeBeacon(MakeBeacon(1, 1));
  short_beacon.pop_back();
  Append(stream, ReceivedFrame(short_beacon));
  Append(stream, std::vector<uint8_t>(50, 0x41));  // too long (and discarded up to the next 0x00)
  Append(stream, {0x00, 0x03, 0x63, 0x01});        // two body bytes: too short (ends at the next 0x00)
  Append(stream, good);
  Feed({stream}, outcome);

  const auto frames = [&](drivers::LinkError error) { return outcome.rejections.frames[static_cast<size_t>(error)]; };
  const auto beacons = [&](wire::WireError error) { return outcome.rejections.beacons[static_cast<size_t>(error)]; };
  // A changed CRC byte is a CRC mismatch, or bad stuffing when it was a COBS code byte.
  EXPECT_EQ(frames(drivers::LinkError::kCrcMismatch) + frames(drivers::LinkError::kBadStuffing), 1u);
  EXPECT_EQ(frames(drivers::LinkError::kFrameTooShort), 1u);
  EXPECT_EQ(frames(drivers::LinkError::kFrameTooLong), 1u);
  EXPECT_EQ(beacons(wire::WireError::kWrongVersion), 1u);
  EXPECT_EQ(beacons(wire::WireError::kRobotIdOutOfRange), 1u);
  EXPECT_EQ(beacons(wire::WireError::kTruncated), 1u);
  EXPECT_EQ(outcome.rejections.total(), 6u);
  ASSERT_EQ(outcome.output.beacons.size(), 1u) << "the good frame after the damage still arrives";
  EXPECT_EQ(std::get<0>(outcome.output.beacons[0]), 1);
}

TEST(BaseStationTest, PresenceIsAbsentUntilHeardRunningWhileRecentAndCrashedWhenSilent) {
  RecordingSink sink;
  StationConfig config;
  config.silent_rounds = 2;
  BaseStation station(config, HeaderFor(2), {&sink}, {});
  wire::Beacon heard = MakeBeacon(0, 1);
  heard.waiting = wire::MemberSet{};  // a swarm of 2
  const std::vector<uint8_t> beacon = ReceivedFrame(EncodeBeacon(heard, 2));
  ASSERT_FALSE(beacon.empty());
  station.Push(beacon);
  for (int round = 0; round < 4; ++round) station.EndRound((round + 1) * 50'000'000);
  station.Push(beacon);
  station.EndRound(5 * 50'000'000);

  ASSERT_EQ(sink.rounds.size(), 5u);
  const auto presence = [&](size_t round, size_t robot) { return sink.rounds[round].robots[robot].presence; };
  EXPECT_EQ(presence(0, 1), replay::Presence::kAbsent);
  EXPECT_EQ(presence(0, 0), replay::Presence::kRunning);
  EXPECT_EQ(presence(2, 0), replay::Presence::kRunning) << "silent 2 rounds: still running";
  EXPECT_EQ(presence(3, 0), replay::Presence::kCrashed) << "silent 3 rounds";
  EXPECT_EQ(presence(4, 0), replay::Presence::kRunning) << "heard again";
}

TEST(BaseStationTest, AVoteViewThatLosesARobotIsAMemberRemovedEvent) {
  RecordingSink sink;
  BaseStation station(StationConfig{}, HeaderFor(kSwarm), {&sink}, {});
  wire::Beacon vote = MakeBeacon(0, 3, wire::Phase::kVote);
  station.Push(ReceivedFrame(EncodeBeacon(vote)));
  station.EndRound(50'000'000);
  vote.waiting.reset(2);
  vote.mode = wire::Mode::kAutonomous;
  station.Push(ReceivedFrame(EncodeBeacon(vote)));
  station.EndRound(100'000'000);

  ASSERT_EQ(sink.rounds.size(), 2u);
  EXPECT_TRUE(sink.rounds[0].events.empty());
  ASSERT_EQ(sink.rounds[1].events.size(), 1u);
  const replay::Event& event = sink.rounds[1].events[0];
  EXPECT_EQ(event.kind, replay::EventKind::kMemberRemoved);
  EXPECT_EQ(event.robot, 0);
  EXPECT_EQ(event.other, 2);
  EXPECT_EQ(event.epoch, 3);
  EXPECT_EQ(event.time_ns, 100'000'000);
  // The AUTONOMOUS vote is for the next epoch; the robot's epoch stays COOPERATIVE.
  EXPECT_EQ(sink.rounds[1].robots[0].mode, static_cast<uint8_t>(wire::Mode::kCooperative));
  EXPECT_EQ(event.mode, static_cast<uint8_t>(wire::Mode::kCooperative));
}

TEST(BaseStationTest, APresenceOnlyBeaconMovesTheRobotAndMarksItJoiningWithoutAnEpoch) {
  RecordingSink sink;
  BaseStation station(StationConfig{}, HeaderFor(kSwarm), {&sink}, {});
  wire::Beacon joiner;
  joiner.robot_id = 3;
  joiner.presence_only = true;
  joiner.snapshot.x_mm = 1500;
  station.Push(ReceivedFrame(EncodeBeacon(joiner)));
  station.EndRound(50'000'000);
  ASSERT_EQ(sink.rounds.size(), 1u);
  const replay::RobotFrame& frame = sink.rounds[0].robots[3];
  EXPECT_EQ(frame.presence, replay::Presence::kRunning);
  EXPECT_EQ(frame.status, 1);
  EXPECT_FLOAT_EQ(frame.est_x_m, 1.5f);
  EXPECT_TRUE(sink.rounds[0].events.empty());
}

TEST(BaseStationTest, TheReplayItWritesReadsBackWithEveryRobotsEpochs) {
  const CleanRun run = MakeCleanRun();
  std::stringstream file;
  ReplaySink replay_sink(file);
  StationConfig config;
  config.rounds_from_stream = true;
  {
    BaseStation station(config, HeaderFor(kSwarm), {&replay_sink}, {});
    station.Push(run.stream);
    station.Finish(true);
  }
  ASSERT_TRUE(replay_sink.ok()) << replay_sink.error().ToString();
  const ReplayFacts facts = ReadReplayFacts(file);
  ASSERT_TRUE(facts.read) << facts.error->ToString();
  EXPECT_FALSE(facts.error);
  EXPECT_EQ(facts.rounds, 3u);
  ASSERT_EQ(facts.robots.size(), kSwarm);
  for (const RobotReplayFacts& robot : facts.robots) {
    EXPECT_TRUE(robot.seen);
    EXPECT_EQ(robot.first_epoch, 1);
    EXPECT_EQ(robot.last_epoch, 2);
    EXPECT_EQ(robot.epoch_starts, 1u);
    EXPECT_EQ(robot.cooperative_starts, 1u);
  }
}

TEST(BaseStationTest, TheSummaryNamesEveryReasonAndEachRobotsHeardSet) {
  BaseStation station(StationConfig{}, HeaderFor(kSwarm), {}, {});
  wire::Beacon one_way = MakeBeacon(1, 4);
  one_way.waiting = wire::MemberSet{};
  one_way.waiting.set(0);
  one_way.waiting.set(1);
  station.Push(ReceivedFrame(EncodeBeacon(one_way)));
  std::vector<uint8_t> version = EncodeBeacon(MakeBeacon(2, 4));
  version[0] = 1;
  station.Push(ReceivedFrame(version));
  station.EndRound(50'000'000);
  station.Finish(true);
  BridgeRunInfo run;
  run.input = "file test";
  run.end = "end of input";

  const std::string json = SummaryJson(station, run, std::nullopt);
  EXPECT_NE(json.find("\"WrongVersion\": 1"), std::string::npos) << json;
  EXPECT_NE(json.find("\"CrcMismatch\": 0"), std::string::npos);
  EXPECT_NE(json.find("\"hears\": [\n        0,\n        1\n      ]"), std::string::npos) << json;
  const std::string text = SummaryText(station, run);
  EXPECT_NE(text.find("robot 1     1 beacons"), std::string::npos) << text;
  EXPECT_NE(text.find("hears {0,1}"), std::string::npos) << text;
  EXPECT_NE(text.find("rejected    beacon WrongVersion: 1"), std::string::npos) << text;
  EXPECT_NE(text.find("robot 3     never heard"), std::string::npos) << text;
}

}  // namespace
}  // namespace syrof::bridge
