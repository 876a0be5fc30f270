// GuestClockRate: a guest's slowdown from (guest time, host time) pairs.
#include "syrof/firmware/swarm/guest_clock.h"

#include <gtest/gtest.h>

namespace syrof::firmware::swarm {
namespace {

constexpr int64_t kMs = 1'000'000;

TEST(GuestClockRateTest, IsTheSlopeOfHostOverGuestTimeOverTheWindow) {
  GuestClockRate rate(2000 * kMs);
  EXPECT_EQ(rate.host_per_guest(), 1.0);
  // A line a round (50 ms of guest time), reaching the host 2.4x later,
  // stamped with up to 3 ms of host jitter and the guest's 1 ms resolution.
  for (int i = 0; i < 200; ++i) {
    const int64_t guest = 1000 * kMs + i * 50 * kMs;
    const int64_t jitter = ((i * 7) % 4) * kMs;
    rate.OnGuestTime(5000 * kMs + guest * 12 / 5 + jitter, guest);
  }
  EXPECT_NEAR(rate.host_per_guest(), 2.4, 0.003);
  EXPECT_NEAR(static_cast<double>(rate.ToHost(25 * kMs)), 60e6, 0.1e6);
}

// The swarm host on the host's clock once measured 0.9936 from lines that
// came unevenly while qemu translated code, and ran the world 25 ms ahead
// of the robots in ten seconds.
TEST(GuestClockRateTest, OnTheHostClockIsOneWhateverTheLinesSay) {
  GuestClockRate measured(2000 * kMs);
  GuestClockRate on_host = GuestClockRate::OnHostClock();
  for (int i = 0; i <= 60; ++i) {  // three seconds, the first lines later and later behind
    const int64_t guest = i * 50 * kMs;
    const int64_t host = 300 * kMs + guest - (60 - i) * kMs / 2;
    measured.OnGuestTime(host, guest);
    on_host.OnGuestTime(host, guest);
  }
  EXPECT_NEAR(measured.host_per_guest(), 1.01, 0.001);
  EXPECT_EQ(on_host.host_per_guest(), 1.0);
  EXPECT_EQ(on_host.ToHost(25 * kMs), 25 * kMs);
}

TEST(GuestClockRateTest, StaysOneUntilATenthOfTheWindowWasSeen) {
  GuestClockRate rate(2000 * kMs);
  rate.OnGuestTime(100 * kMs, 0);
  rate.OnGuestTime(400 * kMs, 150 * kMs);
  EXPECT_EQ(rate.host_per_guest(), 1.0);
  rate.OnGuestTime(500 * kMs, 200 * kMs);
  EXPECT_DOUBLE_EQ(rate.host_per_guest(), 2.0);
}

// The regression: the host used to time the gaps between a robot's beacons,
// which also hold the robot's round shifts. Shifts do not move the guest's
// clock, and the rate from its printed times does not see them.
TEST(GuestClockRateTest, FollowsARateChangeWithinAWindowAndRestartsWhenGuestTimeGoesBack) {
  GuestClockRate rate(1000 * kMs);
  int64_t host = 0;
  int64_t guest = 0;
  for (int i = 0; i < 40; ++i, guest += 50 * kMs, host += 100 * kMs) rate.OnGuestTime(host, guest);
  EXPECT_NEAR(rate.host_per_guest(), 2.0, 1e-9);
  for (int i = 0; i < 40; ++i, guest += 50 * kMs, host += 50 * kMs) rate.OnGuestTime(host, guest);
  EXPECT_NEAR(rate.host_per_guest(), 1.0, 0.06);
  const double before = rate.host_per_guest();
  rate.OnGuestTime(host, 10 * kMs);  // the instance restarted: the last rate holds until a new span
  EXPECT_EQ(rate.host_per_guest(), before);
  rate.OnGuestTime(host + 300 * kMs, 210 * kMs);
  EXPECT_NEAR(rate.host_per_guest(), 1.5, 1e-9);
}

}  // namespace
}  // namespace syrof::firmware::swarm
