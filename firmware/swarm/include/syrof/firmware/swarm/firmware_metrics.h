// What the emulated swarm measured of itself, beside the lab's metrics
// (metrics.json): the firmware runtime's own figures, as DDS has
// lab::metrics::DdsMetrics. The host fills one FirmwareMetrics at the end of
// a run and ToJson writes it as DIR/firmware-swarm.json (docs/firmware.md,
// "The emulated swarm": what each key means). Pure: no I/O.
#pragma once

#include <cstdint>
#include <optional>
#include <string>
#include <vector>

#include "syrof/firmware/swarm/activation_check.h"
#include "syrof/firmware/swarm/fault_outcomes.h"
#include "syrof/lab/metrics/metrics.h"

namespace syrof::firmware::swarm {

/// The radio channel as the host played it.
struct BeaconCounts {
  int64_t offered = 0;           ///< (beacon, receiver) pairs put to the channel
  int64_t delivered = 0;         ///< of those, the ones it passed
  int64_t link_errors = 0;       ///< radio-link decode errors on the robots' radio UARTs
  int64_t late = 0;              ///< without alignment: reached the host past their delivery instant
  int64_t past_their_round = 0;  ///< without alignment: reached the host past the next round boundary
};

/// Sensor-link frames, summed over the robots (sensor_feed.h).
struct SensorLinkCounts {
  int64_t imu = 0, flow = 0, uwb = 0;  ///< frames sent to the robots
  int64_t not_encoded = 0;             ///< readings the link refused (a non-finite value)
  int64_t drives = 0;                  ///< Drive frames back from the robots
  uint64_t rejected_from_robots = 0;   ///< frames from the robots the link rejected
};

/// The estimation error over the scored robot-rounds (metrics.json's `estimation`).
struct EstimationFigures {
  int64_t samples = 0;
  std::optional<double> rmse_m;
  std::optional<double> max_m;
};

/// --stress: what was played (stress_player.h, lab/sim/stress.h).
struct StressFigures {
  uint64_t seed = 0;
  double stalls_per_second = 0;
  int64_t qemu_stalls = 0;
  int64_t host_stalls = 0;
  double late_fraction = 0;  ///< the fraction of beacons asked to be late
  int64_t late_beacons = 0;  ///< beacons delivered late
  uint32_t cpu_quota_permille = 0;
};

/// Every key of firmware-swarm.json, in its order.
struct FirmwareMetrics {
  uint16_t robots = 0;
  int seconds = 0;
  double loss = 0;
  uint64_t seed = 0;
  bool align = false;
  double latency_ms = 0;
  std::string timing;  ///< "host clock (no -icount)" or "-icount shift=N"
  double wall_seconds = 0;
  std::optional<double> all_cooperative_s;  ///< host time from the world's start; unset: never
  int64_t p3_violations = 0;
  int64_t cooperative_starts = 0;
  BeaconCounts beacons;
  SensorLinkCounts sensor_link;
  std::string scenario;  ///< the scenario's name (letters, digits, '_', '-', '.')
  int64_t replay_rounds = 0;
  EstimationFigures estimation;
  std::vector<int> exit_statuses;  ///< per robot: qemu's exit code, 128 + a signal, -1 never reaped
  int64_t partitioned_beacons = 0;
  std::optional<StressFigures> stress;  ///< unset without --stress
  std::vector<FaultOutcome> faults;     ///< one per crash, pause and join
  ActivationFigures activation;         ///< activation_check.h
};

/// firmware-swarm.json: the keys in FirmwareMetrics' order, a trailing
/// newline; an unset optional is null.
std::string ToJson(const FirmwareMetrics& metrics);

}  // namespace syrof::firmware::swarm
