// The Teensy 3.2 kernel hardware's time arithmetic (teensy32_hardware.h):
// PIT ticks of the 36 MHz bus clock to nanoseconds, and alarms that never
// fire early. The registers themselves need a Teensy.
#include <gtest/gtest.h>

#include <cstdint>
#include <random>

#include "syrof/firmware/kernel/teensy32_hardware.h"

namespace syrof::firmware::kernel::teensy32 {
namespace {

TEST(Teensy32TimingTest, NineTicksAreExactly250Nanoseconds) {
  EXPECT_EQ(NsFromTicks(0), 0);
  EXPECT_EQ(NsFromTicks(1), 27);  // 27.78 ns, rounded down
  EXPECT_EQ(NsFromTicks(9), 250);
  EXPECT_EQ(NsFromTicks(36'000'000), 1'000'000'000);
  // Past the 32-bit wrap of the PIT (119.3 s) and after a day, still exact.
  EXPECT_EQ(NsFromTicks(uint64_t{36'000'000} * 86'400), int64_t{86'400} * 1'000'000'000);
}

TEST(Teensy32TimingTest, ClockIsMonotonicAndExactRoundedDown) {
  // floor(ticks x 1000 / 36) in plain 64-bit arithmetic, which holds the
  // product up to 2^40 ticks (8.5 hours); NsFromTicks avoids the product so
  // that it never overflows.
  std::mt19937_64 random(20261126);
  std::uniform_int_distribution<uint64_t> ticks_of(0, uint64_t{1} << 40);
  for (int i = 0; i < 10'000; ++i) {
    const uint64_t ticks = ticks_of(random);
    EXPECT_EQ(NsFromTicks(ticks), static_cast<int64_t>(ticks * 1000 / 36)) << ticks;
    EXPECT_LE(NsFromTicks(ticks), NsFromTicks(ticks + 1));
  }
}

TEST(Teensy32TimingTest, AlarmNeverFiresEarly) {
  // The alarm fires AlarmTicks(ahead) ticks after it is set; the clock then
  // reads at least `ahead` later. Every ahead from 1 ns to 10 us, then a
  // seeded sample up to the longest alarm.
  for (int64_t ahead = 1; ahead <= 10'000; ++ahead) {
    const uint32_t ticks = AlarmTicks(ahead);
    ASSERT_GE(NsFromTicks(ticks), ahead) << ahead;
    ASSERT_LT(NsFromTicks(ticks - 1), ahead) << "one tick fewer would do: " << ahead;
  }
  std::mt19937_64 random(7);
  std::uniform_int_distribution<int64_t> ahead_of(1, NsFromTicks(kLongestAlarmTicks));
  for (int i = 0; i < 10'000; ++i) {
    const int64_t ahead = ahead_of(random);
    ASSERT_GE(NsFromTicks(AlarmTicks(ahead)), ahead) << ahead;
  }
}

TEST(Teensy32TimingTest, LongAlarmsAreCappedSoTheClockIsReadOftenEnough) {
  EXPECT_EQ(AlarmTicks(int64_t{10} * 1'000'000'000), kLongestAlarmTicks);
  EXPECT_LT(NsFromTicks(kLongestAlarmTicks), NsFromTicks(uint64_t{1} << 32) / 32);  // far inside one wrap
}

}  // namespace
}  // namespace syrof::firmware::kernel::teensy32
