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
  repeat.maps.clear();
  rounds.push_back(repeat);

  const testing::Written written = Write(header, rounds);

  // Three robots, nothing changed: tag, index, time, three counts, 3 x 4, crc.
  EXPECT_EQ(written.round_ends[1] - written.round_ends[0], format::kRoundFixedBytes + 3 * 4 + 4);
  EXPECT_EQ(Read(written.bytes).rounds, rounds);
}

// Version 5, written out by hand from docs/replay.md; the CRCs come from
// zlib.crc32. Any change to the layout shows up here: bump kFormatVersion,
// update docs/replay.md, then this.
const std::vector<uint8_t> kGoldenFile = {
    // header
    'S', 'Y', 'R', 'O', 'F', 'R', 'P', 'L',          // magic
    0x05, 0x00,                                      // version 5
    0x08, 0x07, 0x06, 0x05, 0x04, 0x03, 0x02, 0x01,  // seed 0x0102030405060708
    0x80, 0xF0, 0xFA, 0x02, 0x00, 0x00, 0x00, 0x00,  // radio_round_ns 50000000
    0x00, 0x00, 0x80, 0x40,                          // arena_width_m 4.0
    0x00, 0x00, 0x20, 0x40,                          // arena_height_m 2.5
    0x02, 0x00, 'a', 'b',                            // scenario_name "ab"
    0x01, 0x00, 'c',                                 // app_name "c"
    0x01, 0x00, 0x00, 0x00,                          // robot count 1
    0x07, 0x00, 0x01, 0x00, 0x00, 0x00, 0x3E,        // robot 7, rover, radius 0.125
    0x01, 0x00,                                      // anchor count 1
    0x00, 0x00, 0x00, 0x3F, 0x00, 0x00, 0x00, 0x40,  // anchor (0.5, 2.0)
    0x01,                                            // robot 7: 1 input
    0x06, 0x00, 'c', 'h', 'a', 'r', 'g', 'e',        // name "charge"
    0x00, 0x00, 0x00, 0x00, 0x00, 0x30, 0x8B, 0x40,  // value 870.0
    0x02, 0x01,                                      // message: fields, 1 field
    0x06, 0x00, 'c', 'h', 'a', 'r', 'g', 'e',        // name "charge"
    0x02,                                            // type u16be
    0xBA, 0xCE, 0x7B, 0x1C,                          // crc
    // round
    'R',                                             // tag
    0x03, 0x00, 0x00, 0x00,                          // index 3
    0x80, 0xD1, 0xF0, 0x08, 0x00, 0x00, 0x00, 0x00,  // time_ns 150000000
    0x01, 0x00, 0x00, 0x00,                          // frame count 1
    0x02, 0x00, 0x00, 0x00,                          // event count 2
    0x01, 0x00, 0x00, 0x00,                          // map count 1
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
    0xFF, 0xFF,                                      // partition none
    0x0A,                                            // event: PARTITION_START
    0xFF, 0xFF, 0xFF, 0xFF,                          // robot none, other none
    0x00, 0x00, 0x00,                                // epoch 0, mode 0
    0x00, 0x3B, 0x58, 0x08, 0x00, 0x00, 0x00, 0x00,  // time_ns 140000000
    0x05, 0x00,                                      // partition 5
    0x07, 0x00, 0xFF, 0xFF,                          // map: robot 7, same_as none (the map follows)
    0x02, 0x01, 0x01,                                // epoch 0x0102, AUTONOMOUS
    0x01, 0x00,                                      // member count 1
    0x07, 0x00, 0x02,                                // member 7, VOTE
    0xE8, 0x03, 0xFF, 0xFF, 0xF4, 0x01,              // x_mm 1000, y_mm -1, heading_mrad 500
    0x00, 0x00, 0x00, 0x00,                          // vx_mm_s 0, vy_mm_s 0
    0x02, 0xAB, 0xCD,                                // payload of 2 bytes
    0x8F, 0xA4, 0x40, 0xD3,                          // crc
    // end marker
    'E',                                             // tag
    0x01, 0x00, 0x00, 0x00,                          // 1 round
    0x02, 0x00, 0x00, 0x00, 0x00, 0x00, 0x00, 0x00,  // 2 events
    0x01, 0x00, 0x00, 0x00, 0x00, 0x00, 0x00, 0x00,  // 1 frame
    0xE4, 0x11, 0xAB, 0x16,                          // crc
};

// Version 3's golden file (no inputs, no message): still read.
const std::vector<uint8_t> kGoldenFileVersion3 = {
    // header
    'S', 'Y', 'R', 'O', 'F', 'R', 'P', 'L',          // magic
    0x03, 0x00,                                      // version 3
    0x08, 0x07, 0x06, 0x05, 0x04, 0x03, 0x02, 0x01,  // seed 0x0102030405060708
    0x80, 0xF0, 0xFA, 0x02, 0x00, 0x00, 0x00, 0x00,  // radio_round_ns 50000000
    0x00, 0x00, 0x80, 0x40,                          // arena_width_m 4.0
    0x00, 0x00, 0x20, 0x40,                          // arena_height_m 2.5
    0x02, 0x00, 'a', 'b',                            // scenario_name "ab"
    0x01, 0x00, 'c',                                 // app_name "c"
    0x01, 0x00, 0x00, 0x00,                          // robot count 1
    0x07, 0x00, 0x01, 0x00, 0x00, 0x00, 0x3E,        // robot 7, rover, radius 0.125
    0x01, 0x00,                                      // anchor count 1
    0x00, 0x00, 0x00, 0x3F, 0x00, 0x00, 0x00, 0x40,  // anchor (0.5, 2.0)
    0xA1, 0x5E, 0x06, 0x91,                          // crc
    // round
    'R',                                             // tag
    0x03, 0x00, 0x00, 0x00,                          // index 3
    0x80, 0xD1, 0xF0, 0x08, 0x00, 0x00, 0x00, 0x00,  // time_ns 150000000
    0x01, 0x00, 0x00, 0x00,                          // frame count 1
    0x02, 0x00, 0x00, 0x00,                          // event count 2
    0x01, 0x00, 0x00, 0x00,                          // map count 1
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
    0xFF, 0xFF,                                      // partition none
    0x0A,                                            // event: PARTITION_START
    0xFF, 0xFF, 0xFF, 0xFF,                          // robot none, other none
    0x00, 0x00, 0x00,                                // epoch 0, mode 0
    0x00, 0x3B, 0x58, 0x08, 0x00, 0x00, 0x00, 0x00,  // time_ns 140000000
    0x05, 0x00,                                      // partition 5
    0x07, 0x00, 0xFF, 0xFF,                          // map: robot 7, same_as none (the map follows)
    0x02, 0x01, 0x01,                                // epoch 0x0102, AUTONOMOUS
    0x01, 0x00,                                      // member count 1
    0x07, 0x00, 0x02,                                // member 7, VOTE
    0xE8, 0x03, 0xFF, 0xFF, 0xF4, 0x01,              // x_mm 1000, y_mm -1, heading_mrad 500
    0x00, 0x00, 0x00, 0x00,                          // vx_mm_s 0, vy_mm_s 0
    0x02, 0xAB, 0xCD,                                // payload of 2 bytes
    0x8F, 0xA4, 0x40, 0xD3,                          // crc
    // end marker
    'E',                                             // tag
    0x01, 0x00, 0x00, 0x00,                          // 1 round
    0x02, 0x00, 0x00, 0x00, 0x00, 0x00, 0x00, 0x00,  // 2 events
    0x01, 0x00, 0x00, 0x00, 0x00, 0x00, 0x00, 0x00,  // 1 frame
    0xE4, 0x11, 0xAB, 0x16,                          // crc
};

TEST(ReplayWriterReader, LayoutMatchesTheGoldenFile) {
  Header header;
  header.seed = 0x0102030405060708;
  header.radio_round_ns = 50'000'000;
  header.arena_width_m = 4.0f;
  header.arena_height_m = 2.5f;
  header.scenario_name = "ab";
  header.app_name = "c";
  header.robots = {{7, 1, 0.125f, {{"charge", 870.0}}}};
  header.anchors = {{0.5f, 2.0f}};
  message::MessageFormat format;
  format.none = false;
  format.fields = {{"charge", message::FieldType::kU16Be, 0}};
  format.length = 2;
  header.message = format;
  RobotFrame frame{.id = 7, .presence = Presence::kRunning, .status = 1, .phase = 2, .mode = 1, .epoch = 0x0102};
  frame.true_x_m = 1.0f;
  frame.true_heading_rad = -0.5f;
  frame.est_x_m = 1.0f;
  const std::array<Event, 2> events = {Event{EventKind::kEpochStart, 7, kNoRobot, 0x0102, 1, 150'000'000},
                                       Event{EventKind::kPartitionStart, kNoRobot, kNoRobot, 0, 0, 140'000'000, 5}};
  auto map = std::make_shared<EpochMap>();
  map->epoch = 0x0102;
  map->mode = 1;
  map->members = {MapMember{7, 2, 1000, -1, 500, 0, 0, {0xAB, 0xCD}}};
  const RobotMap robot_map{7, map};
  std::ostringstream out;

  Writer writer(out, header);
  writer.WriteRound(3, 150'000'000, {&frame, 1}, events, {&robot_map, 1});
  writer.Finish();

  ASSERT_TRUE(writer.ok()) << writer.error();
  const std::string bytes = out.str();
  EXPECT_EQ(std::vector<uint8_t>(bytes.begin(), bytes.end()), kGoldenFile);
  const testing::ReadBack back = Read(std::string(kGoldenFile.begin(), kGoldenFile.end()));
  EXPECT_TRUE(back.complete) << back.error;
  EXPECT_EQ(back.header, header);
  ASSERT_EQ(back.rounds.size(), 1u);
  EXPECT_EQ(back.rounds[0].robots[0], frame);
  EXPECT_EQ(back.rounds[0].events, std::vector<Event>(events.begin(), events.end()));
  ASSERT_EQ(back.rounds[0].maps.size(), 1u);
  EXPECT_EQ(back.rounds[0].maps[0], robot_map);
}

TEST(ReplayReader, RefusesABadMessageFormatInTheHeader) {
  // The golden file's message kind is at byte 79, its field at 81 (type at 89).
  std::string kind(kGoldenFile.begin(), kGoldenFile.end());
  kind[79] = 7;
  const testing::ReadBack bad_kind = Read(kind);
  EXPECT_FALSE(bad_kind.complete);
  EXPECT_NE(bad_kind.error.find("offset 79: unknown message kind 7"), std::string::npos) << bad_kind.error;
  std::string type(kGoldenFile.begin(), kGoldenFile.end());
  type[89] = 99;
  const testing::ReadBack bad_type = Read(type);
  EXPECT_NE(bad_type.error.find("offset 81: unknown message field type 99"), std::string::npos) << bad_type.error;
  std::string name(kGoldenFile.begin(), kGoldenFile.end());
  name[83] = 'C';  // "Charge": not a field name
  const testing::ReadBack bad_name = Read(name);
  EXPECT_NE(bad_name.error.find("offset 81: message field name 'Charge'"), std::string::npos) << bad_name.error;
}

TEST(ReplayReader, ReadsAVersion3FileWithoutInputsOrMessage) {
  const testing::ReadBack back = Read(std::string(kGoldenFileVersion3.begin(), kGoldenFileVersion3.end()));
  EXPECT_TRUE(back.complete) << back.error;
  ASSERT_EQ(back.header.robots.size(), 1u);
  EXPECT_TRUE(back.header.robots[0].inputs.empty());
  EXPECT_FALSE(back.header.message.has_value());
  ASSERT_EQ(back.rounds.size(), 1u);
  ASSERT_EQ(back.rounds[0].maps.size(), 1u);
  EXPECT_EQ(back.rounds[0].maps[0].map->members[0].payload, (std::vector<uint8_t>{0xAB, 0xCD}));
}

// The same file as version 1 wrote it: version 2's golden file with only the
// version and the header's CRC changed (version 2 only added event kinds).
std::vector<uint8_t> GoldenFileVersion1() {
  std::vector<uint8_t> bytes = testing::GoldenFileVersion2();
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

TEST(ReplayReader, ReadsAVersion2File) {
  const std::vector<uint8_t>& bytes = testing::GoldenFileVersion2();

  const testing::ReadBack back = Read(std::string(bytes.begin(), bytes.end()));

  EXPECT_TRUE(back.complete) << back.error;
  ASSERT_EQ(back.rounds.size(), 1u);
  EXPECT_EQ(back.rounds[0].events,
            (std::vector<Event>{Event{EventKind::kEpochStart, 7, kNoRobot, 0x0102, 1, 150'000'000}}));
  EXPECT_TRUE(back.rounds[0].maps.empty());
}

// Versions 1 and 2 kept a partition's index in the robot field; the reader
// moves it to `partition`, as version 3 writes it.
TEST(ReplayReader, AVersion2PartitionEventGetsItsPartitionField) {
  std::vector<uint8_t> bytes = testing::GoldenFileVersion2();
  bytes[testing::kGoldenV2EventAt] = static_cast<uint8_t>(EventKind::kPartitionStart);  // robot field: 7
  std::string file(bytes.begin(), bytes.end());
  testing::FixCrc(file, testing::kGoldenV2HeaderEnd, testing::kGoldenV2RoundEnd - 4);

  const testing::ReadBack back = Read(file);

  EXPECT_TRUE(back.complete) << back.error;
  ASSERT_EQ(back.rounds.size(), 1u);
  EXPECT_EQ(back.rounds[0].events[0].kind, EventKind::kPartitionStart);
  EXPECT_EQ(back.rounds[0].events[0].partition, 7);
  EXPECT_EQ(back.rounds[0].events[0].robot, kNoRobot);
}

// The reason for the partition field: with more partitions than robots the
// index is no robot of the header, which version 2 could not store.
TEST(ReplayWriterReader, MorePartitionsThanRobotsReadBackWhole) {
  const Header header = SampleHeader();  // three robots
  std::vector<Round> rounds = SampleRounds();
  for (uint16_t partition = 0; partition < 5; ++partition) {
    rounds[1].events.push_back(Event{EventKind::kPartitionEnd, kNoRobot, kNoRobot, 0, 0, 60'000'000, partition});
  }

  const testing::ReadBack back = Read(Write(header, rounds).bytes);

  EXPECT_TRUE(back.complete) << back.error;
  EXPECT_EQ(back.rounds, rounds);
}

TEST(ReplayWriterReader, SharedMapIsStoredOnce) {
  const Header header = SampleHeader();
  std::vector<Round> with_maps = SampleRounds();
  std::vector<Round> copies = with_maps;
  // The same content in two objects: the writer compares contents.
  copies[0].maps[1].map = std::make_shared<EpochMap>(*copies[0].maps[0].map);
  std::vector<Round> without_maps = with_maps;
  for (Round& round : without_maps) round.maps.clear();

  const size_t bare = Write(header, without_maps).bytes.size();
  const size_t shared = Write(header, with_maps).bytes.size();
  const size_t copied = Write(header, copies).bytes.size();
  const testing::ReadBack back = Read(Write(header, copies).bytes);

  // Round 0: robot 0's map in full (9 + 2 members of 14 bytes + 0 and 1
  // payload bytes), robot 1's as a 4-byte reference; round 2: robot 2's in
  // full (9 + 28 + 0 + 2).
  EXPECT_EQ(shared - bare, (9 + 28 + 1) + 4 + (9 + 28 + 2));
  EXPECT_EQ(copied, shared);
  EXPECT_EQ(back.rounds, with_maps);
  EXPECT_EQ(back.rounds[0].maps[0].map, back.rounds[0].maps[1].map);  // one object for both
}

// A reference names the lowest robot that still holds an equal map: after
// robot 0 moves on to another map, robot 2's copy of the first one refers to
// robot 1. The same bytes whether equal maps are one object or copies.
TEST(ReplayWriterReader, AReferenceNamesTheLowestRobotStillHoldingTheMap) {
  const Header header = SampleHeader();
  std::vector<Round> rounds(3);
  for (size_t i = 0; i < rounds.size(); ++i) {
    rounds[i].index = static_cast<uint32_t>(i);
    rounds[i].time_ns = static_cast<int64_t>(i + 1) * 50'000'000;
    for (const uint16_t id : {0, 1, 2}) {
      rounds[i].robots.push_back(testing::Frame(id, Presence::kRunning, 1, 1.0f + id, 1.0f));
    }
  }
  const std::shared_ptr<const EpochMap> first = testing::Map(1, 0, {0, 1, 2});
  rounds[0].maps = {{0, first}, {1, first}, {2, first}};
  rounds[1].maps = {{0, testing::Map(2, 0, {0, 1, 2})}};
  rounds[2].maps = {{2, testing::Map(1, 0, {0, 1, 2})}};  // equal to `first`, another object
  std::vector<Round> copies = rounds;
  copies[0].maps[1].map = testing::Map(1, 0, {0, 1, 2});
  copies[0].maps[2].map = testing::Map(1, 0, {0, 1, 2});
  std::vector<Round> without_round_2_map = rounds;
  without_round_2_map[2].maps.clear();

  const testing::Written shared = Write(header, rounds);
  const testing::Written copied = Write(header, copies);
  const testing::ReadBack back = Read(shared.bytes);

  EXPECT_EQ(copied.bytes, shared.bytes);
  EXPECT_EQ(shared.bytes.size() - Write(header, without_round_2_map).bytes.size(), 4u);  // a reference
  // Robot 2's record is its id and the source's id, the round's last 4 bytes before the CRC.
  const size_t record_end = shared.round_ends[2] - 4;
  EXPECT_EQ(shared.bytes.substr(record_end - 4, 4), std::string("\x02\x00\x01\x00", 4));
  ASSERT_EQ(back.rounds.size(), 3u);
  EXPECT_EQ(back.rounds, rounds);
}

TEST(ReplayWriter, RefusesMapsTheFormatCannotHold) {
  const Header header = SampleHeader();
  std::vector<Round> rounds = SampleRounds();
  auto bad = std::make_shared<EpochMap>(*rounds[0].maps[0].map);
  bad->members[1].payload.assign(10, 0);
  rounds[0].maps[1].map = bad;
  std::ostringstream out;

  Writer writer(out, header);
  writer.WriteRound(rounds[0].index, rounds[0].time_ns, rounds[0].robots, rounds[0].events, rounds[0].maps);

  EXPECT_FALSE(writer.ok());
  EXPECT_NE(writer.error().message.find("map of robot 1: map member 1 has a payload of 10 bytes"), std::string::npos)
      << writer.error();
}

TEST(ReplayWriter, RefusesAPartitionEventWithoutItsPartition) {
  const Header header = SampleHeader();
  const Event event{EventKind::kPartitionStart, 0, kNoRobot, 0, 0, 0};
  std::ostringstream out;

  Writer writer(out, header);
  writer.WriteRound(0, 0, {}, {&event, 1});

  EXPECT_FALSE(writer.ok());
  EXPECT_NE(writer.error().message.find("PARTITION_START event names no partition"), std::string::npos)
      << writer.error();
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
      {{}, {Event{.kind = static_cast<EventKind>(18)}}, 1, "unknown event kind 18"},
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
  EXPECT_STREQ(ToString(EventKind::kSafetyIntervention), "SAFETY_INTERVENTION");
  EXPECT_STREQ(ToString(EventKind::kJoinWait), "JOIN_WAIT");
  EXPECT_STREQ(ToString(EventKind::kBeaconLost), "BEACON_LOST");
  EXPECT_STREQ(ToString(static_cast<EventKind>(18)), "?");
  EXPECT_STREQ(ToString(Presence::kAbsent), "ABSENT");
  EXPECT_STREQ(ToString(Presence::kRunning), "RUNNING");
  EXPECT_STREQ(ToString(Presence::kPaused), "PAUSED");
  EXPECT_STREQ(ToString(Presence::kCrashed), "CRASHED");
  EXPECT_STREQ(ToString(static_cast<Presence>(4)), "?");
}

}  // namespace
}  // namespace syrof::lab::replay
