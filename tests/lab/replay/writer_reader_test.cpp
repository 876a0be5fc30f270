// Round trip, determinism and the pinned byte layout of lab/replay.
#include <gtest/gtest.h>

#include <algorithm>
#include <array>
#include <bit>
#include <cmath>
#include <limits>
#include <sstream>
#include <string>
#include <vector>

#include "replay_test_support.h"
#include "syrof/lab/replay/format.h"
#include "syrof/lab/replay/reader.h"
#include "syrof/lab/replay/writer.h"

namespace syrof::lab::replay {
namespace {

using testing::Read;
using testing::SampleHeader;
using testing::SampleRounds;
using testing::Write;
using testing::WriteSample;

TEST(ReplayWriterReader, RoundTripGivesEqualHeaderAndRounds) {
  const Header header = SampleHeader();
  const std::vector<Round> rounds = SampleRounds();

  const testing::ReadBack back = Read(Write(header, rounds).bytes);

  ASSERT_TRUE(back.header_ok) << back.error;
  EXPECT_EQ(back.header, header);
  EXPECT_EQ(back.rounds, rounds);
  EXPECT_TRUE(back.complete) << back.error;
  EXPECT_EQ(back.error, "");
}

TEST(ReplayWriterReader, FloatsComeBackBitForBit) {
  const Header header = SampleHeader();
  std::vector<Round> rounds(2);
  rounds[0].index = 0;
  rounds[0].robots = {RobotFrame{.id = 0}};
  rounds[0].robots[0].true_x_m = -0.0f;  // differs from the all-zero baseline only in its bits
  rounds[0].robots[0].est_x_m = std::numeric_limits<float>::quiet_NaN();
  rounds[0].robots[0].est_y_m = std::numeric_limits<float>::infinity();
  rounds[0].robots[0].true_heading_rad = std::numeric_limits<float>::denorm_min();
  rounds[1] = rounds[0];
  rounds[1].index = 1;
  rounds[1].robots[0].true_x_m = 0.0f;

  const testing::ReadBack back = Read(Write(header, rounds).bytes);

  ASSERT_EQ(back.rounds.size(), 2u) << back.error;
  for (size_t index = 0; index < 2; ++index) {
    const RobotFrame& want = rounds[index].robots[0];
    const RobotFrame& got = back.rounds[index].robots[0];
    EXPECT_EQ(std::bit_cast<uint32_t>(got.true_x_m), std::bit_cast<uint32_t>(want.true_x_m));
    EXPECT_EQ(std::bit_cast<uint32_t>(got.est_x_m), std::bit_cast<uint32_t>(want.est_x_m));
    EXPECT_EQ(std::bit_cast<uint32_t>(got.est_y_m), std::bit_cast<uint32_t>(want.est_y_m));
    EXPECT_EQ(std::bit_cast<uint32_t>(got.true_heading_rad), std::bit_cast<uint32_t>(want.true_heading_rad));
  }
}

TEST(ReplayWriterReader, SameCallsGiveSameBytes) {
  const std::string first = WriteSample().bytes;
  const std::string second = WriteSample().bytes;

  EXPECT_EQ(first, second);
  EXPECT_GT(first.size(), 100u);
}

TEST(ReplayWriterReader, UnchangedRobotCostsFourBytes) {
  const Header header = SampleHeader();
  std::vector<Round> rounds = SampleRounds();
  rounds.resize(1);
  Round repeat = rounds[0];
  repeat.index = 1;
  repeat.events.clear();
  rounds.push_back(repeat);

  const testing::Written written = Write(header, rounds);

  // Three robots, nothing changed: tag, index, time, two counts, 3 x 4, crc.
  EXPECT_EQ(written.round_ends[1] - written.round_ends[0], format::kRoundFixedBytes + 3 * 4 + 4);
  EXPECT_EQ(Read(written.bytes).rounds, rounds);
}

// Version 2, written out by hand from docs/replay.md; the CRCs come from
// zlib.crc32. Any change to the layout shows up here: bump kFormatVersion,
// update docs/replay.md, then this.
const std::vector<uint8_t> kGoldenFile = {
    // header
    'S', 'Y', 'R', 'O', 'F', 'R', 'P', 'L',          // magic
    0x02, 0x00,                                      // version 2
    0x08, 0x07, 0x06, 0x05, 0x04, 0x03, 0x02, 0x01,  // seed 0x0102030405060708
    0x80, 0xF0, 0xFA, 0x02, 0x00, 0x00, 0x00, 0x00,  // radio_round_ns 50000000
    0x00, 0x00, 0x80, 0x40,                          // arena_width_m 4.0
    0x00, 0x00, 0x20, 0x40,                          // arena_height_m 2.5
    0x02, 0x00, 'a', 'b',                            // scenario_name "ab"
    0x01, 0x00, 'c',                                 // app_name "c"
    0x01, 0x00, 0x00, 0x00,                          // robot count 1
    0x07, 0x00, 0x01, 0x00, 0x00, 0x00, 0x3E,        // robot 7, rover, radius 0.125
    0x05, 0xE8, 0xE3, 0xFC,                          // crc
    // round
    'R',                                             // tag
    0x03, 0x00, 0x00, 0x00,                          // index 3
    0x80, 0xD1, 0xF0, 0x08, 0x00, 0x00, 0x00, 0x00,  // time_ns 150000000
    0x01, 0x00, 0x00, 0x00,                          // frame count 1
    0x01, 0x00, 0x00, 0x00,                          // event count 1
    0x07, 0x00,                                      // frame: robot 7
    0x35,                                            // running, joining, VOTE, AUTONOMOUS
    0x1B,                                            // changed: epoch, true_x, true_heading, est_x
    0x02, 0x01,                                      // epoch 0x0102
    0x00, 0x00, 0x80, 0x3F,                          // true_x_m 1.0
    0x00, 0x00, 0x00, 0xBF,                          // true_heading_rad -0.5
    0x00, 0x00, 0x80, 0x3F,                          // est_x_m 1.0
    0x00,                                            // event: EPOCH_START
    0x07, 0x00, 0xFF, 0xFF,                          // robot 7, other none
    0x02, 0x01, 0x01,                                // epoch 0x0102, AUTONOMOUS
    0x80, 0xD1, 0xF0, 0x08, 0x00, 0x00, 0x00, 0x00,  // time_ns 150000000
    0xA0, 0x86, 0x17, 0xA0,                          // crc
    // end marker
    'E',                                             // tag
    0x01, 0x00, 0x00, 0x00,                          // 1 round
    0x01, 0x00, 0x00, 0x00, 0x00, 0x00, 0x00, 0x00,  // 1 event
    0x01, 0x00, 0x00, 0x00, 0x00, 0x00, 0x00, 0x00,  // 1 frame
    0x16, 0xA5, 0x63, 0x3F,                          // crc
};

TEST(ReplayWriterReader, LayoutMatchesTheGoldenFile) {
  Header header;
  header.seed = 0x0102030405060708;
  header.radio_round_ns = 50'000'000;
  header.arena_width_m = 4.0f;
  header.arena_height_m = 2.5f;
  header.scenario_name = "ab";
  header.app_name = "c";
  header.robots = {{7, 1, 0.125f}};
  RobotFrame frame{.id = 7, .presence = Presence::kRunning, .status = 1, .phase = 2, .mode = 1, .epoch = 0x0102};
  frame.true_x_m = 1.0f;
  frame.true_heading_rad = -0.5f;
  frame.est_x_m = 1.0f;
  const Event event{EventKind::kEpochStart, 7, kNoRobot, 0x0102, 1, 150'000'000};
  std::ostringstream out;

  Writer writer(out, header);
  writer.WriteRound(3, 150'000'000, {&frame, 1}, {&event, 1});
  writer.Finish();

  ASSERT_TRUE(writer.ok()) << writer.error();
  const std::string bytes = out.str();
  EXPECT_EQ(std::vector<uint8_t>(bytes.begin(), bytes.end()), kGoldenFile);
  const testing::ReadBack back = Read(std::string(kGoldenFile.begin(), kGoldenFile.end()));
  EXPECT_TRUE(back.complete) << back.error;
  ASSERT_EQ(back.rounds.size(), 1u);
  EXPECT_EQ(back.rounds[0].robots[0], frame);
}

// The same file as version 1 wrote it: only the version and the header's
// CRC differ (version 2 only added event kinds).
std::vector<uint8_t> GoldenFileVersion1() {
  std::vector<uint8_t> bytes = kGoldenFile;
  bytes[8] = 0x01;
  const std::array<uint8_t, 4> crc = {0xA3, 0xA0, 0x9B, 0x82};
  std::copy(crc.begin(), crc.end(), bytes.begin() + 52);  // the header crc
  return bytes;
}

TEST(ReplayReader, ReadsAVersion1File) {
  const std::vector<uint8_t> bytes = GoldenFileVersion1();
  std::istringstream in(std::string(bytes.begin(), bytes.end()));
  Reader reader(in);
  Header header;
  Round round;

  ASSERT_TRUE(reader.ReadHeader(header)) << reader.error();
  EXPECT_EQ(reader.version(), 1);
  ASSERT_TRUE(reader.Next(round)) << reader.error();
  EXPECT_EQ(round.events[0].kind, EventKind::kEpochStart);
  EXPECT_FALSE(reader.Next(round));
  EXPECT_TRUE(reader.complete()) << reader.error();
}

TEST(ReplayWriterReader, AppEventsOfVersion2ReadBack) {
  const Header header = SampleHeader();
  std::vector<Round> rounds = SampleRounds();
  rounds[0].events = {Event{EventKind::kAppFault, 1, kNoRobot, 3, 0, 10},
                      Event{EventKind::kInvalidCommand, 2, kNoRobot, 4, 1, 20},
                      Event{EventKind::kPayloadRefused, 0, kNoRobot, 5, 0, 30}};

  const testing::ReadBack back = Read(Write(header, rounds).bytes);

  EXPECT_TRUE(back.complete) << back.error;
  EXPECT_EQ(back.rounds, rounds);
}

TEST(ReplayFormat, Crc32MatchesTheStandardCheckValue) {
  const std::string text = "123456789";
  const auto* bytes = reinterpret_cast<const uint8_t*>(text.data());

  EXPECT_EQ(format::Crc32({bytes, text.size()}), 0xCBF43926u);
  EXPECT_EQ(format::Crc32({bytes + 4, 5}, format::Crc32({bytes, 4})), 0xCBF43926u);
}

TEST(ReplayWriter, RefusesHeaderItCannotRecord) {
  std::vector<Header> bad(6, SampleHeader());
  bad[0].scenario_name.assign(kMaxNameBytes + 1, 'x');
  bad[1].app_name = "a\x1b[2Jb";
  bad[2].radio_round_ns = 0;
  bad[3].arena_width_m = std::numeric_limits<float>::infinity();
  bad[4].robots[1].id = 0;  // not increasing
  bad[5].robots[2].id = kNoRobot;

  for (const Header& header : bad) {
    std::ostringstream out;
    Writer writer(out, header);
    writer.WriteRound(0, 0, {}, {});
    writer.Finish();
    EXPECT_FALSE(writer.ok());
    EXPECT_NE(writer.error().ToString().find("header: "), std::string::npos) << writer.error();
    EXPECT_EQ(out.str(), "");
  }
}

TEST(ReplayWriter, RefusesRoundItCannotRecordAndWritesNoMore) {
  struct Case {
    std::vector<RobotFrame> robots;
    std::vector<Event> events;
    uint32_t index;
    const char* expected;
  };
  const std::vector<Case> cases = {
      {{RobotFrame{.id = 5}}, {}, 1, "not in the header"},
      {{RobotFrame{.id = 1}, RobotFrame{.id = 0}}, {}, 1, "increasing id order"},
      {{RobotFrame{.id = 0, .phase = 3}}, {}, 1, "phase 3"},
      {{RobotFrame{.id = 0, .status = 2}}, {}, 1, "status 2"},
      {{RobotFrame{.id = 0, .mode = 2}}, {}, 1, "mode 2"},
      {{RobotFrame{.id = 0, .presence = static_cast<Presence>(4)}}, {}, 1, "presence 4"},
      {{}, {Event{.kind = static_cast<EventKind>(17)}}, 1, "unknown event kind 17"},
      {{}, {Event{.kind = EventKind::kCollision, .robot = 0, .other = 9}}, 1, "other 9"},
      {{}, {}, 0, "round index 0 does not follow round 0"},
  };
  for (const Case& bad : cases) {
    std::ostringstream out;
    Writer writer(out, SampleHeader());
    writer.WriteRound(0, 0, {}, {});
    const size_t good_bytes = out.str().size();

    writer.WriteRound(bad.index, 10, bad.robots, bad.events);
    writer.WriteRound(7, 20, {}, {});
    writer.Finish();

    EXPECT_FALSE(writer.ok());
    EXPECT_NE(writer.error().ToString().find(bad.expected), std::string::npos) << writer.error();
    EXPECT_EQ(out.str().size(), good_bytes);
    EXPECT_TRUE(Read(out.str()).truncated);
  }
}

TEST(ReplayWriter, ReportsAFailingStream) {
  std::ostringstream out;
  out.setstate(std::ios::badbit);

  Writer writer(out, SampleHeader());

  EXPECT_FALSE(writer.ok());
  EXPECT_NE(writer.error().ToString().find("failed"), std::string::npos) << writer.error();
}

TEST(ReplayNames, EveryEnumeratorHasAName) {
  EXPECT_STREQ(ToString(EventKind::kEpochStart), "EPOCH_START");
  EXPECT_STREQ(ToString(EventKind::kPartitionEnd), "PARTITION_END");
  for (unsigned kind = 0; kind <= static_cast<unsigned>(kLastEventKind); ++kind) {
    EXPECT_STRNE(ToString(static_cast<EventKind>(kind)), "?") << kind;
  }
  EXPECT_STREQ(ToString(EventKind::kAppFault), "APP_FAULT");
  EXPECT_STREQ(ToString(EventKind::kInvalidCommand), "INVALID_COMMAND");
  EXPECT_STREQ(ToString(EventKind::kPayloadRefused), "PAYLOAD_REFUSED");
  EXPECT_STREQ(ToString(static_cast<EventKind>(17)), "?");
  EXPECT_STREQ(ToString(Presence::kAbsent), "ABSENT");
  EXPECT_STREQ(ToString(Presence::kRunning), "RUNNING");
  EXPECT_STREQ(ToString(Presence::kPaused), "PAUSED");
  EXPECT_STREQ(ToString(Presence::kCrashed), "CRASHED");
  EXPECT_STREQ(ToString(static_cast<Presence>(4)), "?");
}

}  // namespace
}  // namespace syrof::lab::replay
