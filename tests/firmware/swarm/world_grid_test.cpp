// world_grid.h: the round a beacon was sent in, from when it reached the
// host, on the world's grid from the robot's switch-on.
#include "syrof/firmware/swarm/world_grid.h"

#include <gtest/gtest.h>

namespace syrof::firmware::swarm {
namespace {

constexpr int64_t kGridPeriodNs = 50'000'000;
constexpr double kMsNs = 1e6;

TEST(WorldGridTest, APresentRobotsBeaconsKeyTheirRounds) {
  // Switched on at world 0; the Start frame went 0.3 ms later. Its first
  // round task runs a round after its start: that beacon is round 1's, as
  // the lab's first broadcast (at 50 ms) is asked about round 1.
  const SwitchOn on{0, 0.3 * kMsNs};
  EXPECT_EQ(BeaconRound(on, 52.8 * kMsNs, kGridPeriodNs), 1);
  EXPECT_EQ(BeaconRound(on, 103.0 * kMsNs, kGridPeriodNs), 2);
  EXPECT_DOUBLE_EQ(BoundaryOf(on, 2, kGridPeriodNs), 100.3 * kMsNs);
}

TEST(WorldGridTest, ABeaconTensOfMillisecondsLateKeepsItsRound) {
  // qemu translating the image's code on its first rounds held this one
  // 37 ms: rounding to the nearest boundary (what the host first did) gave
  // round 2.
  const SwitchOn on{0, 0.0};
  EXPECT_EQ(BeaconRound(on, 90.7 * kMsNs, kGridPeriodNs), 1);
  EXPECT_EQ(BeaconRound(on, 94.9 * kMsNs, kGridPeriodNs), 1);
  EXPECT_EQ(BeaconRound(on, 95.1 * kMsNs, kGridPeriodNs), 2);  // past the round, less the tolerance
}

TEST(WorldGridTest, ABoundaryALittleEarlyStillCounts) {
  const SwitchOn on{0, 0.0};
  EXPECT_EQ(BeaconRound(on, 146.0 * kMsNs, kGridPeriodNs), 3);  // 4 ms before round 3's boundary
}

TEST(WorldGridTest, AJoinerCountsFromItsSwitchOnRound) {
  // Switched on at 3 s (round 60), the frame sent 4 ms into the round; its
  // first beacon is round 61's, as a lab joiner switched on at 3 s.
  const SwitchOn on{60, 3'004.0 * kMsNs};
  EXPECT_EQ(BeaconRound(on, 3'056.0 * kMsNs, kGridPeriodNs), 61);
  // Paused from 7 to 8.95 s: the guest's clock ran on, its rounds with it.
  EXPECT_EQ(BeaconRound(on, 9'006.5 * kMsNs, kGridPeriodNs), 180);
  EXPECT_DOUBLE_EQ(BoundaryOf(on, 180, kGridPeriodNs), 9'004.0 * kMsNs);
}

// The round-start skew takes each robot's boundary of the round recorded:
// its beacon of that round, not the next round's that came in early, and
// nothing for a round whose beacon it missed.
TEST(WorldGridTest, TakeBoundaryGivesTheRecordedRoundsAndKeepsLaterOnes) {
  BoundariesByRound boundaries;
  boundaries.emplace(3, 150);
  boundaries.emplace(3, 160);  // a second beacon named round 3: the first counts
  boundaries.emplace(5, 250);
  boundaries.emplace(6, 298);  // in before round 5 is recorded

  EXPECT_EQ(TakeBoundary(boundaries, 3), std::optional<int64_t>(150));
  EXPECT_EQ(TakeBoundary(boundaries, 4), std::nullopt);
  EXPECT_EQ(TakeBoundary(boundaries, 5), std::optional<int64_t>(250));
  EXPECT_EQ(boundaries, (BoundariesByRound{{6, 298}}));
  EXPECT_EQ(TakeBoundary(boundaries, 7), std::nullopt);  // round 6 never recorded: dropped
  EXPECT_TRUE(boundaries.empty());
}

}  // namespace
}  // namespace syrof::firmware::swarm
