#include "syrof/firmware/drivers/dw1000_ranging.h"

namespace syrof::firmware::drivers {
namespace dw1000 {

uint64_t TimestampFromBytes(std::span<const uint8_t, 5> bytes) {
  uint64_t value = 0;
  for (size_t i = 5; i-- > 0;) value = (value << 8) | bytes[i];
  return value;
}

int64_t TicksBetween(uint64_t earlier, uint64_t later) {
  return static_cast<int64_t>((later - earlier) & kTimestampMask);
}

}  // namespace dw1000

namespace {
bool IntervalOk(int64_t ticks) { return ticks >= 1 && ticks <= dw1000::kMaxIntervalTicks; }
}  // namespace

base::Result<double, DriverError> DsTwrTimeOfFlightTicks(const DsTwrTimestamps& t, AntennaDelay tag,
                                                         AntennaDelay anchor) {
  using dw1000::TicksBetween;
  const int64_t tag_delays = int64_t{tag.tx_ticks} + tag.rx_ticks;
  const int64_t anchor_delays = int64_t{anchor.tx_ticks} + anchor.rx_ticks;
  // Each interval between the antenna-referred instants: a round (transmit
  // to receive) is shorter than its timestamps say, a reply longer.
  const int64_t round_a = TicksBetween(t.poll_tx, t.response_rx) - tag_delays;
  const int64_t reply_a = TicksBetween(t.response_rx, t.final_tx) + tag_delays;
  const int64_t round_b = TicksBetween(t.response_tx, t.final_rx) - anchor_delays;
  const int64_t reply_b = TicksBetween(t.poll_rx, t.response_tx) + anchor_delays;
  if (!IntervalOk(round_a) || !IntervalOk(reply_a) || !IntervalOk(round_b) || !IntervalOk(reply_b)) {
    return DriverError::kIntervalOutOfRange;
  }
  // Exact in int64: each product is below 2^62.
  const int64_t numerator = round_a * round_b - reply_a * reply_b;
  const int64_t denominator = round_a + round_b + reply_a + reply_b;
  return static_cast<double>(numerator) / static_cast<double>(denominator);
}

base::Result<double, DriverError> DsTwrRangeMetres(const DsTwrTimestamps& timestamps, AntennaDelay tag,
                                                   AntennaDelay anchor) {
  const auto tof = DsTwrTimeOfFlightTicks(timestamps, tag, anchor);
  if (!tof.ok()) return tof.error();
  return tof.value() * dw1000::kTickSeconds * dw1000::kSpeedOfLightMps;
}

base::Result<UwbSweep, DriverError> UwbSweep::Create(const UwbSweepConfig& config) {
  if (config.anchor_count < 1 || config.anchor_count > estimation::kMaxAnchors) return DriverError::kBadConfig;
  if (!(config.min_range_m < config.max_range_m)) return DriverError::kBadConfig;
  UwbSweep sweep;
  sweep.config_ = config;
  return sweep;
}

estimation::UwbReading UwbSweep::Finish(std::span<const AnchorExchange> exchanges, int64_t timestamp_ns) {
  estimation::UwbReading reading{};
  reading.timestamp_ns = timestamp_ns;
  reading.sweep = sweeps_++;
  if (exchanges.size() != static_cast<size_t>(config_.anchor_count)) return reading;
  for (size_t i = 0; i < exchanges.size(); ++i) {
    if (!exchanges[i].completed) {
      ++failed_exchanges_;
      continue;
    }
    const auto range = DsTwrRangeMetres(exchanges[i].timestamps, config_.tag, config_.anchors[i]);
    if (!range.ok() || range.value() < config_.min_range_m || range.value() > config_.max_range_m) {
      ++rejected_ranges_;
      continue;
    }
    reading.range_m[i] = range.value() < 0 ? 0.0f : static_cast<float>(range.value());
    reading.valid_mask |= 1u << i;
  }
  return reading;
}

}  // namespace syrof::firmware::drivers
