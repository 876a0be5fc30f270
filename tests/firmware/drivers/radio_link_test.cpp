// The radio link's framing (and the sensor link's kinds): round trips of every kind, the encoder's
// refusals, the decoder's rejections (each LinkError), and resynchronisation
// after garbage and corruption.
#include "syrof/firmware/drivers/radio_link.h"

#include <gtest/gtest.h>

#include <array>
#include <cstdint>
#include <limits>
#include <random>
#include <vector>

namespace syrof::firmware::drivers {
namespace {

std::vector<uint8_t> Encoded(const Frame& frame) {
  std::array<uint8_t, kMaxWireBytes> out{};
  const auto length = EncodeFrame(frame, out);
  EXPECT_TRUE(length.ok()) << ToString(length.error());
  if (!length.ok()) return {};
  return {out.begin(), out.begin() + static_cast<std::ptrdiff_t>(length.value())};
}

// Every event a stream produces, with the frames delivered.
struct Feed {
  std::vector<Frame> frames;
  std::vector<LinkError> errors;
  std::vector<uint64_t> error_offsets;
};

Feed Push(FrameDecoder& decoder, const std::vector<uint8_t>& bytes) {
  Feed feed;
  for (const uint8_t byte : bytes) {
    switch (decoder.Push(byte)) {
      case DecodeEvent::kFrame: feed.frames.push_back(decoder.frame()); break;
      case DecodeEvent::kError:
        feed.errors.push_back(decoder.error());
        feed.error_offsets.push_back(decoder.error_offset());
        break;
      case DecodeEvent::kNone: break;
    }
  }
  return feed;
}

// A test-side COBS stuffing of any body, with 0x00 around it, for frames the
// encoder would refuse to write.
std::vector<uint8_t> Stuffed(const std::vector<uint8_t>& body) {
  std::vector<uint8_t> out{0x00};
  std::vector<uint8_t> block;
  for (const uint8_t byte : body) {
    if (byte == 0) {
      out.push_back(static_cast<uint8_t>(block.size() + 1));
      out.insert(out.end(), block.begin(), block.end());
      block.clear();
    } else {
      block.push_back(byte);
    }
  }
  out.push_back(static_cast<uint8_t>(block.size() + 1));
  out.insert(out.end(), block.begin(), block.end());
  out.push_back(0x00);
  return out;
}

std::vector<uint8_t> WithCrc(std::vector<uint8_t> body) {
  const uint16_t crc = Crc16(body);
  body.push_back(static_cast<uint8_t>(crc >> 8));
  body.push_back(static_cast<uint8_t>(crc & 0xFF));
  return body;
}

std::vector<uint8_t> SampleBeacon(size_t length) {
  std::vector<uint8_t> beacon(length);
  for (size_t i = 0; i < length; ++i) beacon[i] = static_cast<uint8_t>(i * 37 % 7);  // zeros included
  return beacon;
}

ImuPayload SampleImu() {
  ImuPayload imu;
  imu.accel_g = {0.012f, -0.25f, 1.0f};
  imu.gyro_dps = {0.0f, -0.0f, 37.5f};
  return imu;
}

UwbPayload SampleUwb() {
  UwbPayload uwb;
  uwb.valid_mask = 0x0B;  // anchors 0, 1, 3
  uwb.sweep = 0;
  uwb.range_mm = {1414, 65535, 0, 2830, 0, 0, 0, 0};
  return uwb;
}

DrivePayload SampleDrive() {
  DrivePayload drive;
  drive.vx_mps = 0.25f;
  drive.vy_mps = -0.125f;
  drive.yaw_rate_radps = 1e-30f;
  return drive;
}

std::vector<Frame> EveryKind() {
  const std::vector<uint8_t> beacon = SampleBeacon(29);
  return {MakeSendBeacon(7, beacon),
          MakeReceivedBeacon(200, -87, beacon),
          MakeSendDone(7, SendStatus::kBusy),
          MakeHello(0),
          MakeImu(1, SampleImu()),
          MakeFlow(2, FlowPayload{20'000'000, -3, 32767}),
          MakeUwb(3, SampleUwb()),
          MakeDrive(255, SampleDrive()),
          MakeStart(4, 20'000),
          MakeStart(5, 0xFFFF'FFFFu)};
}

TEST(RadioLinkTest, Crc16HasTheCatalogueCheckValue) {
  const std::vector<uint8_t> check{'1', '2', '3', '4', '5', '6', '7', '8', '9'};
  EXPECT_EQ(Crc16(check), 0xD64E);
}

TEST(RadioLinkTest, EveryKindRoundTrips) {
  for (const Frame& frame : EveryKind()) {
    FrameDecoder decoder;
    const std::vector<uint8_t> bytes = Encoded(frame);
    const Feed feed = Push(decoder, bytes);
    ASSERT_EQ(feed.frames.size(), 1u) << ToString(frame.kind);
    EXPECT_EQ(feed.frames[0], frame) << ToString(frame.kind);
    EXPECT_TRUE(feed.errors.empty());
    EXPECT_EQ(decoder.counters().frames, 1u);
  }
}

TEST(RadioLinkTest, WireBytesHoldNoZeroBetweenTheDelimiters) {
  for (const Frame& frame : EveryKind()) {
    const std::vector<uint8_t> bytes = Encoded(frame);
    ASSERT_GE(bytes.size(), 2u);
    EXPECT_EQ(bytes.front(), 0x00);
    EXPECT_EQ(bytes.back(), 0x00);
    for (size_t i = 1; i + 1 < bytes.size(); ++i) EXPECT_NE(bytes[i], 0x00) << "byte " << i;
  }
}

TEST(RadioLinkTest, BeaconsOfEveryLengthRoundTrip) {
  for (size_t length = 1; length <= kMaxLinkBeaconBytes; ++length) {
    const Frame frame = MakeReceivedBeacon(static_cast<uint8_t>(length), -40, SampleBeacon(length));
    FrameDecoder decoder;
    const Feed feed = Push(decoder, Encoded(frame));
    ASSERT_EQ(feed.frames.size(), 1u) << length;
    EXPECT_EQ(feed.frames[0], frame);
  }
  const std::vector<uint8_t> zeros(kMaxLinkBeaconBytes, 0x00);
  EXPECT_EQ(Encoded(MakeReceivedBeacon(0, -1, zeros)).size(), kMaxWireBytes);
}

TEST(RadioLinkTest, FramesBackToBackAreAllDelivered) {
  std::vector<uint8_t> stream;
  for (const Frame& frame : EveryKind()) {
    const std::vector<uint8_t> bytes = Encoded(frame);
    stream.insert(stream.end(), bytes.begin(), bytes.end());
  }
  FrameDecoder decoder;
  const Feed feed = Push(decoder, stream);
  EXPECT_EQ(feed.frames, EveryKind());
  EXPECT_TRUE(feed.errors.empty());
}

TEST(RadioLinkTest, EncoderRefusesWhatTheDecoderWouldReject) {
  std::array<uint8_t, kMaxWireBytes> out{};
  EXPECT_EQ(EncodeFrame(MakeSendBeacon(1, {}), out).error(), LinkError::kBadLength);
  EXPECT_EQ(EncodeFrame(MakeSendBeacon(1, SampleBeacon(kMaxLinkBeaconBytes + 1)), out).error(),
            LinkError::kBadLength);
  EXPECT_EQ(EncodeFrame(MakeSendDone(1, static_cast<SendStatus>(3)), out).error(), LinkError::kBadField);
  Frame hello = MakeHello(1);
  hello.version = 2;
  EXPECT_EQ(EncodeFrame(hello, out).error(), LinkError::kBadField);
  Frame unknown = MakeHello(1);
  unknown.kind = static_cast<FrameKind>(10);
  EXPECT_EQ(EncodeFrame(unknown, out).error(), LinkError::kUnknownKind);
  const Frame frame = MakeSendBeacon(1, SampleBeacon(10));
  const size_t needed = Encoded(frame).size();
  std::vector<uint8_t> short_out(needed - 1);
  EXPECT_EQ(EncodeFrame(frame, short_out).error(), LinkError::kBufferTooSmall);
}

TEST(RadioLinkTest, SensorLinkRefusesNonFiniteFloatsZeroIntervalsAndUnknownDriveKinds) {
  std::array<uint8_t, kMaxWireBytes> out{};
  ImuPayload imu = SampleImu();
  imu.gyro_dps[2] = std::numeric_limits<float>::quiet_NaN();
  EXPECT_EQ(EncodeFrame(MakeImu(1, imu), out).error(), LinkError::kBadField);
  EXPECT_EQ(EncodeFrame(MakeFlow(1, FlowPayload{0, 1, 1}), out).error(), LinkError::kBadField);
  DrivePayload drive = SampleDrive();
  drive.right_mps = std::numeric_limits<float>::infinity();
  EXPECT_EQ(EncodeFrame(MakeDrive(1, drive), out).error(), LinkError::kBadField);
  drive = SampleDrive();
  drive.kind = 2;
  EXPECT_EQ(EncodeFrame(MakeDrive(1, drive), out).error(), LinkError::kBadField);

  // The same values as a sender that skipped the checks would write them.
  std::vector<uint8_t> nan_imu = {5, 1};
  for (int i = 0; i < 6; ++i) nan_imu.insert(nan_imu.end(), {0x7F, 0xC0, 0x00, 0x00});
  std::vector<uint8_t> wheels_kind_two = {8, 1, 2};
  wheels_kind_two.insert(wheels_kind_two.end(), 20, 0x00);
  std::vector<uint8_t> short_uwb = {7, 1, 0x01, 0x00, 0x05};
  const std::vector<std::pair<std::vector<uint8_t>, LinkError>> cases = {
      {nan_imu, LinkError::kBadField},
      {{6, 1, 0, 0, 0, 0, 0, 1, 0, 1}, LinkError::kBadField},  // flow interval 0
      {wheels_kind_two, LinkError::kBadField},
      {short_uwb, LinkError::kBadLength},
  };
  for (size_t i = 0; i < cases.size(); ++i) {
    FrameDecoder decoder;
    EXPECT_EQ(Push(decoder, Stuffed(WithCrc(cases[i].first))).errors, std::vector<LinkError>{cases[i].second})
        << "case " << i;
  }
}

TEST(RadioLinkTest, SensorLinkFieldsAreBigEndian) {
  const std::vector<uint8_t> bytes = Encoded(MakeFlow(9, FlowPayload{0x01020304, 0x0506, -2}));
  // 0x00, COBS code, kind 6, sequence 9, interval, dx, dy, CRC, 0x00: no zero in this body.
  ASSERT_EQ(bytes.size(), 2u + 1 + 12);
  const std::vector<uint8_t> payload(bytes.begin() + 4, bytes.begin() + 12);
  EXPECT_EQ(payload, (std::vector<uint8_t>{0x01, 0x02, 0x03, 0x04, 0x05, 0x06, 0xFF, 0xFE}));
}

TEST(RadioLinkTest, DecoderNamesEachMalformedFrame) {
  struct Case {
    std::vector<uint8_t> wire;
    LinkError expected;
  };
  std::vector<uint8_t> bad_crc = WithCrc({1, 5, 0x42});
  bad_crc.back() ^= 0x01;
  const std::vector<Case> cases = {
      {Stuffed(bad_crc), LinkError::kCrcMismatch},
      {Stuffed(WithCrc({10, 1, 0x42})), LinkError::kUnknownKind},
      {Stuffed(WithCrc({3, 1, 0, 0})), LinkError::kBadLength},    // send-done with two payload bytes
      {Stuffed(WithCrc({2, 1, 0xC0})), LinkError::kBadLength},    // received beacon with no beacon
      {Stuffed(WithCrc({3, 1})), LinkError::kBadLength},          // send-done with no status
      {Stuffed(WithCrc({9, 1, 0, 0, 0x4E})), LinkError::kBadLength},  // start with three bytes of run_ms
      {Stuffed(WithCrc({3, 1, 3})), LinkError::kBadField},        // status 3
      {Stuffed(WithCrc({4, 1, 2})), LinkError::kBadField},        // version 2
      {{0x00, 0x05, 0x41, 0x00}, LinkError::kBadStuffing},        // block of 4 ends after 1
      {{0x00, 0x02, 0x01, 0x00}, LinkError::kFrameTooShort},
  };
  for (size_t i = 0; i < cases.size(); ++i) {
    FrameDecoder decoder;
    const Feed feed = Push(decoder, cases[i].wire);
    EXPECT_TRUE(feed.frames.empty()) << "case " << i;
    ASSERT_EQ(feed.errors.size(), 1u) << "case " << i;
    EXPECT_EQ(feed.errors[0], cases[i].expected) << "case " << i << ": " << ToString(feed.errors[0]);
    EXPECT_EQ(feed.error_offsets[0], 1u) << "case " << i;
  }
  std::vector<uint8_t> beacon_too_long = {1, 1};
  const std::vector<uint8_t> beacon = SampleBeacon(kMaxLinkBeaconBytes);
  beacon_too_long.insert(beacon_too_long.end(), beacon.begin(), beacon.end());
  beacon_too_long.push_back(7);
  FrameDecoder decoder;
  EXPECT_EQ(Push(decoder, Stuffed(WithCrc(beacon_too_long))).errors, std::vector<LinkError>{LinkError::kBadLength});
}

TEST(RadioLinkTest, ErrorOffsetPointsAtTheRejectedFrame) {
  const std::vector<uint8_t> good = Encoded(MakeHello(3));
  std::vector<uint8_t> bad = Encoded(MakeSendDone(4, SendStatus::kSent));
  bad[3] ^= 0x10;
  std::vector<uint8_t> stream = good;
  stream.insert(stream.end(), bad.begin(), bad.end());
  FrameDecoder decoder;
  const Feed feed = Push(decoder, stream);
  ASSERT_EQ(feed.frames.size(), 1u);
  ASSERT_EQ(feed.errors.size(), 1u);
  EXPECT_EQ(feed.errors[0], LinkError::kCrcMismatch);
  EXPECT_EQ(feed.error_offsets[0], good.size() + 1);  // the byte after the bad frame's leading 0x00
  EXPECT_EQ(decoder.counters().crc_mismatches, 1u);
}

TEST(RadioLinkTest, EmptyGapsAreNotErrors) {
  FrameDecoder decoder;
  const Feed feed = Push(decoder, {0x00, 0x00, 0x00, 0x00});
  EXPECT_TRUE(feed.frames.empty());
  EXPECT_TRUE(feed.errors.empty());
}

TEST(RadioLinkTest, OverlongRunIsRejectedOnceThenDiscardedUntilTheNextDelimiter) {
  // A delimiter, then 200 non-zero bytes (built whole: GCC 12's -Warray-bounds
  // misfires on inserting into a one-byte vector at -O3 for the M4).
  std::vector<uint8_t> stream(201, 0x7E);
  stream[0] = 0x00;
  const Frame frame = MakeHello(9);
  const std::vector<uint8_t> good = Encoded(frame);
  stream.insert(stream.end(), good.begin(), good.end());
  FrameDecoder decoder;
  const Feed feed = Push(decoder, stream);
  EXPECT_EQ(feed.errors, std::vector<LinkError>{LinkError::kFrameTooLong});
  ASSERT_EQ(feed.frames.size(), 1u);
  EXPECT_EQ(feed.frames[0], frame);
  EXPECT_GT(decoder.counters().bytes_discarded, 100u);
}

TEST(RadioLinkTest, ResynchronisesAfterRandomGarbage) {
  std::mt19937 random(20261125);
  const Frame frame = MakeReceivedBeacon(42, -60, SampleBeacon(29));
  const std::vector<uint8_t> good = Encoded(frame);
  for (int trial = 0; trial < 500; ++trial) {
    std::vector<uint8_t> stream(random() % 120);
    for (uint8_t& byte : stream) byte = static_cast<uint8_t>(random() & 0xFF);
    stream.insert(stream.end(), good.begin(), good.end());
    FrameDecoder decoder;
    const Feed feed = Push(decoder, stream);
    ASSERT_FALSE(feed.frames.empty()) << "trial " << trial;
    EXPECT_EQ(feed.frames.back(), frame) << "trial " << trial;
  }
}

// Includes the trailing delimiter turned into 0x01, which appends a 0x00 to
// the body: a CRC without a final xor (CRC-16/CCITT-FALSE) keeps its zero
// residue through appended zeros and accepted that frame with a beacon one
// byte longer.
TEST(RadioLinkTest, EverySingleBitFlipIsCaughtAndTheNextFrameArrives) {
  const Frame next = MakeHello(77);
  const std::vector<uint8_t> next_bytes = Encoded(next);
  for (const Frame& frame : EveryKind()) {
    const std::vector<uint8_t> bytes = Encoded(frame);
    for (size_t i = 0; i < bytes.size(); ++i) {
      for (int bit = 0; bit < 8; ++bit) {
        std::vector<uint8_t> stream = bytes;
        stream[i] ^= static_cast<uint8_t>(1u << bit);
        stream.insert(stream.end(), next_bytes.begin(), next_bytes.end());
        FrameDecoder decoder;
        const Feed feed = Push(decoder, stream);
        ASSERT_EQ(feed.frames.size(), 1u) << ToString(frame.kind) << " byte " << i << " bit " << bit;
        EXPECT_EQ(feed.frames[0], next);
      }
    }
  }
}

TEST(RadioLinkTest, ResetDiscardsAHalfReceivedFrame) {
  const std::vector<uint8_t> bytes = Encoded(MakeHello(1));
  FrameDecoder decoder;
  for (size_t i = 0; i < bytes.size() / 2; ++i) EXPECT_EQ(decoder.Push(bytes[i]), DecodeEvent::kNone);
  decoder.Reset();
  const Feed feed = Push(decoder, bytes);
  ASSERT_EQ(feed.frames.size(), 1u);
  EXPECT_TRUE(feed.errors.empty());
  EXPECT_EQ(decoder.counters().frames, 1u);
}

}  // namespace
}  // namespace syrof::firmware::drivers
