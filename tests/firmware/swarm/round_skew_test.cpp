#include "syrof/firmware/swarm/round_skew.h"

#include <gtest/gtest.h>

#include <vector>

namespace syrof::firmware::swarm {
namespace {

constexpr int64_t kRound = 50'000'000;

std::vector<int64_t> Grid(int64_t offset_ns, int rounds) {
  std::vector<int64_t> times;
  for (int k = 0; k < rounds; ++k) times.push_back(offset_ns + k * kRound);
  return times;
}

TEST(RoundSkewTest, AlignedRobotsHaveNoSkew) {
  const std::vector<std::vector<int64_t>> sends = {Grid(0, 100), Grid(0, 100), Grid(0, 100)};
  const lab::metrics::SkewStats stats = RoundStartSkew(sends, kRound, 0);
  EXPECT_EQ(stats.samples, 200);
  EXPECT_EQ(stats.max_us, 0);
}

TEST(RoundSkewTest, OffsetsAreMeasuredEitherSideAndFoldedToHalfARound) {
  // Robot 1 is 3 ms late, robot 2 4 ms early, robot 3 40 ms late (10 ms
  // early for the next round).
  const std::vector<std::vector<int64_t>> sends = {Grid(10 * kRound, 100), Grid(3'000'000, 120),
                                                   Grid(-4'000'000, 120), Grid(40'000'000, 120)};
  const lab::metrics::SkewStats stats = RoundStartSkew(sends, kRound, 10 * kRound);
  EXPECT_EQ(stats.max_us, 10'000);
  EXPECT_EQ(stats.p50_us, 4'000);
}

TEST(RoundSkewTest, BeaconsBeforeTheStartAreLeftOut) {
  std::vector<int64_t> late = Grid(20'000'000, 10);  // misaligned during the first 10 rounds
  for (int64_t t : Grid(10 * kRound, 50)) late.push_back(t);
  const std::vector<std::vector<int64_t>> sends = {Grid(0, 60), late};
  EXPECT_EQ(RoundStartSkew(sends, kRound, 10 * kRound).max_us, 0);
  EXPECT_EQ(RoundStartSkew(sends, kRound, 0).max_us, 20'000);
}

TEST(RoundSkewTest, NothingToCompareGivesNoSamples) {
  EXPECT_EQ(RoundStartSkew(std::vector<std::vector<int64_t>>{Grid(0, 5)}, kRound, 0).samples, 0);
  EXPECT_EQ(RoundStartSkew(std::vector<std::vector<int64_t>>{{}, Grid(0, 5)}, kRound, 0).samples, 0);
}

}  // namespace
}  // namespace syrof::firmware::swarm
