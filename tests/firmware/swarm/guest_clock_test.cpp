// GuestClockRate: a guest's slowdown from its beacons' host arrival times.
#include "syrof/firmware/swarm/guest_clock.h"

#include <gtest/gtest.h>

namespace syrof::firmware::swarm {
namespace {

constexpr int64_t kRoundNs = 50'000'000;

TEST(GuestClockRateTest, ConvergesToTheGapOverTheRoundAndIgnoresOutliers) {
  GuestClockRate rate(kRoundNs);
  EXPECT_EQ(rate.host_per_guest(), 1.0);
  int64_t t = 1'000'000'000;
  for (int i = 0; i < 100; ++i) {
    rate.OnBeacon(t);
    t += 120'000'000;  // 2.4 x the round
  }
  EXPECT_NEAR(rate.host_per_guest(), 2.4, 0.01);
  EXPECT_NEAR(static_cast<double>(rate.ToHost(25'000'000)), 60e6, 1e6);
  rate.OnBeacon(t + 10 * kRoundNs);  // a stall: ignored
  rate.OnBeacon(t + 10 * kRoundNs + 1'000'000);  // a merged pair: ignored
  EXPECT_NEAR(rate.host_per_guest(), 2.4, 0.01);
}

}  // namespace
}  // namespace syrof::firmware::swarm
