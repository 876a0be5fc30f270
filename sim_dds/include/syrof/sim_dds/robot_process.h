// The robot process, syrof-robot: one scenario robot's software
// (core/runtime's Robot on the POSIX port, with its own broker) as its own
// process on DDS (docs/dds.md, "Running a swarm on one machine").
//
//   - sensor drivers: Imu_/Flow_/Uwb_ samples for this robot, stamped with
//     the robot's port clock on arrival and published on its broker exactly
//     as lab/sensors' SensorPublishers does;
//   - actuator driver: the drive topic's latest command, written as Drive_;
//   - radio: BeaconRadio on rt/syrof/beacon (the lab's channel model in the
//     receiver);
//   - observer: every event the lab's observer gets, plus one observation a
//     round, as Report_ samples (report_codec.h); Status_ at start-up and
//     once a second;
//   - rounds: on the grid of the world's Control_ start time
//     (PosixPort::StartAt on CLOCK_MONOTONIC).
// Its RobotConfig is the lab's for the same scenario robot
// (lab::sim::RobotConfigFor); the app is a built-in one or a student library
// through the app host, as `syrof run --app` runs it.
//
// Lifetime: it dies with its parent (PR_SET_PDEATHSIG, and a check of the
// parent's pid), and exits when Control_ says stop, when the world's
// participant has been gone for kWorldLostNs, or on SIGINT/SIGTERM.
#pragma once

#include <cstdint>
#include <optional>
#include <ostream>
#include <string>
#include <vector>

#include "syrof/app_host/app_supply.h"
#include "syrof/lab/base/error.h"
#include "syrof/lab/scenario/scenario.h"
#include "syrof/lab/sim/stress.h"

namespace syrof::sim_dds {

/// What syrof-robot is told on its command line.
struct RobotProcessOptions {
  std::string scenario_path;
  lab::scenario::Overrides overrides;  ///< the same the world loaded the scenario with
  uint16_t robot = 0;
  uint64_t run_id = 0;
  uint32_t domain_id = 0;
  std::string interface = "lo";        ///< CycloneOptions::interface
  std::string log_directory;           ///< a library app's host log goes to <dir>/<id>.log; empty: none
  int64_t parent_pid = 0;              ///< exit if the parent is no longer this process (0: no check)
  /// The robot's task threads at SCHED_FIFO priorities (PosixPortOptions::
  /// realtime_priorities); refused without CAP_SYS_NICE, and said so.
  bool realtime = false;
  /// Rounds aligned from the beacons heard (RobotConfig::align_rounds,
  /// docs/clocks.md) rather than held on the world's start grid alone.
  bool align_rounds = false;
  /// The run's start read from the control sample's CLOCK_REALTIME instant
  /// (hosts whose clocks are kept in sync) instead of its CLOCK_MONOTONIC one
  /// (meaningful on one host only).
  bool realtime_start = false;
  /// The start this robot reads is this far off the world's (within
  /// +-kMaxClockOffsetUs): a host whose clock is not in sync with the
  /// others', for tests of align_rounds on one machine.
  int64_t clock_offset_us = 0;
  /// The stress's late samples (lab/sim/stress.h, SampleDelayNs): with a
  /// seed, the robot holds that fraction of the beacons and sensor readings
  /// it takes before it handles them, as a network that delivers them late
  /// (docs/dds.md, "Stress"). Only the seed and the delay fields are passed.
  lab::sim::StressOptions stress;
};

inline constexpr int64_t kMaxClockOffsetUs = 10'000'000;

/// The arguments (argv[1..]) that make syrof-robot run `options`.
std::vector<std::string> RobotArguments(const RobotProcessOptions& options);

/// Parses them back; an error names the argument.
struct ParsedRobotArguments {
  std::optional<RobotProcessOptions> options;
  std::optional<lab::Error> error;
  bool ok() const { return options.has_value(); }
};
ParsedRobotArguments ParseRobotArguments(const std::vector<std::string>& arguments);

/// What a beacon's trip from one robot process's round boundary to another's
/// receive takes on loopback (bench_sim_dds_beacon_latency: p50 121 us):
/// the delay round alignment expects on an aligned link.
inline constexpr int64_t kBeaconLatencyNs = 150'000;

/// The world's participant gone for this long (its liveliness lost): the
/// robot stops.
inline constexpr int64_t kWorldLostNs = 3'000'000'000;

/// Robot `options.robot`'s apps, as every runtime sets them up
/// (app_host::AppsFor): the scenario's built-in app, or its library with the
/// scenario's params and inputs, the log folder, and the limits `syrof run`
/// gives the same scenario (HostLimits::ForBudgets: an unset wall cap is 4x
/// the CPU budget when that is more than the default).
app_host::AppsResult RobotApps(const lab::scenario::Scenario& scenario, const RobotProcessOptions& options);

/// Runs the robot until the world stops it. 0 on a clean stop, 2 on bad
/// input (scenario, robot id, app), 1 on a DDS or system failure; the reason
/// goes to `err`.
int RunRobotProcess(const RobotProcessOptions& options, std::ostream& err);

}  // namespace syrof::sim_dds
