// firmware-swarm.json. The layout (one key a line, the small objects on one
// line) and the number formats (the stream's six significant digits; the
// optional seconds and metres with six decimals) are what the file has
// always held, so runs written before read the same.
#include "syrof/firmware/swarm/firmware_metrics.h"

#include <ostream>
#include <sstream>

namespace syrof::firmware::swarm {

namespace {

std::string FixedOrNull(const std::optional<double>& value) {
  return value ? std::to_string(*value) : std::string("null");
}

std::string IntegerOrNull(const std::optional<int64_t>& value) {
  return value ? std::to_string(*value) : std::string("null");
}

const char* Bool(bool value) { return value ? "true" : "false"; }

const char* FaultKind(HostAction::Kind kind) {
  switch (kind) {
    case HostAction::Kind::kKill:
      return "crash";
    case HostAction::Kind::kStop:
      return "pause";
    default:
      return "join";
  }
}

// "faults": one object a line per crash, pause and join; `[]` when none.
void WriteFaults(std::ostream& out, const std::vector<FaultOutcome>& faults) {
  out << "[";
  bool first = true;
  for (const FaultOutcome& outcome : faults) {
    out << (first ? "\n    " : ",\n    ") << "{\"kind\": \"" << FaultKind(outcome.kind)
        << "\", \"robot\": " << outcome.robot << ", \"at_s\": " << static_cast<double>(outcome.at_ns) * 1e-9
        << ", \"ok\": " << Bool(outcome.ok) << ", \"done_s\": "
        << (outcome.done_ns ? std::to_string(static_cast<double>(*outcome.done_ns) * 1e-9) : std::string("null"));
    if (outcome.kind == HostAction::Kind::kStop) {
      out << ", \"guest_gap_ms\": " << IntegerOrNull(outcome.guest_gap_ms)
          << ", \"world_gap_ms\": " << IntegerOrNull(outcome.world_gap_ms)
          << ", \"rejoined_as_joiner\": " << Bool(outcome.rejoined_as_joiner);
    }
    out << "}";
    first = false;
  }
  if (!first) out << "\n  ";
  out << "]";
}

}  // namespace

std::string ToJson(const FirmwareMetrics& metrics) {
  const BeaconCounts& beacons = metrics.beacons;
  const SensorLinkCounts& sensor_link = metrics.sensor_link;
  std::ostringstream out;
  out << "{\n  \"robots\": " << metrics.robots << ",\n  \"seconds\": " << metrics.seconds
      << ",\n  \"loss\": " << metrics.loss << ",\n  \"seed\": " << metrics.seed << ",\n  \"align\": " << Bool(metrics.align)
      << ",\n  \"latency_ms\": " << metrics.latency_ms << ",\n  \"timing\": \"" << metrics.timing
      << "\",\n  \"wall_seconds\": " << metrics.wall_seconds
      << ",\n  \"all_cooperative_s\": " << FixedOrNull(metrics.all_cooperative_s)
      << ",\n  \"p3_violations\": " << metrics.p3_violations
      << ",\n  \"cooperative_starts\": " << metrics.cooperative_starts;
  out << ",\n  \"beacons\": {\"offered\": " << beacons.offered << ", \"delivered\": " << beacons.delivered
      << ", \"link_errors\": " << beacons.link_errors << ", \"late\": " << beacons.late
      << ", \"past_their_round\": " << beacons.past_their_round << "}";
  out << ",\n  \"sensor_link\": {\"imu\": " << sensor_link.imu << ", \"flow\": " << sensor_link.flow
      << ", \"uwb\": " << sensor_link.uwb << ", \"not_encoded\": " << sensor_link.not_encoded
      << ", \"drives\": " << sensor_link.drives << ", \"rejected_from_robots\": " << sensor_link.rejected_from_robots
      << "}";
  out << ",\n  \"scenario\": \"" << metrics.scenario << "\", \"replay_rounds\": " << metrics.replay_rounds;
  out << ",\n  \"estimation\": {\"samples\": " << metrics.estimation.samples
      << ", \"rmse_m\": " << FixedOrNull(metrics.estimation.rmse_m)
      << ", \"max_m\": " << FixedOrNull(metrics.estimation.max_m) << "}";
  out << ",\n  \"exit_statuses\": [";
  for (size_t i = 0; i < metrics.exit_statuses.size(); ++i) out << (i ? ", " : "") << metrics.exit_statuses[i];
  out << "],\n  \"partitioned_beacons\": " << metrics.partitioned_beacons << ",\n  \"stress\": ";
  if (metrics.stress) {
    const StressFigures& stress = *metrics.stress;
    out << "{\"seed\": " << stress.seed << ", \"stalls_per_second\": " << stress.stalls_per_second
        << ", \"qemu_stalls\": " << stress.qemu_stalls << ", \"host_stalls\": " << stress.host_stalls
        << ", \"late_fraction\": " << stress.late_fraction << ", \"late_beacons\": " << stress.late_beacons
        << ", \"cpu_quota_permille\": " << stress.cpu_quota_permille << "}";
  } else {
    out << "null";
  }
  out << ",\n  \"faults\": ";
  WriteFaults(out, metrics.faults);
  const ActivationFigures& activation = metrics.activation;
  out << ",\n  \"activation\": {\"model\": \"" << activation.model << "\", \"starts\": " << activation.starts
      << ", \"looked\": " << activation.looked << ", \"against_schedule\": " << activation.against_schedule << "}";
  out << "\n}\n";
  return out.str();
}

}  // namespace syrof::firmware::swarm
