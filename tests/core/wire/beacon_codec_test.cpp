#include "syrof/wire/beacon_codec.h"

#include <gtest/gtest.h>

#include <array>
#include <cstdint>
#include <vector>

#include "beacon_test_support.h"

namespace syrof::wire {
namespace {

using Bytes = std::vector<uint8_t>;

constexpr uint16_t kSwarm = 32;

// The beacon of the golden encoding below.
Beacon golden_beacon() {
  Beacon beacon;
  beacon.robot_id = 17;
  beacon.epoch = 0x1234;
  beacon.phase = Phase::kVote;
  beacon.mode = Mode::kAutonomous;
  beacon.vote_counter = 5;
  beacon.waiting.set(0);
  beacon.waiting.set(3);
  beacon.waiting.set(17);
  beacon.waiting.set(31);
  beacon.snapshot.x_mm = -1500;
  beacon.snapshot.y_mm = 2750;
  beacon.snapshot.heading_mrad = -3142;
  beacon.snapshot.vx_mm_s = 300;
  beacon.snapshot.vy_mm_s = -1;
  const std::array<uint8_t, 3> payload = {0xDE, 0xAD, 0x42};
  EXPECT_EQ(beacon.snapshot.SetPayload(payload), WireError::kOk);
  beacon.relay.slot = 4;  // robot 3
  beacon.relay.x_16mm = -100;
  beacon.relay.y_16mm = kMaxRelayUnits;
  return beacon;
}

// Version 4 for 32 robots, written out by hand from docs/beacon.md: any
// change to the layout shows up here.
const Bytes kGoldenBytes = {
    0x04,                                                  // version
    0x11,                                                  // robot_id 17
    0x34, 0x12,                                            // epoch 0x1234
    0x36,                                                  // phase 2, mode 1, payload_length 3
    0x05,                                                  // vote_counter
    0x09, 0x00, 0x02, 0x80,                                // waiting {0, 3, 17, 31}
    0x24, 0xFA,                                            // x_mm -1500
    0xBE, 0x0A,                                            // y_mm 2750
    0xBA, 0xF3,                                            // heading_mrad -3142
    0x2C, 0x01,                                            // vx_mm_s 300
    0xFF, 0xFF,                                            // vy_mm_s -1
    0xDE, 0xAD, 0x42, 0x00, 0x00, 0x00, 0x00, 0x00, 0x00,  // payload
    0x04,                                                  // relay: robot 3
    0x9C, 0xFF, 0x7F,                                      // relay_x -100 (0xF9C), relay_y 2047 (0x7FF)
};

// Byte offsets of the golden layout that the decoder tests mutate.
constexpr size_t kRobotIdByte = 1;
constexpr size_t kFlagsByte = 4;
constexpr size_t kHeadingByte = 14;
constexpr size_t kPayloadByte = 20;
constexpr size_t kRelayByte = 29;

Bytes encode_to_bytes(const Beacon& beacon, uint16_t swarm_size) {
  Bytes bytes(kMaxBeaconBytes);
  const auto size = Encode(beacon, swarm_size, bytes);
  EXPECT_TRUE(size.ok()) << ToString(size.error());
  bytes.resize(size.ok() ? size.value() : 0);
  return bytes;
}

WireError decode_error(const Bytes& bytes, uint16_t swarm_size = kSwarm) {
  return Decode(bytes, swarm_size).error();
}

WireError encode_error(const Beacon& beacon, uint16_t swarm_size = kSwarm) {
  std::array<uint8_t, kMaxBeaconBytes> buffer{};
  return Encode(beacon, swarm_size, buffer).error();
}

// --- Encoding and round trips ---

TEST(BeaconEncodeTest, MatchesTheGoldenBytesFor32Robots) {
  const Beacon beacon = golden_beacon();

  const Bytes bytes = encode_to_bytes(beacon, kSwarm);

  EXPECT_EQ(bytes, kGoldenBytes);
}

TEST(BeaconDecodeTest, ReadsTheGoldenBytesFor32Robots) {
  const auto beacon = Decode(kGoldenBytes, kSwarm);

  ASSERT_TRUE(beacon.ok()) << ToString(beacon.error());
  EXPECT_EQ(beacon.value(), golden_beacon());
}

TEST(BeaconEncodeTest, ReturnsTheEncodedSizeAndLeavesTheRestOfTheBuffer) {
  std::array<uint8_t, kMaxBeaconBytes + 4> buffer;
  buffer.fill(0xAA);

  const auto size = Encode(golden_beacon(), kSwarm, buffer);

  ASSERT_TRUE(size.ok());
  EXPECT_EQ(size.value(), EncodedSize(kSwarm));
  EXPECT_EQ(buffer[size.value()], 0xAA);
}

TEST(BeaconCodecTest, RoundTripsExtremeBeaconsForEverySwarmSize) {
  for (const uint16_t swarm_size : testing::swarm_sizes_under_test()) {
    for (const Beacon& beacon :
         {Beacon(), testing::lowest_beacon(), testing::highest_beacon(swarm_size)}) {
      SCOPED_TRACE(swarm_size);

      const Bytes bytes = encode_to_bytes(beacon, swarm_size);
      const auto decoded = Decode(bytes, swarm_size);

      EXPECT_EQ(bytes.size(), EncodedSize(swarm_size));
      ASSERT_TRUE(decoded.ok()) << ToString(decoded.error());
      EXPECT_EQ(decoded.value(), beacon);
    }
  }
}

TEST(BeaconCodecTest, RoundTripsRandomBeaconsForEverySwarmSize) {
  std::mt19937 random(20240611);
  for (const uint16_t swarm_size : testing::swarm_sizes_under_test()) {
    for (int trial = 0; trial < 200; ++trial) {
      const Beacon beacon = testing::random_beacon(random, swarm_size);

      const auto decoded = Decode(encode_to_bytes(beacon, swarm_size), swarm_size);

      ASSERT_TRUE(decoded.ok()) << swarm_size << ": " << ToString(decoded.error());
      ASSERT_EQ(decoded.value(), beacon) << swarm_size;
    }
  }
}

TEST(BeaconCodecTest, RobotIdTakesTwoBytesAbove256Robots) {
  if (kMaxSwarmSize < 257) {
    GTEST_SKIP() << "this build supports at most " << kMaxSwarmSize << " robots";
  }
  Beacon beacon;
  beacon.robot_id = 256;

  const Bytes bytes = encode_to_bytes(beacon, 257);

  ASSERT_GE(bytes.size(), 3u);
  EXPECT_EQ(bytes[1], 0x00);
  EXPECT_EQ(bytes[2], 0x01);
}

// --- Decoder errors, each from the golden bytes changed as little as possible ---

TEST(BeaconDecodeTest, RejectsAnOutOfRangeSwarmSize) {
  EXPECT_EQ(decode_error(kGoldenBytes, 0), WireError::kSwarmSizeOutOfRange);
  if (kMaxSwarmSize < 65535) {
    EXPECT_EQ(decode_error(kGoldenBytes, kMaxSwarmSize + 1), WireError::kSwarmSizeOutOfRange);
  }
}

TEST(BeaconDecodeTest, RejectsTruncatedInput) {
  Bytes bytes = kGoldenBytes;
  bytes.pop_back();

  EXPECT_EQ(decode_error(bytes), WireError::kTruncated);
  EXPECT_EQ(decode_error(Bytes()), WireError::kTruncated);
  EXPECT_EQ(decode_error(Bytes(kGoldenBytes.begin(), kGoldenBytes.begin() + 1)),
            WireError::kTruncated);
}

TEST(BeaconDecodeTest, RejectsTrailingBytes) {
  Bytes bytes = kGoldenBytes;
  bytes.push_back(0x00);

  EXPECT_EQ(decode_error(bytes), WireError::kTrailingBytes);
}

TEST(BeaconDecodeTest, RejectsAnotherVersion) {
  Bytes bytes = kGoldenBytes;
  bytes[0] = kBeaconVersion + 1;

  EXPECT_EQ(decode_error(bytes), WireError::kWrongVersion);
  bytes[0] = 0;
  EXPECT_EQ(decode_error(bytes), WireError::kWrongVersion);
}

TEST(BeaconDecodeTest, NamesAnotherVersionWhateverItsLength) {
  const Bytes bytes = {kBeaconVersion + 1, 0x00};

  EXPECT_EQ(decode_error(bytes), WireError::kWrongVersion);
}

TEST(BeaconDecodeTest, RejectsARobotIdBeyondTheSwarm) {
  Bytes bytes = kGoldenBytes;
  bytes[kRobotIdByte] = kSwarm;

  EXPECT_EQ(decode_error(bytes), WireError::kRobotIdOutOfRange);
}

TEST(BeaconDecodeTest, RejectsAnOutOfRangePhase) {
  Bytes bytes = kGoldenBytes;
  bytes[kFlagsByte] |= 0x03;  // phase 3

  EXPECT_EQ(decode_error(bytes), WireError::kPhaseOutOfRange);
}

// Version 2 gave the mode's second bit to presence_only: bit 3 of the flags
// byte, which version 1 read as "mode 2" and rejected.
TEST(BeaconDecodeTest, ReadsBitThreeOfTheFlagsAsPresenceOnly) {
  Bytes bytes = kGoldenBytes;
  bytes[kFlagsByte] = static_cast<uint8_t>((bytes[kFlagsByte] & ~0x0C) | 0x08);  // mode 0, presence_only

  const auto decoded = Decode(bytes, kSwarm);
  ASSERT_TRUE(decoded.ok());
  EXPECT_TRUE(decoded.value().presence_only);
  EXPECT_EQ(decoded.value().mode, Mode::kCooperative);
}

TEST(BeaconCodecTest, RoundTripsAPresenceOnlyBeacon) {
  Beacon beacon;
  beacon.robot_id = 5;
  beacon.presence_only = true;
  beacon.snapshot.x_mm = 1200;
  beacon.snapshot.y_mm = -300;
  std::array<uint8_t, kMaxBeaconBytes> buffer{};
  const auto size = Encode(beacon, kSwarm, buffer);
  ASSERT_TRUE(size.ok());
  const auto decoded = Decode(std::span<const uint8_t>(buffer.data(), size.value()), kSwarm);
  ASSERT_TRUE(decoded.ok());
  EXPECT_EQ(decoded.value(), beacon);
}

TEST(BeaconDecodeTest, RejectsAPayloadLengthOverNine) {
  Bytes bytes = kGoldenBytes;
  bytes[kFlagsByte] = static_cast<uint8_t>((bytes[kFlagsByte] & 0x0F) | 0xA0);  // length 10

  EXPECT_EQ(decode_error(bytes), WireError::kPayloadTooLong);
}

TEST(BeaconDecodeTest, RejectsAWaitingMemberBeyondTheSwarm) {
  constexpr uint16_t kThirtyRobots = 30;
  Beacon beacon = golden_beacon();
  beacon.waiting.reset(31);
  Bytes bytes = encode_to_bytes(beacon, kThirtyRobots);
  ASSERT_EQ(bytes.size(), EncodedSize(kThirtyRobots));
  bytes[6 + 3] |= 0x40;  // member 30, the first padding bit of the waiting set

  EXPECT_EQ(decode_error(bytes, kThirtyRobots), WireError::kMemberOutOfRange);
}

TEST(BeaconDecodeTest, RejectsAnOutOfRangeHeading) {
  Bytes bytes = kGoldenBytes;
  bytes[kHeadingByte] = 0x47;  // 3143 = 0x0C47
  bytes[kHeadingByte + 1] = 0x0C;

  EXPECT_EQ(decode_error(bytes), WireError::kHeadingOutOfRange);
}

TEST(BeaconDecodeTest, RejectsNonZeroPayloadPadding) {
  Bytes bytes = kGoldenBytes;
  bytes[kPayloadByte + 3] = 0x01;  // the first byte past payload_length 3

  EXPECT_EQ(decode_error(bytes), WireError::kNonZeroPadding);
}

TEST(BeaconDecodeTest, RejectsARelayBeyondTheSwarm) {
  Bytes bytes = kGoldenBytes;
  bytes[kRelayByte] = kSwarm + 1;  // robot 32 of 0 .. 31

  EXPECT_EQ(decode_error(bytes), WireError::kRelayOutOfRange);
}

TEST(BeaconDecodeTest, RejectsAPositionWhereNothingIsRelayed) {
  Bytes bytes = kGoldenBytes;
  bytes[kRelayByte] = 0;  // nothing relayed, yet the coordinates are not zero

  EXPECT_EQ(decode_error(bytes), WireError::kRelayOutOfRange);
  bytes[kRelayByte + 1] = bytes[kRelayByte + 2] = bytes[kRelayByte + 3] = 0;
  const auto decoded = Decode(bytes, kSwarm);
  ASSERT_TRUE(decoded.ok()) << ToString(decoded.error());
  EXPECT_FALSE(decoded.value().relay.relays());
}

TEST(BeaconDecodeTest, ReportsTheFirstProblemInLayoutOrder) {
  Bytes bytes = kGoldenBytes;
  bytes[kHeadingByte + 1] = 0x7F;
  bytes[kRobotIdByte] = 0xFF;
  bytes.pop_back();

  EXPECT_EQ(decode_error(bytes), WireError::kRobotIdOutOfRange);
}

// --- Encoder errors: the same checks on a Beacon in memory ---

TEST(BeaconEncodeTest, RejectsAnOutOfRangeSwarmSize) {
  EXPECT_EQ(encode_error(Beacon(), 0), WireError::kSwarmSizeOutOfRange);
  if (kMaxSwarmSize < 65535) {
    EXPECT_EQ(encode_error(Beacon(), kMaxSwarmSize + 1), WireError::kSwarmSizeOutOfRange);
  }
}

TEST(BeaconEncodeTest, RejectsABufferTooSmall) {
  std::array<uint8_t, kMaxBeaconBytes> buffer{};
  const auto too_small = std::span<uint8_t>(buffer).first(EncodedSize(kSwarm) - 1);

  EXPECT_EQ(Encode(golden_beacon(), kSwarm, too_small).error(), WireError::kBufferTooSmall);
}

TEST(BeaconEncodeTest, RejectsARobotIdBeyondTheSwarm) {
  Beacon beacon = golden_beacon();
  beacon.robot_id = kSwarm;

  EXPECT_EQ(encode_error(beacon), WireError::kRobotIdOutOfRange);
}

TEST(BeaconEncodeTest, RejectsAnOutOfRangePhase) {
  Beacon beacon = golden_beacon();
  beacon.phase = static_cast<Phase>(3);

  EXPECT_EQ(encode_error(beacon), WireError::kPhaseOutOfRange);
}

TEST(BeaconEncodeTest, RejectsAnOutOfRangeMode) {
  Beacon beacon = golden_beacon();
  beacon.mode = static_cast<Mode>(2);

  EXPECT_EQ(encode_error(beacon), WireError::kModeOutOfRange);
}

TEST(BeaconEncodeTest, RejectsAPayloadLengthOverNine) {
  Beacon beacon = golden_beacon();
  beacon.snapshot.payload_length = kMaxPayloadBytes + 1;

  EXPECT_EQ(encode_error(beacon), WireError::kPayloadTooLong);
}

TEST(BeaconEncodeTest, RejectsAWaitingMemberBeyondTheSwarm) {
  // 30 robots, so member 30 still fits a MemberSet of the Teensy's capacity 32.
  constexpr uint16_t kThirtyRobots = 30;
  Beacon beacon = golden_beacon();
  beacon.waiting.reset(31);
  beacon.waiting.set(kThirtyRobots);

  EXPECT_EQ(encode_error(beacon, kThirtyRobots), WireError::kMemberOutOfRange);
}

TEST(BeaconEncodeTest, RejectsARelayBeyondTheSwarmOrAPositionWithNone) {
  Beacon beacon = golden_beacon();
  beacon.relay.slot = kSwarm + 1;
  EXPECT_EQ(encode_error(beacon), WireError::kRelayOutOfRange);

  beacon.relay.slot = 0;  // nothing relayed, a position left behind
  EXPECT_EQ(encode_error(beacon), WireError::kRelayOutOfRange);

  beacon.relay.slot = 1;
  beacon.relay.x_16mm = kMaxRelayUnits + 1;  // beyond the 12 bits
  EXPECT_EQ(encode_error(beacon), WireError::kRelayOutOfRange);
}

TEST(BeaconEncodeTest, RejectsAnOutOfRangeHeading) {
  Beacon beacon = golden_beacon();
  beacon.snapshot.heading_mrad = kMaxHeadingMilliradians + 1;
  EXPECT_EQ(encode_error(beacon), WireError::kHeadingOutOfRange);

  beacon.snapshot.heading_mrad = kMinHeadingMilliradians - 1;
  EXPECT_EQ(encode_error(beacon), WireError::kHeadingOutOfRange);
}

TEST(BeaconEncodeTest, RejectsNonZeroPayloadPadding) {
  Beacon beacon = golden_beacon();
  beacon.snapshot.payload[beacon.snapshot.payload_length] = 0x01;

  EXPECT_EQ(encode_error(beacon), WireError::kNonZeroPadding);
}

TEST(BeaconEncodeTest, LeavesZeroesAfterAnError) {
  Beacon beacon = golden_beacon();
  beacon.snapshot.payload[kMaxPayloadBytes - 1] = 0x01;
  std::array<uint8_t, kMaxBeaconBytes> buffer;
  buffer.fill(0xAA);

  const auto size = Encode(beacon, kSwarm, buffer);

  EXPECT_EQ(size.error(), WireError::kNonZeroPadding);
  for (size_t index = 0; index < EncodedSize(kSwarm); ++index) {
    EXPECT_EQ(buffer[index], 0) << index;
  }
}

}  // namespace
}  // namespace syrof::wire
