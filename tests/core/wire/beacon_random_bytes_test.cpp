// The decoder against seeded random input: it never crashes, returns only its
// documented errors, and whatever it accepts re-encodes to the same bytes.
// tests/fuzz/ runs the same property under libFuzzer.
#include <gtest/gtest.h>

#include <algorithm>
#include <array>
#include <cstdint>
#include <random>
#include <span>
#include <vector>

#include "beacon_test_support.h"
#include "syrof/wire/beacon_codec.h"

namespace syrof::wire {
namespace {

bool is_decoder_error(WireError error) {
  switch (error) {
    case WireError::kTruncated:
    case WireError::kTrailingBytes:
    case WireError::kWrongVersion:
    case WireError::kRobotIdOutOfRange:
    case WireError::kPhaseOutOfRange:
    case WireError::kModeOutOfRange:
    case WireError::kPayloadTooLong:
    case WireError::kMemberOutOfRange:
    case WireError::kHeadingOutOfRange:
    case WireError::kNonZeroPadding:
    case WireError::kRelayOutOfRange: return true;
    default: return false;
  }
}

// Decodes `in`; on success checks that it re-encodes to exactly `in`.
// Returns whether the decoder accepted it.
bool decode_and_check_canonical(std::span<const uint8_t> in, uint16_t swarm_size) {
  const auto beacon = Decode(in, swarm_size);
  if (!beacon.ok()) {
    EXPECT_TRUE(is_decoder_error(beacon.error())) << ToString(beacon.error());
    return false;
  }
  std::array<uint8_t, kMaxBeaconBytes> again{};
  const auto size = Encode(beacon.value(), swarm_size, again);
  EXPECT_TRUE(size.ok()) << ToString(size.error());
  if (!size.ok()) return true;
  const auto reencoded = std::span<const uint8_t>(again).first(size.value());
  EXPECT_TRUE(std::equal(in.begin(), in.end(), reencoded.begin(), reencoded.end()));
  return true;
}

uint16_t random_swarm_size(std::mt19937& random, const std::vector<uint16_t>& sizes) {
  return sizes[std::uniform_int_distribution<size_t>(0, sizes.size() - 1)(random)];
}

TEST(BeaconRandomBytesTest, DecoderSurvivesRandomBuffers) {
  std::mt19937 random(1);
  std::uniform_int_distribution<int> byte(0, 255);
  std::uniform_int_distribution<int> coin(0, 1);
  const std::vector<uint16_t> sizes = testing::swarm_sizes_under_test();
  std::array<uint8_t, kMaxBeaconBytes + 2> buffer{};

  for (int trial = 0; trial < 100000; ++trial) {
    const uint16_t swarm_size = random_swarm_size(random, sizes);
    // Half the buffers get the right length and half the right version, so
    // the decoder is driven past its first checks.
    const size_t length = coin(random) != 0
                              ? EncodedSize(swarm_size)
                              : std::uniform_int_distribution<size_t>(0, buffer.size())(random);
    for (size_t index = 0; index < length; ++index) {
      buffer[index] = static_cast<uint8_t>(byte(random));
    }
    if (length > 0 && coin(random) != 0) buffer[0] = kBeaconVersion;

    decode_and_check_canonical(std::span<const uint8_t>(buffer).first(length), swarm_size);
    if (::testing::Test::HasFailure()) FAIL() << "trial " << trial;
  }
}

TEST(BeaconRandomBytesTest, MutatedBeaconsDecodeOnlyToTheirOwnBytes) {
  std::mt19937 random(2);
  std::uniform_int_distribution<int> byte(0, 255);
  const std::vector<uint16_t> sizes = testing::swarm_sizes_under_test();
  constexpr int kMostChanges = 3;
  std::array<uint8_t, kMaxBeaconBytes + kMostChanges> buffer{};
  int accepted = 0;

  for (int trial = 0; trial < 100000; ++trial) {
    const uint16_t swarm_size = random_swarm_size(random, sizes);
    const Beacon beacon = testing::random_beacon(random, swarm_size);
    const auto size = Encode(beacon, swarm_size, buffer);
    ASSERT_TRUE(size.ok()) << ToString(size.error());
    size_t length = size.value();
    // One to three changes: a flipped bit, a random byte, or a byte more or less.
    const int changes = std::uniform_int_distribution<int>(1, kMostChanges)(random);
    for (int change = 0; change < changes && length > 0; ++change) {
      const size_t index = std::uniform_int_distribution<size_t>(0, length - 1)(random);
      switch (std::uniform_int_distribution<int>(0, 5)(random)) {
        case 0: buffer[length++] = static_cast<uint8_t>(byte(random)); break;
        case 1: --length; break;
        case 2: buffer[index] = static_cast<uint8_t>(byte(random)); break;
        default:
          buffer[index] ^=
              static_cast<uint8_t>(1u << std::uniform_int_distribution<int>(0, 7)(random));
          break;
      }
    }

    if (decode_and_check_canonical(std::span<const uint8_t>(buffer).first(length), swarm_size)) {
      ++accepted;
    }
    if (::testing::Test::HasFailure()) FAIL() << "trial " << trial;
  }

  // Most single-bit flips land in fields with no invalid values.
  EXPECT_GT(accepted, 10000);
}

}  // namespace
}  // namespace syrof::wire
