// The robots' Report_ samples of a DDS run read into the world loop
// (lab/sim/remote_world.h): the DDS world's part of recording a round, its
// reports parsed into the loop's common round report. Internal to sim_dds.
#pragma once

#include <cstdint>
#include <map>
#include <utility>
#include <vector>

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
  /// `loop` outlives the book.
  explicit RoundReportBook(lab::sim::RemoteWorld& loop) : loop_(loop) {}

  /// Keeps `report` for round `round`.
  void Add(int64_t round, PlacedReport report) { by_round_[round].push_back(std::move(report)); }

  /// Round `round`'s reports, read (and dropped from the book). `start_ns`
  /// is the grid's origin on CLOCK_MONOTONIC, the clock of the reports'
  /// activations and safety times.
  lab::sim::RemoteRound Read(int64_t round, int64_t start_ns);

  /// In-round deliveries over the beacons that could have been delivered
  /// in-round (docs/dds.md, "Reports"); 0 before any.
  double delivery_ratio() const { return expected_deliveries_ > 0 ? in_round_deliveries_ / expected_deliveries_ : 0; }

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
  std::map<int64_t, std::vector<PlacedReport>> by_round_;
  std::map<int64_t, wire::MemberSet> round_senders_;  // robots that reported (broadcast) in a round
  double expected_deliveries_ = 0;
  double in_round_deliveries_ = 0;
};

}  // namespace syrof::sim_dds
