// DS-TWR arithmetic against simulated exchanges: each device keeps its own
// 40-bit clock (an offset, a drift, truncation to whole counts, wrap-around)
// and its antennas add delays the timestamps do not show. The distance comes
// back within what the 15.65 ps counts allow.
#include "syrof/firmware/drivers/dw1000_ranging.h"

#include <gtest/gtest.h>

#include <array>
#include <cmath>
#include <cstdint>
#include <vector>

namespace syrof::firmware::drivers {
namespace {

using dw1000::kSpeedOfLightMps;
using dw1000::kTickSeconds;
using dw1000::kTimestampMask;

// One count is 4.69 mm of flight. Six truncated timestamps put at most a
// few counts of error into the four intervals; the formula divides it down
// to about one count, so 1 cm is the math's accuracy with margin.
constexpr double kToleranceM = 0.01;

struct Device {
  double drift = 0;          // the clock runs (1 + drift) times true time
  uint64_t offset = 0;       // its count at true time 0
  AntennaDelay antenna{};    // what its antenna adds, unseen by its timestamps

  uint64_t Count(double true_seconds) const {
    const double local = true_seconds * (1.0 + drift) / kTickSeconds;
    return (offset + static_cast<uint64_t>(std::floor(local))) & kTimestampMask;
  }
  double TicksToSeconds(double local_ticks) const { return local_ticks * kTickSeconds / (1.0 + drift); }
};

// One exchange at true time `start_s`, `distance_m` apart; each side replies
// after its own reply time measured on its own clock.
DsTwrTimestamps Exchange(const Device& tag, const Device& anchor, double distance_m, double start_s,
                         double anchor_reply_s, double tag_reply_s) {
  const double flight = distance_m / kSpeedOfLightMps;
  const double tag_tx_delay = tag.TicksToSeconds(tag.antenna.tx_ticks);
  const double tag_rx_delay = tag.TicksToSeconds(tag.antenna.rx_ticks);
  const double anchor_tx_delay = anchor.TicksToSeconds(anchor.antenna.tx_ticks);
  const double anchor_rx_delay = anchor.TicksToSeconds(anchor.antenna.rx_ticks);
  DsTwrTimestamps t;
  // Transmit timestamps are taken before the antenna, receive timestamps after it.
  const double poll_leaves = start_s + tag_tx_delay;
  const double poll_stamped = poll_leaves + flight + anchor_rx_delay;
  const double response_stamped = poll_stamped + anchor_reply_s / (1.0 + anchor.drift);
  const double response_heard = response_stamped + anchor_tx_delay + flight + tag_rx_delay;
  const double final_stamped = response_heard + tag_reply_s / (1.0 + tag.drift);
  const double final_heard = final_stamped + tag_tx_delay + flight + anchor_rx_delay;
  t.poll_tx = tag.Count(start_s);
  t.poll_rx = anchor.Count(poll_stamped);
  t.response_tx = anchor.Count(response_stamped);
  t.response_rx = tag.Count(response_heard);
  t.final_tx = tag.Count(final_stamped);
  t.final_rx = anchor.Count(final_heard);
  return t;
}

TEST(Dw1000RangingTest, ReadsTimestampsLeastSignificantByteFirst) {
  const std::array<uint8_t, 5> bytes = {0x01, 0x02, 0x03, 0x04, 0xF5};
  EXPECT_EQ(dw1000::TimestampFromBytes(bytes), 0xF504030201u);
}

TEST(Dw1000RangingTest, IntervalsWrapAt40Bits) {
  EXPECT_EQ(dw1000::TicksBetween(kTimestampMask - 9, 10), 20);
  EXPECT_EQ(dw1000::TicksBetween(100, 350), 250);
  EXPECT_EQ(dw1000::TicksBetween(5, 5), 0);
}

TEST(Dw1000RangingTest, IdealClocksGiveTheDistance) {
  const Device tag;
  const Device anchor;
  for (const double distance : {0.3, 1.0, 2.5, 5.66, 12.0, 40.0}) {
    const auto range = DsTwrRangeMetres(Exchange(tag, anchor, distance, 0.001, 300e-6, 300e-6), {}, {});
    ASSERT_TRUE(range.ok());
    EXPECT_NEAR(range.value(), distance, kToleranceM) << distance;
  }
}

TEST(Dw1000RangingTest, DriftingOffsetClocksAndUnequalRepliesStillGiveTheDistance) {
  // ±20 ppm crystals, arbitrary offsets, reply times 0.25 ms and 2.5 ms: a
  // single-sided exchange would be off by 2.5 ms * 40 ppm / 2 * c, about 15 m.
  const Device tag{20e-6, 0x12'3456'789Aull, {}};
  const Device anchor{-20e-6, 0xAB'CDEF'0123ull, {}};
  for (const double distance : {0.5, 3.0, 5.0, 25.0}) {
    for (const auto& [anchor_reply, tag_reply] : {std::pair{250e-6, 2.5e-3}, std::pair{2.5e-3, 250e-6}}) {
      const DsTwrTimestamps t = Exchange(tag, anchor, distance, 0.25, anchor_reply, tag_reply);
      const auto range = DsTwrRangeMetres(t, {}, {});
      ASSERT_TRUE(range.ok());
      EXPECT_NEAR(range.value(), distance, kToleranceM) << distance << " " << anchor_reply;
      // What a single-sided exchange would have said, to show the drift matters.
      const double single_sided = (static_cast<double>(dw1000::TicksBetween(t.poll_tx, t.response_rx)) -
                                   static_cast<double>(dw1000::TicksBetween(t.poll_rx, t.response_tx))) /
                                  2 * kTickSeconds * kSpeedOfLightMps;
      EXPECT_GT(std::abs(single_sided - distance), 1.0);
    }
  }
}

TEST(Dw1000RangingTest, TimestampsThatWrapMidExchange) {
  // The tag's clock wraps between poll and response, the anchor's between response and final.
  const double start_s = 0.5;
  Device tag{5e-6, 0, {}};
  tag.offset = (kTimestampMask + 1 - tag.Count(start_s + 100e-6)) & kTimestampMask;
  Device anchor{-7e-6, 0, {}};
  anchor.offset = (kTimestampMask + 1 - anchor.Count(start_s + 600e-6)) & kTimestampMask;
  const DsTwrTimestamps t = Exchange(tag, anchor, 4.2, start_s, 500e-6, 500e-6);
  ASSERT_GT(t.poll_tx, t.response_rx);  // the wrap really happened
  ASSERT_GT(t.response_tx, t.final_rx);
  const auto range = DsTwrRangeMetres(t, {}, {});
  ASSERT_TRUE(range.ok());
  EXPECT_NEAR(range.value(), 4.2, kToleranceM);
}

TEST(Dw1000RangingTest, AntennaDelaysAreTakenOut) {
  // About 16450 counts per device (the DW1000's usual total), split between
  // transmit and receive: 77 m of flight if left in.
  const Device tag{3e-6, 1000, {8200, 8250}};
  const Device anchor{-4e-6, 99'000, {8230, 8190}};
  const DsTwrTimestamps t = Exchange(tag, anchor, 2.0, 0.01, 400e-6, 900e-6);
  const auto corrected = DsTwrRangeMetres(t, tag.antenna, anchor.antenna);
  ASSERT_TRUE(corrected.ok());
  EXPECT_NEAR(corrected.value(), 2.0, kToleranceM);
  const auto uncorrected = DsTwrRangeMetres(t, {}, {});
  ASSERT_TRUE(uncorrected.ok());
  EXPECT_GT(uncorrected.value() - 2.0, 50.0);
}

TEST(Dw1000RangingTest, RejectsImpossibleIntervals) {
  const Device tag;
  const Device anchor;
  DsTwrTimestamps t = Exchange(tag, anchor, 2.0, 0.001, 300e-6, 300e-6);
  DsTwrTimestamps swapped = t;
  std::swap(swapped.poll_tx, swapped.response_rx);  // wraps to almost 2^40
  EXPECT_EQ(DsTwrTimeOfFlightTicks(swapped, {}, {}).error(), DriverError::kIntervalOutOfRange);
  DsTwrTimestamps same = t;
  same.final_tx = same.response_rx;
  EXPECT_EQ(DsTwrTimeOfFlightTicks(same, {}, {}).error(), DriverError::kIntervalOutOfRange);
  DsTwrTimestamps slow = t;
  slow.final_rx = (slow.response_tx + dw1000::kMaxIntervalTicks + 1) & kTimestampMask;
  EXPECT_EQ(DsTwrTimeOfFlightTicks(slow, {}, {}).error(), DriverError::kIntervalOutOfRange);
}

// The default arena's anchors (core/estimation/arena.h) and a robot's antenna at 0.10 m.
constexpr std::array<std::array<double, 3>, 4> kAnchors = {{{0, 0, 0}, {4, 4, 0}, {0, 4, 2}, {4, 0, 2}}};

double DistanceTo(const std::array<double, 3>& anchor, double x, double y) {
  return std::sqrt((anchor[0] - x) * (anchor[0] - x) + (anchor[1] - y) * (anchor[1] - y) +
                   (anchor[2] - 0.1) * (anchor[2] - 0.1));
}

TEST(UwbSweepTest, SweepOverTheArenaMarksFailedExchanges) {
  UwbSweepConfig config;
  config.tag = {8200, 8250};
  const Device tag{12e-6, 0xFF'FFF0'0000ull, config.tag};
  std::array<AnchorExchange, 4> exchanges{};
  for (size_t i = 0; i < 4; ++i) {
    const Device anchor{-15e-6 + 8e-6 * static_cast<double>(i), 0x1000ull * (i + 1), {8210, 8230}};
    config.anchors[i] = anchor.antenna;
    exchanges[i].completed = true;
    exchanges[i].timestamps =
        Exchange(tag, anchor, DistanceTo(kAnchors[i], 1.0, 2.5), 0.1 + 0.005 * static_cast<double>(i), 350e-6,
                 1.2e-3);
  }
  exchanges[2].completed = false;  // no response from anchor 2
  auto created = UwbSweep::Create(config);
  ASSERT_TRUE(created.ok());
  UwbSweep sweep = created.value();

  const estimation::UwbReading reading = sweep.Finish(exchanges, 100'000'000);

  EXPECT_EQ(reading.timestamp_ns, 100'000'000);
  EXPECT_EQ(reading.valid_mask, 0b1011u);
  EXPECT_EQ(reading.sweep, 0u);
  for (const size_t i : {0u, 1u, 3u}) EXPECT_NEAR(reading.range_m[i], DistanceTo(kAnchors[i], 1.0, 2.5), kToleranceM);
  EXPECT_EQ(reading.range_m[2], 0.0f);
  EXPECT_EQ(sweep.failed_exchanges(), 1u);

  // A corrupt report and a range past the limit are rejected; the counter moves on.
  exchanges[2].completed = true;
  std::swap(exchanges[2].timestamps.poll_rx, exchanges[2].timestamps.response_tx);
  config.max_range_m = 3.0f;  // anchors 1 and 3 are 3.36 m and 4.34 m away, anchor 0 2.69 m
  UwbSweep limited = UwbSweep::Create(config).value();
  const estimation::UwbReading second = limited.Finish(exchanges, 200'000'000);
  EXPECT_EQ(second.valid_mask, 0b0001u);
  EXPECT_EQ(limited.rejected_ranges(), 3u);
  EXPECT_EQ(limited.failed_exchanges(), 0u);
  EXPECT_EQ(limited.Finish(exchanges, 300'000'000).sweep, 1u);
}

TEST(UwbSweepTest, WrongExchangeCountGivesNoRanges) {
  UwbSweep sweep = UwbSweep::Create(UwbSweepConfig{}).value();
  const std::array<AnchorExchange, 3> three{};
  EXPECT_EQ(sweep.Finish(three, 0).valid_mask, 0u);
}

TEST(UwbSweepTest, RejectsBadConfigurations) {
  UwbSweepConfig config;
  config.anchor_count = 0;
  EXPECT_EQ(UwbSweep::Create(config).error(), DriverError::kBadConfig);
  config.anchor_count = estimation::kMaxAnchors + 1;
  EXPECT_EQ(UwbSweep::Create(config).error(), DriverError::kBadConfig);
  config.anchor_count = 4;
  config.min_range_m = 5.0f;
  config.max_range_m = 5.0f;
  EXPECT_EQ(UwbSweep::Create(config).error(), DriverError::kBadConfig);
}

}  // namespace
}  // namespace syrof::firmware::drivers
