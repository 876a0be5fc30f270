#include "syrof/wire/beacon.h"

#include <gtest/gtest.h>

#include <algorithm>
#include <array>
#include <cstdlib>
#include <cstring>

#include "syrof/wire/wire_error.h"

namespace syrof::wire {
namespace {

TEST(BeaconTest, SetPayloadCopiesAndZeroesTheRest) {
  Beacon beacon;
  beacon.snapshot.payload.fill(0xEE);
  const std::array<uint8_t, 3> bytes = {1, 2, 3};

  const WireError error = beacon.snapshot.SetPayload(bytes);

  EXPECT_EQ(error, WireError::kOk);
  EXPECT_EQ(beacon.snapshot.payload_length, 3);
  EXPECT_EQ(beacon.snapshot.payload, (std::array<uint8_t, kMaxPayloadBytes>{1, 2, 3, 0, 0, 0, 0, 0, 0}));
  ASSERT_EQ(beacon.snapshot.payload_bytes().size(), 3u);
  EXPECT_EQ(beacon.snapshot.payload_bytes()[2], 3);
}

TEST(BeaconTest, SetPayloadRefusesMoreThanNineBytes) {
  Beacon beacon;
  const std::array<uint8_t, kMaxPayloadBytes + 1> bytes{};

  const WireError error = beacon.snapshot.SetPayload(bytes);

  EXPECT_EQ(error, WireError::kPayloadTooLong);
  EXPECT_EQ(beacon, Beacon());
}

TEST(BeaconTest, PayloadBytesClampsABadLength) {
  Beacon beacon;
  beacon.snapshot.payload_length = 200;

  EXPECT_EQ(beacon.snapshot.payload_bytes().size(), kMaxPayloadBytes);
}

TEST(BeaconTest, PhaseAndModeHaveProtocolNames) {
  EXPECT_STREQ(ToString(Phase::kProgress), "PROGRESS");
  EXPECT_STREQ(ToString(Phase::kWait), "WAIT");
  EXPECT_STREQ(ToString(Phase::kVote), "VOTE");
  EXPECT_STREQ(ToString(static_cast<Phase>(3)), "?");
  EXPECT_STREQ(ToString(Mode::kCooperative), "COOPERATIVE");
  EXPECT_STREQ(ToString(Mode::kAutonomous), "AUTONOMOUS");
  EXPECT_STREQ(ToString(static_cast<Mode>(2)), "?");
}

TEST(RelayUnitsTest, RoundToTheNearestSixteenMillimetresWithinTheRounding) {
  EXPECT_EQ(ToRelayUnits(0), 0);
  EXPECT_EQ(ToRelayUnits(7), 0);
  EXPECT_EQ(ToRelayUnits(8), 1);  // ties away from zero
  EXPECT_EQ(ToRelayUnits(-8), -1);
  EXPECT_EQ(ToRelayUnits(-7), 0);
  EXPECT_EQ(ToRelayUnits(32767), kMaxRelayUnits);  // 2048 units clamp to the 12 bits
  EXPECT_EQ(ToRelayUnits(-32768), kMinRelayUnits);
  EXPECT_EQ(FromRelayUnits(kMaxRelayUnits), 32752);
  EXPECT_EQ(FromRelayUnits(kMinRelayUnits), -32768);
  // Every millimetre comes back within half a unit an axis, or the clamp's
  // 15 mm at the top: within kRelayRoundingMm, a diagonal included.
  int32_t worst = 0;
  for (int32_t mm = -32768; mm <= 32767; ++mm) {
    const int32_t back = FromRelayUnits(ToRelayUnits(static_cast<int16_t>(mm)));
    ASSERT_LE(std::abs(back - mm), mm > 32752 ? kRelayAxisErrorMm : kRelayUnitMm / 2) << mm;
    worst = std::max(worst, std::abs(back - mm));
  }
  EXPECT_EQ(worst, kRelayAxisErrorMm);
  EXPECT_GE(kRelayRoundingMm * kRelayRoundingMm, 2 * kRelayAxisErrorMm * kRelayAxisErrorMm);
}

TEST(WireErrorTest, EveryErrorHasItsOwnName) {
  constexpr int kErrors = static_cast<int>(WireError::kRelayOutOfRange) + 1;
  for (int first = 0; first < kErrors; ++first) {
    const char* name = ToString(static_cast<WireError>(first));
    EXPECT_STRNE(name, "?") << first;
    for (int second = 0; second < first; ++second) {
      EXPECT_STRNE(name, ToString(static_cast<WireError>(second))) << first << " " << second;
    }
  }
  EXPECT_STREQ(ToString(static_cast<WireError>(kErrors)), "?");
}

}  // namespace
}  // namespace syrof::wire
