#include "syrof/lab/live/round_ring.h"

#include <gtest/gtest.h>

#include <memory>
#include <string>

namespace syrof::lab::live {
namespace {

constexpr int64_t kRingRoundNs = 50'000'000;

std::shared_ptr<const std::string> Text(uint64_t n) { return std::make_shared<const std::string>(std::to_string(n)); }

TEST(RoundRing, KeepsTheLastSpanOfWorldTime) {
  RoundRing ring(60'000'000'000, 100'000, 1u << 30);
  for (uint64_t n = 0; n < 2000; ++n) ring.Push(static_cast<int64_t>(n) * kRingRoundNs, Text(n));  // 100 s
  EXPECT_EQ(ring.end(), 2000u);
  EXPECT_EQ(ring.size(), 1201u);  // 60 s of 50 ms rounds, both ends included
  EXPECT_EQ(ring.begin(), 799u);
  const RoundRing::Taken first = ring.Take(ring.begin(), 1);
  ASSERT_EQ(first.texts.size(), 1u);
  EXPECT_EQ(*first.texts[0], "799");
}

TEST(RoundRing, AReaderBehindTheStartSkipsToItAndIsToldHowFar) {
  RoundRing ring(1'000'000'000, 100'000, 1u << 30);
  for (uint64_t n = 0; n < 100; ++n) ring.Push(static_cast<int64_t>(n) * kRingRoundNs, Text(n));
  const RoundRing::Taken taken = ring.Take(10, 5);
  EXPECT_EQ(taken.skipped, ring.begin() - 10);
  ASSERT_EQ(taken.texts.size(), 5u);
  EXPECT_EQ(*taken.texts[0], std::to_string(ring.begin()));
  EXPECT_EQ(taken.next, ring.begin() + 5);
}

TEST(RoundRing, AReaderAtTheEndGetsNothingAndKeepsItsCursor) {
  RoundRing ring(1'000'000'000, 100, 1u << 30);
  ring.Push(0, Text(0));
  const RoundRing::Taken taken = ring.Take(1, 10);
  EXPECT_TRUE(taken.texts.empty());
  EXPECT_EQ(taken.next, 1u);
  EXPECT_EQ(taken.skipped, 0u);
}

TEST(RoundRing, IsBoundedInRoundsAndBytesButKeepsTheNewest) {
  RoundRing by_rounds(1'000'000'000'000, 10, 1u << 30);
  for (uint64_t n = 0; n < 50; ++n) by_rounds.Push(0, Text(n));
  EXPECT_EQ(by_rounds.size(), 10u);
  EXPECT_EQ(by_rounds.begin(), 40u);

  RoundRing by_bytes(1'000'000'000'000, 1000, 100);
  for (uint64_t n = 0; n < 50; ++n) by_bytes.Push(0, std::make_shared<const std::string>(30, 'x'));
  EXPECT_LE(by_bytes.bytes(), 100u);
  EXPECT_EQ(by_bytes.size(), 3u);
  by_bytes.Push(0, std::make_shared<const std::string>(500, 'y'));  // larger than the bound: still held
  EXPECT_EQ(by_bytes.size(), 1u);
  EXPECT_EQ(by_bytes.end(), 51u);
}

}  // namespace
}  // namespace syrof::lab::live
