// The stress plan (lab/sim/stress.h): stalls and late samples are functions
// of the seed, within their bounds, off without a seed; the options' checks.
#include "syrof/lab/sim/stress.h"

#include <gtest/gtest.h>

#include <algorithm>

namespace syrof::lab::sim {
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
  EXPECT_FALSE(CheckStressOptions(options).has_value());
  options.min_stall_ms = 300;
  ASSERT_TRUE(CheckStressOptions(options).has_value());
  EXPECT_NE(CheckStressOptions(options)->message.find("min <= max"), std::string::npos);
  options = StressOptions{};
  options.stalls_per_second = -1;
  EXPECT_TRUE(CheckStressOptions(options).has_value());
  options = StressOptions{};
  options.cpu_quota_permille = 1001;
  ASSERT_TRUE(CheckStressOptions(options).has_value());
  EXPECT_NE(CheckStressOptions(options)->message.find("quota"), std::string::npos);
  options.seed = 1;
  EXPECT_TRUE(PlanStalls(options, kNineSeconds, 4).empty());  // refused options plan nothing
}

TEST(SampleDelayTest, AboutTheFractionOfSamplesIsLateWithinTheBoundsAndTheSameOnARerun) {
  StressOptions options;
  options.seed = 11;
  options.delayed_fraction = 0.1;
  int late = 0;
  for (int64_t round = 0; round < 2000; ++round) {
    const int64_t delay = SampleDelayNs(options, DelayedStream::kBeacon, 2, 3, round);
    EXPECT_EQ(SampleDelayNs(options, DelayedStream::kBeacon, 2, 3, round), delay);
    if (delay == 0) continue;
    ++late;
    EXPECT_GE(delay, 10'000'000);
    EXPECT_LE(delay, 200'000'000);
    EXPECT_EQ(delay % 1'000'000, 0);
  }
  EXPECT_GT(late, 150);  // about 200 of 2000
  EXPECT_LT(late, 250);
}

TEST(SampleDelayTest, EachLinkAndStreamIsLateOnItsOwn) {
  StressOptions options;
  options.seed = 11;
  options.delayed_fraction = 0.5;
  int differ_by_receiver = 0, differ_by_stream = 0, differ_by_seed = 0;
  for (int64_t stamp = 0; stamp < 200; ++stamp) {
    const int64_t a = SampleDelayNs(options, DelayedStream::kBeacon, 1, 2, stamp);
    differ_by_receiver += a != SampleDelayNs(options, DelayedStream::kBeacon, 1, 3, stamp);
    differ_by_stream += a != SampleDelayNs(options, DelayedStream::kImu, 1, 2, stamp);
    StressOptions other = options;
    other.seed = 12;
    differ_by_seed += a != SampleDelayNs(other, DelayedStream::kBeacon, 1, 2, stamp);
  }
  EXPECT_GT(differ_by_receiver, 50);
  EXPECT_GT(differ_by_stream, 50);
  EXPECT_GT(differ_by_seed, 50);
}

TEST(SampleDelayTest, NothingIsLateWithoutASeedAFractionOrWithRefusedOptions) {
  StressOptions options;
  options.delayed_fraction = 1;
  EXPECT_EQ(SampleDelayNs(options, DelayedStream::kUwb, kFromWorld, 0, 123), 0);  // no seed
  options.seed = 4;
  EXPECT_GT(SampleDelayNs(options, DelayedStream::kUwb, kFromWorld, 0, 123), 0);  // every sample at 1
  options.delayed_fraction = 0;
  EXPECT_EQ(SampleDelayNs(options, DelayedStream::kUwb, kFromWorld, 0, 123), 0);
  options.delayed_fraction = 1;
  options.min_delay_ms = 500;  // above max_delay_ms
  ASSERT_TRUE(CheckStressOptions(options).has_value());
  EXPECT_NE(CheckStressOptions(options)->message.find("sample delays"), std::string::npos);
  EXPECT_EQ(SampleDelayNs(options, DelayedStream::kUwb, kFromWorld, 0, 123), 0);
  options = StressOptions{};
  options.delayed_fraction = 1.5;
  ASSERT_TRUE(CheckStressOptions(options).has_value());
  EXPECT_NE(CheckStressOptions(options)->message.find("fraction"), std::string::npos);
}

}  // namespace
}  // namespace syrof::lab::sim
