// The reader on untrusted bytes: every kind of damage gives a clear error
// naming the byte offset, never a crash.
#include <gtest/gtest.h>

#include <sstream>
#include <string>
#include <vector>

#include "replay_test_support.h"
#include "syrof/base/split_mix64.h"
#include "syrof/lab/replay/reader.h"

namespace syrof::lab::replay {
namespace {

using testing::FixCrc;
using testing::PutU16At;
using testing::PutU32At;
using testing::Read;
using testing::ReadBack;
using testing::Written;
using testing::WriteSample;

// Offsets in the sample's header (replay_test_support.h; format.h).
constexpr size_t kVersionAt = 8;
constexpr size_t kScenarioNameAt = 34;                       // "three_robots", 12 bytes
constexpr size_t kAppNameAt = kScenarioNameAt + 2 + 12;      // "builtin:idle", 12 bytes
constexpr size_t kRobotCountAt = kAppNameAt + 2 + 12;
// Offsets in a round record, from its tag.
constexpr size_t kIndexAt = 1;
constexpr size_t kTimeAt = 5;
constexpr size_t kFrameCountAt = 13;
constexpr size_t kEventCountAt = 17;
constexpr size_t kMapCountAt = 21;
constexpr size_t kFirstFrameAt = 25;
// In the sample's first round, robots 0 and 1 change every field (30 bytes
// each) and robot 2 is all zero (4 bytes).
constexpr size_t kSecondFrameAt = kFirstFrameAt + 30;
constexpr size_t kFirstEventAt = kFirstFrameAt + 30 + 30 + 4;
// Two events of 18 bytes, then robot 0's map in full, then robot 1's
// reference to it.
constexpr size_t kFirstMapAt = kFirstEventAt + 2 * 18;
constexpr size_t kSecondMapAt = kFirstMapAt + 9 + 2 * 14 + 1;

std::string At(size_t offset) { return "offset " + std::to_string(offset) + ": "; }

// Asserts the reader stopped with an error starting "offset N: " and containing `what`.
void ExpectError(const ReadBack& back, size_t offset, const std::string& what) {
  EXPECT_FALSE(back.complete);
  EXPECT_EQ(back.error.rfind(At(offset), 0), 0u) << back.error;
  EXPECT_NE(back.error.find(what), std::string::npos) << back.error;
}

TEST(ReplayReader, RefusesWrongMagic) {
  std::string bytes = WriteSample().bytes;
  bytes[3] = 'X';

  ExpectError(Read(bytes), 0, "not a SyROF replay file");
  ExpectError(Read("hello"), 0, "not a SyROF replay file: it starts with 68 65 6C 6C 6F");
  EXPECT_FALSE(Read(bytes).truncated);
}

TEST(ReplayReader, RefusesNewerAndUnknownVersions) {
  std::string newer = WriteSample().bytes;
  PutU16At(newer, kVersionAt, kFormatVersion + 1);
  std::string zero = newer;
  PutU16At(zero, kVersionAt, 0);

  ExpectError(Read(newer), kVersionAt, "format version 6 is newer than this reader's (5)");
  ExpectError(Read(zero), kVersionAt, "format version 0 does not exist (this reader knows versions 1 to 5)");
}

TEST(ReplayReader, TruncatedAtEveryOffsetGivesCleanIncompleteState) {
  const Written written = WriteSample();
  const std::vector<Round> rounds = testing::SampleRounds();

  for (size_t length = 0; length < written.bytes.size(); ++length) {
    const ReadBack back = Read(written.bytes.substr(0, length));

    SCOPED_TRACE("prefix of " + std::to_string(length) + " bytes");
    EXPECT_FALSE(back.complete);
    EXPECT_TRUE(back.truncated);
    EXPECT_EQ(back.error.rfind("offset ", 0), 0u) << back.error;
    EXPECT_NE(back.error.find("truncated"), std::string::npos) << back.error;
    EXPECT_EQ(back.header_ok, length >= written.header_end);
    size_t whole_rounds = 0;
    while (whole_rounds < written.round_ends.size() && written.round_ends[whole_rounds] <= length) ++whole_rounds;
    ASSERT_EQ(back.rounds.size(), whole_rounds);
    EXPECT_EQ(back.rounds, std::vector<Round>(rounds.begin(), rounds.begin() + whole_rounds));
  }
  EXPECT_TRUE(Read(written.bytes).complete);
}

TEST(ReplayReader, FileEndingBetweenRecordsSaysHowManyRoundsItHolds) {
  const Written written = WriteSample();

  const ReadBack back = Read(written.bytes.substr(0, written.round_ends[1]));

  ExpectError(back, written.round_ends[1], "file ends after 2 rounds without the end marker");
  EXPECT_TRUE(back.truncated);
}

TEST(ReplayReader, RefusesAbsurdRobotCount) {
  std::string bytes = WriteSample().bytes;
  PutU32At(bytes, kRobotCountAt, 0xFFFFFFFF);

  ExpectError(Read(bytes), kRobotCountAt, "robot count 4294967295 is more than the 65535");
}

TEST(ReplayReader, LargeRobotCountInShortFileIsTruncationNotAllocation) {
  std::string bytes = WriteSample().bytes.substr(0, kRobotCountAt + 4);
  PutU32At(bytes, kRobotCountAt, kMaxRobots);

  const ReadBack back = Read(bytes);

  ExpectError(back, kRobotCountAt + 4, "file ends inside robot entry");
  EXPECT_TRUE(back.truncated);
}

TEST(ReplayReader, RefusesTooManyOrNonFiniteAnchors) {
  const Written written = WriteSample();
  const size_t anchor_count_at = kRobotCountAt + 4 + 3 * 7;
  std::string many = written.bytes;
  PutU16At(many, anchor_count_at, 300);
  std::string infinite = written.bytes;
  PutU32At(infinite, anchor_count_at + 2 + 8 + 4, 0x7F800000);  // anchor 1's y

  ExpectError(Read(many), anchor_count_at, "anchor count 300 is more than the 256 allowed");
  ExpectError(Read(infinite), anchor_count_at + 2 + 8, "anchor 1 at (4, inf) is not finite");
}

TEST(ReplayReader, RefusesNameTooLongOrWithControlCharacters) {
  std::string too_long = WriteSample().bytes;
  PutU16At(too_long, kScenarioNameAt, 5000);
  std::string control = WriteSample().bytes;
  control[kAppNameAt + 2 + 3] = '\x1b';

  ExpectError(Read(too_long), kScenarioNameAt, "scenario_name is 5000 bytes, more than the 256 allowed");
  ExpectError(Read(control), kAppNameAt + 2, "app_name has control character 0x1B at byte 3");
}

// A name is shown as text (syrof view's page, --format jsonl): bytes that
// are not UTF-8 are refused here, at their offset, not by the JSON library.
TEST(ReplayReader, RefusesNamesThatAreNotUtf8) {
  std::string stray = WriteSample().bytes;
  stray[kAppNameAt + 2 + 3] = '\xFF';
  std::string cut = WriteSample().bytes;
  cut[kScenarioNameAt + 2 + 11] = '\xC3';  // the first byte of a two-byte character, last in the name
  const Written written = WriteSample();
  std::string accented = written.bytes;
  accented[kScenarioNameAt + 2 + 4] = '\xC3';  // "thre\xC3\xA9_robots": an e with an acute accent
  accented[kScenarioNameAt + 2 + 5] = '\xA9';
  FixCrc(accented, 0, written.header_end - 4);

  ExpectError(Read(stray), kAppNameAt + 2, "app_name is not UTF-8 at byte 3");
  ExpectError(Read(cut), kScenarioNameAt + 2, "scenario_name is not UTF-8 at byte 11");
  EXPECT_TRUE(Read(accented).complete) << Read(accented).error;
}

TEST(ReplayReader, RefusesRoundIndexGoingBackwards) {
  const Written written = WriteSample();
  std::string backwards = written.bytes;
  const size_t third = written.round_ends[1];
  PutU32At(backwards, third + kIndexAt, 1);  // the second round is 1
  std::string earlier = written.bytes;
  PutU32At(earlier, third + kTimeAt, 0);

  const ReadBack back = Read(backwards);

  ExpectError(back, third + kIndexAt, "round index 1 does not follow round 1");
  EXPECT_EQ(back.rounds.size(), 2u);
  ExpectError(Read(earlier), third + kIndexAt, "round 3 at 0 ns is before the previous round's 100000000 ns");
}

TEST(ReplayReader, RefusesUnknownOrRepeatedRobotId) {
  const Written written = WriteSample();
  const size_t first = written.header_end;
  std::string unknown = written.bytes;
  PutU16At(unknown, first + kFirstFrameAt, 9);
  std::string repeated = written.bytes;
  PutU16At(repeated, first + kSecondFrameAt, 0);

  ExpectError(Read(unknown), first + kFirstFrameAt, "frame of robot 9, which is not in the header");
  ExpectError(Read(repeated), first + kSecondFrameAt, "frame of robot 0 after robot 0");
}

TEST(ReplayReader, RefusesReservedBitsAndBadPhase) {
  const Written written = WriteSample();
  const size_t state_at = written.header_end + kFirstFrameAt + 2;
  std::string reserved = written.bytes;
  reserved[state_at] = static_cast<char>(0x41);
  std::string phase = written.bytes;
  phase[state_at] = static_cast<char>(3 << 3);
  std::string changed = written.bytes;
  changed[state_at + 1] = static_cast<char>(0xFF);

  ExpectError(Read(reserved), state_at, "state byte 0x41 has reserved bits set");
  ExpectError(Read(phase), state_at, "robot 0 has phase 3");
  ExpectError(Read(changed), state_at + 1, "changed-fields byte 0xFF has reserved bits set");
}

TEST(ReplayReader, RefusesAbsurdFrameAndEventCounts) {
  const Written written = WriteSample();
  const size_t first = written.header_end;
  std::string frames = written.bytes;
  PutU32At(frames, first + kFrameCountAt, 4);
  std::string events = written.bytes;
  PutU32At(events, first + kEventCountAt, 0xFFFFFFFF);

  ExpectError(Read(frames), first + kFrameCountAt, "frame count 4 is more than the header's 3 robots");
  ExpectError(Read(events), first + kEventCountAt, "event count 4294967295 is more than the 1048576");
}

TEST(ReplayReader, RefusesUnknownEventKindAndRobot) {
  const Written written = WriteSample();
  const size_t event_at = written.header_end + kFirstEventAt;
  std::string kind = written.bytes;
  kind[event_at] = 18;
  std::string robot = written.bytes;
  PutU16At(robot, event_at + 1, 9);
  std::string partition = written.bytes;
  PutU16At(partition, event_at + 16, 3);  // on the EPOCH_START

  ExpectError(Read(kind), event_at, "unknown event kind 18 (format version 5)");
  ExpectError(Read(robot), event_at + 1, "event robot 9 is not a robot of the header");
  ExpectError(Read(partition), event_at, "EPOCH_START event names partition 3; only partition events do");
}

TEST(ReplayReader, RefusesBadMaps) {
  const Written written = WriteSample();
  const size_t round = written.header_end;
  const size_t map_at = round + kFirstMapAt;
  const size_t member_at = map_at + 9;
  auto damaged = [&](auto edit) {
    std::string bytes = written.bytes;
    edit(bytes);
    FixCrc(bytes, round, written.round_ends[0] - 4);
    return Read(bytes);
  };

  ExpectError(damaged([&](std::string& b) { PutU32At(b, round + kMapCountAt, 4); }), round + kMapCountAt,
              "round 0: map count 4 is more than the header's 3 robots");
  ExpectError(damaged([&](std::string& b) { PutU16At(b, map_at, 9); }), map_at,
              "map of robot 9, which is not in the header");
  ExpectError(damaged([&](std::string& b) { PutU16At(b, round + kSecondMapAt, 0); }), round + kSecondMapAt,
              "map of robot 0 after robot 0");
  ExpectError(damaged([&](std::string& b) { PutU16At(b, round + kSecondMapAt + 2, 2); }), round + kSecondMapAt + 2,
              "map of robot 1 is the same as robot 2's, but robot 2 has no map yet");
  ExpectError(damaged([&](std::string& b) { b[map_at + 6] = 2; }), map_at + 6, "map of robot 0: map mode 2");
  ExpectError(damaged([&](std::string& b) { PutU16At(b, map_at + 7, 0xFFFF); }), map_at + 7,
              "map of robot 0: member count 65535 is more than the header's 3 robots");
  ExpectError(damaged([&](std::string& b) { PutU16At(b, member_at, 7); }), member_at,
              "map of robot 0: map member 7 is not a robot of the header");
  ExpectError(damaged([&](std::string& b) { b[member_at + 2] = 3; }), member_at,
              "map of robot 0: map member 0 has phase 3");
  ExpectError(damaged([&](std::string& b) { b[member_at + 13] = 10; }), member_at,
              "map of robot 0: map member 0 has a payload of 10 bytes");
  ExpectError(damaged([&](std::string& b) { PutU16At(b, member_at + 14, 0); }), member_at + 14,
              "map of robot 0: map member 0 follows member 0");
}

TEST(ReplayReader, AVersion1FileHasNoAppEvents) {
  // Arrange: version 2's golden file as version 1 with its event APP_FAULT,
  // a kind version 1 did not have.
  const std::vector<uint8_t>& golden = testing::GoldenFileVersion2();
  std::string bytes(golden.begin(), golden.end());
  PutU16At(bytes, kVersionAt, 1);
  FixCrc(bytes, 0, testing::kGoldenV2HeaderEnd - 4);
  bytes[testing::kGoldenV2EventAt] = static_cast<char>(EventKind::kAppFault);

  ExpectError(Read(bytes), testing::kGoldenV2EventAt, "unknown event kind 12 (format version 1)");
}

TEST(ReplayReader, AVersion2FileHasNoSafetyEvents) {
  const std::vector<uint8_t>& golden = testing::GoldenFileVersion2();
  std::string bytes(golden.begin(), golden.end());
  bytes[testing::kGoldenV2EventAt] = static_cast<char>(EventKind::kSafetyIntervention);

  ExpectError(Read(bytes), testing::kGoldenV2EventAt, "unknown event kind 15 (format version 2)");
}

TEST(ReplayReader, RefusesDamagedBytesByChecksum) {
  const Written written = WriteSample();
  std::string header = written.bytes;
  header[12] ^= 0x10;  // inside the seed, which has no range to check
  std::string round = written.bytes;
  round[written.header_end + kFirstFrameAt + 10] ^= 0x01;  // inside a float

  ExpectError(Read(header), written.header_end - 4, "checksum of the header starting at offset 0");
  ExpectError(Read(round), written.round_ends[0] - 4,
              "checksum of the round starting at offset " + std::to_string(written.header_end));
}

TEST(ReplayReader, EverySingleByteChangeIsAnError) {
  const std::string good = WriteSample().bytes;

  for (size_t offset = 0; offset < good.size(); ++offset) {
    for (const char flip : {'\x01', '\x80'}) {
      std::string bytes = good;
      bytes[offset] = static_cast<char>(bytes[offset] ^ flip);

      const ReadBack back = Read(bytes);

      EXPECT_FALSE(back.complete) << "offset " << offset;
      EXPECT_EQ(back.error.rfind("offset ", 0), 0u) << "offset " << offset << ": " << back.error;
    }
  }
}

TEST(ReplayReader, RandomDamageNeverCrashes) {
  const std::string good = WriteSample().bytes;
  base::SplitMix64 random(20240611);

  for (int trial = 0; trial < 3000; ++trial) {
    std::string bytes = good.substr(0, good.size() - random.Below(8));
    const uint32_t changes = 1 + random.Below(4);
    for (uint32_t change = 0; change < changes; ++change) {
      bytes[random.Below(static_cast<uint32_t>(bytes.size()))] = static_cast<char>(random.Below(256));
    }

    const ReadBack back = Read(bytes);

    // Either the damage happened to change nothing, or it is reported.
    if (bytes == good) {
      EXPECT_TRUE(back.complete);
    } else {
      EXPECT_FALSE(back.complete) << "trial " << trial;
      EXPECT_FALSE(back.error.empty()) << "trial " << trial;
    }
  }
}

TEST(ReplayReader, RefusesEndMarkerThatDisagreesWithTheRounds) {
  const Written written = WriteSample();
  std::string bytes = written.bytes;
  const size_t end = written.round_ends.back();
  PutU32At(bytes, end + 1, 4);
  FixCrc(bytes, end, bytes.size() - 4);

  ExpectError(Read(bytes), end + 1, "end marker counts 4 rounds, 6 events and 8 frames, but the file holds 3, 6 and 8");
}

TEST(ReplayReader, RefusesBytesAfterTheEndMarker) {
  const std::string bytes = WriteSample().bytes + "x";

  ExpectError(Read(bytes), bytes.size() - 1, "unexpected bytes after the end marker");
}

TEST(ReplayReader, RefusesUnknownRecordTag) {
  const Written written = WriteSample();
  std::string bytes = written.bytes;
  bytes[written.header_end] = 'X';

  ExpectError(Read(bytes), written.header_end, "unknown record tag 0x58");
}

TEST(ReplayReader, RefusesCallsOutOfOrder) {
  const std::string bytes = WriteSample().bytes;
  std::istringstream in(bytes);
  Reader reader(in);
  Round round;
  Header header;

  EXPECT_FALSE(reader.Next(round));
  EXPECT_NE(reader.error().message.find("Next called before ReadHeader"), std::string::npos) << reader.error();
  EXPECT_FALSE(reader.ReadHeader(header));
  EXPECT_FALSE(reader.complete());
}

}  // namespace
}  // namespace syrof::lab::replay
