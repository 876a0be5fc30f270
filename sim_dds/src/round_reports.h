// The robots' Report_ samples of a DDS run read into the world loop
// (lab/sim/remote_world.h): the DDS world's part of recording a round, its
// reports taken, decoded, placed on the grid and parsed into the loop's
// common round report. Internal to sim_dds.
#pragma once

#include <dds/dds.h>

#include <cstdint>
#include <map>
#include <ostream>
#include <utility>
#include <vector>

#include "round_grid.h"
#include "syrof/lab/sim/remote_world.h"
#include "syrof/sim_dds/report_codec.h"
#include "syrof/wire/beacon.h"

namespace syrof::sim_dds {

/// A decoded report placed on the run's grid.
struct PlacedReport {
  uint16_t robot = 0;
  int64_t time_ns = 0;  ///< run time (since the grid's origin)
  ReportBody body;
};

/// Keeps each round's reports until the round is recorded, then reads them,
/// in robot order, into the loop: the collector (epoch starts, membership,
/// app faults, commands, payloads, safety, the apps' returns), the loop's
/// robot states (round reports), the round's common report; and counts the
/// in-round deliveries the round reports say.
class RoundReportBook {
 public:
  /// The reports of run `run_id`; with `align` the robots number their own
  /// rounds and the grid follows them. `loop` and `log` outlive the book.
  RoundReportBook(lab::sim::RemoteWorld& loop, uint64_t run_id, bool align, std::ostream& log)
      : loop_(loop), run_id_(run_id), align_(align), log_(log) {}

  /// Takes the Report_ samples `reader` holds: each of this run is decoded
  /// (a malformed one refused and logged) and kept for its round on `grid`
  /// (a round report's own round, noted on the grid; any other the round
  /// its robot time falls in, rounded). One of a round before `first_open`
  /// (recorded already) is late. `start_ns` is the grid's start.
  void Take(dds_entity_t reader, int64_t start_ns, RoundGrid& grid, int64_t first_open);

  /// Keeps `report` for round `round`.
  void Add(int64_t round, PlacedReport report) { by_round_[round].push_back(std::move(report)); }

  /// Round `round`'s reports, read (and dropped from the book). `start_ns`
  /// is the grid's origin on CLOCK_MONOTONIC, the clock of the reports'
  /// activations and safety times.
  lab::sim::RemoteRound Read(int64_t round, int64_t start_ns);

  /// In-round deliveries over the beacons that could have been delivered
  /// in-round (docs/dds.md, "Reports"); 0 before any.
  double delivery_ratio() const { return expected_deliveries_ > 0 ? in_round_deliveries_ / expected_deliveries_ : 0; }

  /// Samples refused (a robot id out of range, a body that did not
  /// decode), late (their round recorded already) and of another run.
  int64_t rejected() const { return rejected_; }
  int64_t late() const { return late_; }
  int64_t other_runs() const { return other_runs_; }

 private:
  // One round's reports as they are read.
  struct Reading {
    lab::sim::RemoteRound common;
    wire::MemberSet senders;
    std::vector<std::pair<uint16_t, wire::MemberSet>> heard;  // each reporting robot's in-round deliveries

    void AddEvent(lab::replay::EventKind kind, int64_t time_ns, uint16_t robot, uint16_t epoch, uint8_t mode,
                  uint16_t other = lab::replay::kNoRobot);
  };

  void ReadOne(int64_t round, int64_t start_ns, const PlacedReport& r, Reading& read);
  void CountDeliveries(int64_t round, const Reading& read);

  lab::sim::RemoteWorld& loop_;
  const uint64_t run_id_;
  const bool align_;
  std::ostream& log_;
  int64_t rejected_ = 0, late_ = 0, other_runs_ = 0;
  std::map<int64_t, std::vector<PlacedReport>> by_round_;
  std::map<int64_t, wire::MemberSet> round_senders_;  // robots that reported (broadcast) in a round
  double expected_deliveries_ = 0;
  double in_round_deliveries_ = 0;
};

}  // namespace syrof::sim_dds
