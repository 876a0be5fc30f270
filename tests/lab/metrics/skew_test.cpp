// SkewOf: the round-start skew figures both runtimes outside the lab give.
#include <gtest/gtest.h>

#include <cstdint>
#include <vector>

#include "syrof/lab/metrics/metrics.h"

namespace syrof::lab::metrics {
namespace {

TEST(SkewOfTest, PercentilesAreNearestRanksInMicroseconds) {
  std::vector<int64_t> skews_ns;
  for (int64_t k = 200; k >= 1; --k) skews_ns.push_back(k * 1000);  // 200 .. 1 us, in no order SkewOf needs

  const SkewStats stats = SkewOf(skews_ns);

  EXPECT_EQ(stats.samples, 200);
  EXPECT_EQ(stats.p50_us, 100);  // the 100th smallest
  EXPECT_EQ(stats.p99_us, 198);  // the 198th
  EXPECT_EQ(stats.max_us, 200);
}

// Of an even count, p50 is the lower middle sample (the firmware's median
// took the upper one before both runtimes shared this definition).
TEST(SkewOfTest, TheMedianOfAnEvenCountIsTheLowerMiddleSample) {
  const SkewStats stats = SkewOf({4'000, 1'000, 3'000, 2'000});
  EXPECT_EQ(stats.p50_us, 2);
  EXPECT_EQ(stats.p99_us, 4);
  EXPECT_EQ(stats.max_us, 4);
}

TEST(SkewOfTest, OneSampleIsEveryFigure) {
  const SkewStats stats = SkewOf({1'500});
  EXPECT_EQ(stats.samples, 1);
  EXPECT_EQ(stats.p50_us, 1.5);
  EXPECT_EQ(stats.p99_us, 1.5);
  EXPECT_EQ(stats.max_us, 1.5);
}

TEST(SkewOfTest, NoSamplesGiveZeros) {
  const SkewStats stats = SkewOf({});
  EXPECT_EQ(stats.samples, 0);
  EXPECT_EQ(stats.p50_us, 0);
  EXPECT_EQ(stats.p99_us, 0);
  EXPECT_EQ(stats.max_us, 0);
}

}  // namespace
}  // namespace syrof::lab::metrics
