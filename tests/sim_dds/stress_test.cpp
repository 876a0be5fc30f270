// The stress plan (sim_dds/stress.h): a function of the seed, within its
// bounds, off without a seed; the options' checks.
#include "syrof/sim_dds/stress.h"

#include <gtest/gtest.h>

#include <algorithm>

namespace syrof::sim_dds {
namespace {

constexpr int64_t kNineSeconds = 9'000'000'000;

TEST(StressPlanTest, TheSameSeedGivesTheSamePlanAndAnotherSeedAnother) {
  StressOptions options;
  options.seed = 17;
  const std::vector<Stall> a = PlanStalls(options, kNineSeconds, 6);
  EXPECT_EQ(PlanStalls(options, kNineSeconds, 6), a);
  options.seed = 18;
  EXPECT_NE(PlanStalls(options, kNineSeconds, 6), a);
}

TEST(StressPlanTest, StallsAreSortedWithinTheRunAndTheirBoundsAndHitEveryTarget) {
  StressOptions options;
  options.seed = 3;
  options.stalls_per_second = 40;
  const std::vector<Stall> plan = PlanStalls(options, kNineSeconds, 6);
  ASSERT_EQ(plan.size(), 360u);  // 40 a second for 9 s
  EXPECT_TRUE(std::is_sorted(plan.begin(), plan.end(), [](const Stall& x, const Stall& y) { return x.at_ns < y.at_ns; }));
  std::vector<int> hits(7, 0);
  for (const Stall& stall : plan) {
    EXPECT_GE(stall.at_ns, 0);
    EXPECT_LT(stall.at_ns, kNineSeconds * 95 / 100);
    EXPECT_GE(stall.duration_ns, 10'000'000);
    EXPECT_LE(stall.duration_ns, 200'000'000);
    ASSERT_TRUE(stall.target < 6 || stall.target == kStallWorld);
    ++hits[stall.target == kStallWorld ? 6 : stall.target];
  }
  for (const int h : hits) EXPECT_GT(h, 20);  // about 51 each
}

TEST(StressPlanTest, TheWorldIsLeftAloneWhenAskedAndNothingIsPlannedWithoutASeed) {
  StressOptions options;
  options.seed = 5;
  options.stall_world = false;
  for (const Stall& stall : PlanStalls(options, kNineSeconds, 4)) EXPECT_LT(stall.target, 4);
  options.seed = 0;
  EXPECT_TRUE(PlanStalls(options, kNineSeconds, 4).empty());
}

TEST(StressPlanTest, BadOptionsAreNamed) {
  StressOptions options;
  EXPECT_EQ(CheckStressOptions(options), "");
  options.min_stall_ms = 300;
  EXPECT_NE(CheckStressOptions(options).find("min <= max"), std::string::npos);
  options = StressOptions{};
  options.stalls_per_second = -1;
  EXPECT_NE(CheckStressOptions(options), "");
  options = StressOptions{};
  options.cpu_quota_permille = 1001;
  EXPECT_NE(CheckStressOptions(options).find("quota"), std::string::npos);
  options.seed = 1;
  EXPECT_TRUE(PlanStalls(options, kNineSeconds, 4).empty());  // refused options plan nothing
}

}  // namespace
}  // namespace syrof::sim_dds
