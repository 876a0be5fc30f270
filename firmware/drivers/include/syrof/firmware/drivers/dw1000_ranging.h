// The DWM1000's double-sided two-way ranging (DS-TWR), initiator side: the
// timestamp arithmetic, and a sweep over the arena's anchors that becomes one
// estimation::UwbReading (the topic the lab's simulated UWB publishes;
// core/estimation/messages.h).
//
// One exchange with an anchor (the robot is the initiator, the "tag"):
//
//   tag     poll_tx ----------> poll_rx                anchor
//           response_rx <------ response_tx
//           final_tx ---------> final_rx
//           (the anchor then reports poll_rx, response_tx and final_rx)
//
// With round_a = response_rx - poll_tx, reply_a = final_tx - response_rx (tag's
// clock) and round_b = final_rx - response_tx, reply_b = response_tx - poll_rx
// (anchor's clock), the time of flight is the asymmetric DS-TWR formula
//
//   tof = (round_a * round_b - reply_a * reply_b) / (round_a + round_b + reply_a + reply_b)
//
// which needs no equal reply times and whose error from the two clocks'
// drifts e_a, e_b is about tof * (e_a - e_b) / 2 (sub-millimetre at 20 ppm).
// Facts from Decawave's DW1000 user manual (v2.18): timestamps are 40-bit
// counts of 1 / (128 * 499.2 MHz) = 15.65 ps, wrapping every 17.2 s;
// Decawave's application note APS013 gives the formula.
//
// The exchange's radio frames and the DW1000's SPI registers need the chip
// and are the board's; what is here is pure arithmetic on explicit inputs.
#pragma once

#include <array>
#include <cstddef>
#include <cstdint>
#include <span>

#include "syrof/base/result.h"
#include "syrof/estimation/messages.h"
#include "syrof/firmware/drivers/driver_error.h"

namespace syrof::firmware::drivers {
namespace dw1000 {

/// Timestamps are 40 bits wide.
inline constexpr uint64_t kTimestampMask = (uint64_t{1} << 40) - 1;
/// One timestamp count: 1 / (128 * 499.2 MHz), about 15.65 ps.
inline constexpr double kTickSeconds = 1.0 / (128.0 * 499.2e6);
/// Radio waves in air, m/s (the vacuum speed divided by air's index 1.0003).
inline constexpr double kSpeedOfLightMps = 299'702'547.0;
/// Longest interval of an exchange the arithmetic takes: 2^31 counts (33.6 ms).
/// Bounding it keeps round * round below 2^62, exact in int64.
inline constexpr int64_t kMaxIntervalTicks = int64_t{1} << 31;

/// A 40-bit timestamp from its five register bytes (least significant first).
uint64_t TimestampFromBytes(std::span<const uint8_t, 5> bytes);

/// later - earlier on the 40-bit wrapping clock: counts from `earlier` to
/// `later`, in 0 .. 2^40 - 1 (correct when the true interval is under 17.2 s).
int64_t TicksBetween(uint64_t earlier, uint64_t later);

}  // namespace dw1000

/// The antenna delays of one device, in timestamp counts, that its own
/// timestamps do not already include: a transmit timestamp is that much
/// before the signal leaves the antenna, a receive timestamp that much after
/// it arrived. (A DW1000 told its delays through TX_ANTD and LDE_RXANTD
/// includes them itself; then these are 0.)
struct AntennaDelay {
  uint16_t tx_ticks = 0;
  uint16_t rx_ticks = 0;
};

/// The six raw 40-bit timestamps of one exchange.
struct DsTwrTimestamps {
  uint64_t poll_tx = 0;      ///< tag's clock
  uint64_t response_rx = 0;  ///< tag's clock
  uint64_t final_tx = 0;     ///< tag's clock
  uint64_t poll_rx = 0;      ///< anchor's clock, from its report
  uint64_t response_tx = 0;  ///< anchor's clock
  uint64_t final_rx = 0;     ///< anchor's clock
};

/// The time of flight in timestamp counts (a fraction; may come out slightly
/// negative at very short range). Error: kIntervalOutOfRange when an
/// interval, after the antenna delays, is not in 1 .. kMaxIntervalTicks (a
/// corrupt report, or an exchange slower than 33.6 ms per step).
base::Result<double, DriverError> DsTwrTimeOfFlightTicks(const DsTwrTimestamps& timestamps, AntennaDelay tag,
                                                         AntennaDelay anchor);

/// The same as a distance in metres (time of flight times the speed of light in air).
base::Result<double, DriverError> DsTwrRangeMetres(const DsTwrTimestamps& timestamps, AntennaDelay tag,
                                                   AntennaDelay anchor);

/// One anchor's exchange in a sweep: completed (all three frames and the
/// report arrived in time) with its timestamps, or failed.
struct AnchorExchange {
  bool completed = false;
  DsTwrTimestamps timestamps{};
};

/// What a sweep knows about the arena and the radios.
struct UwbSweepConfig {
  int anchor_count = 4;  ///< 1 .. estimation::kMaxAnchors, in the arena's anchor order
  AntennaDelay tag{};
  std::array<AntennaDelay, estimation::kMaxAnchors> anchors{};
  /// Ranges below min_range_m or above max_range_m are failed exchanges;
  /// ranges in [min_range_m, 0) are reported as 0 (timestamp noise at an
  /// anchor's foot).
  float min_range_m = -0.5f;
  float max_range_m = 100.0f;
};

/// Turns one sweep's exchanges into a UwbReading. Anchor i's bit in
/// valid_mask is set when its exchange completed and gave a range within the
/// limits. Counters of the outcomes are kept for the log.
class UwbSweep {
 public:
  /// Error: kBadConfig when anchor_count is outside 1 .. kMaxAnchors or the
  /// limits are not min_range_m < max_range_m.
  static base::Result<UwbSweep, DriverError> Create(const UwbSweepConfig& config);
  UwbSweep() = default;

  /// The reading for `exchanges` (one per anchor, exchanges.size() ==
  /// anchor_count, else every range is invalid), stamped `timestamp_ns`
  /// (the port clock at the end of the sweep). Counts the sweep.
  estimation::UwbReading Finish(std::span<const AnchorExchange> exchanges, int64_t timestamp_ns);

  uint32_t sweeps() const { return sweeps_; }
  uint32_t failed_exchanges() const { return failed_exchanges_; }  ///< not completed
  uint32_t rejected_ranges() const { return rejected_ranges_; }    ///< completed, but bad intervals or out of limits

 private:
  UwbSweepConfig config_{};
  uint32_t sweeps_ = 0;
  uint32_t failed_exchanges_ = 0;
  uint32_t rejected_ranges_ = 0;
};

}  // namespace syrof::firmware::drivers
