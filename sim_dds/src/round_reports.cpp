#include "round_reports.h"

#include <algorithm>
#include <optional>
#include <string>

#include "syrof/app/call_status.h"
#include "syrof/lab/metrics/agreement.h"
#include "syrof/lab/sim/run_parts.h"
#include "syrof/motion/safety_filter.h"
#include "syrof/sim_dds/topics.h"
#include "take_samples.h"

namespace syrof::sim_dds {

namespace replay = lab::replay;

void RoundReportBook::Reading::AddEvent(replay::EventKind kind, int64_t time_ns, uint16_t robot, uint16_t epoch,
                                        uint8_t mode, uint16_t other) {
  replay::Event e{};
  e.kind = kind;
  e.robot = robot;
  e.other = other;
  e.epoch = epoch;
  e.mode = mode;
  e.time_ns = time_ns;
  common.events.push_back(e);
}

void RoundReportBook::Take(dds_entity_t reader, int64_t start_ns, RoundGrid& grid, int64_t first_open) {
  const uint16_t robots = loop_.player().robot_count();
  TakeSamples<syrof_msg_dds__Report_>(reader, [&](const syrof_msg_dds__Report_& s, const dds_sample_info_t&) {
    if (s.run_id != run_id_) {
      ++other_runs_;
      return;
    }
    if (s.robot >= robots) {
      ++rejected_;
      return;
    }
    DecodedReport decoded = DecodeReport(s.kind, std::span<const uint8_t>(s.body._buffer, s.body._length), robots);
    if (!decoded.body) {
      ++rejected_;
      log_ << "syrof swarm: robot " << s.robot << "'s report " << s.sequence_number
           << " refused: " << decoded.error->ToString() << "\n";
      return;
    }
    PlacedReport received{s.robot, s.robot_time_ns - start_ns, std::move(*decoded.body)};
    const int64_t round = received.body.kind == ReportKind::kRound
                              ? static_cast<int64_t>(received.body.round.round)
                              : grid.RoundAt(s.robot_time_ns + grid.round_ns() / 2);
    if (align_ && received.body.kind == ReportKind::kRound) {
      grid.NoteRound(s.robot, round, received.body.round.activation_ns);
    }
    if (round < first_open) {
      ++late_;
      return;
    }
    Add(round, std::move(received));
  });
}

lab::sim::RemoteRound RoundReportBook::Read(int64_t round, int64_t start_ns) {
  std::vector<PlacedReport> reports;
  if (auto it = by_round_.find(round); it != by_round_.end()) {
    reports = std::move(it->second);
    by_round_.erase(it);
  }
  std::stable_sort(reports.begin(), reports.end(),
                   [](const PlacedReport& a, const PlacedReport& b) { return a.robot < b.robot; });
  Reading read;
  for (const PlacedReport& r : reports) ReadOne(round, start_ns, r, read);
  CountDeliveries(round, read);
  return std::move(read.common);
}

// Events are stamped with the robot's newest round report before this one.
void RoundReportBook::ReadOne(int64_t round, int64_t start_ns, const PlacedReport& r, Reading& read) {
  const lab::sim::RemoteRobotState& last = loop_.robot(r.robot);
  const uint16_t epoch = last.reported ? last.epoch : 0;
  const uint8_t mode = last.reported ? last.epoch_mode : 1;
  lab::metrics::Collector& collector = loop_.recorder().collector();
  switch (r.body.kind) {
    case ReportKind::kEpochStart:
      loop_.recorder().OnEpochStart(r.robot, round, r.time_ns, r.body.ldmap);
      read.AddEvent(replay::EventKind::kEpochStart, r.time_ns, r.robot, r.body.ldmap.epoch,
                    static_cast<uint8_t>(r.body.ldmap.mode));
      read.common.maps.push_back(replay::RobotMap{r.robot, lab::sim::ToEpochMap(r.body.ldmap)});
      break;
    case ReportKind::kMembership:
      collector.OnMembership(r.robot, round, r.body.removed, r.body.joined);
      for (const uint16_t m : r.body.removed) read.AddEvent(replay::EventKind::kMemberRemoved, r.time_ns, r.robot, epoch, mode, m);
      for (const uint16_t m : r.body.joined) read.AddEvent(replay::EventKind::kMemberJoined, r.time_ns, r.robot, epoch, mode, m);
      break;
    case ReportKind::kBecameJoiner:
      read.AddEvent(replay::EventKind::kBecameJoiner, r.time_ns, r.robot, epoch, mode);
      break;
    case ReportKind::kAppFault:
      collector.OnAppFault(lab::metrics::AppFault{r.robot, app::ToString(static_cast<app::Callback>(r.body.callback)),
                                                  r.body.epoch, r.time_ns,
                                                  app::ToString(static_cast<app::Verdict>(r.body.verdict)), r.body.text});
      read.AddEvent(replay::EventKind::kAppFault, r.time_ns, r.robot, r.body.epoch, mode);
      loop_.player().NoteAppFault(r.robot);
      break;
    case ReportKind::kInvalidCommand:
      collector.OnInvalidCommand(r.robot, r.body.epoch, r.body.text);
      break;
    case ReportKind::kPayloadRefused:
      collector.OnPayloadRefused(r.robot, r.body.epoch, std::to_string(r.body.length) + " bytes");
      break;
    case ReportKind::kSafety: {
      const bool wall = r.body.other == motion::kWallObstacle;
      collector.OnSafetyIntervention(r.body.time_ns - start_ns, r.robot,
                                     wall ? std::nullopt : std::optional<uint16_t>(r.body.other));
      read.AddEvent(replay::EventKind::kSafetyIntervention, r.body.time_ns - start_ns, r.robot, epoch, mode,
                    wall ? replay::kNoRobot : r.body.other);
      break;
    }
    case ReportKind::kPrecaution: {
      const bool wall = r.body.other == motion::kWallObstacle;
      collector.OnSafetyPrecaution(r.robot, wall ? std::nullopt : std::optional<uint16_t>(r.body.other));
      break;
    }
    case ReportKind::kRound: {
      const RoundReport& report = r.body.round;
      loop_.NoteRound(r.robot, lab::sim::RemoteRobotState{true, report.status, report.phase, report.epoch_mode,
                                                          report.estimate_valid != 0, report.epoch, report.est_x_m,
                                                          report.est_y_m, report.est_heading_rad});
      read.common.activations_ns.push_back(report.activation_ns);
      read.senders.set(r.robot);
      read.heard.emplace_back(r.robot, report.heard_in_round);
      if (report.status == 0) read.common.phase_boundaries_ns.push_back(report.activation_ns - start_ns);
      break;
    }
    case ReportKind::kAppState: {
      const AppStateReport& a = r.body.app_state;
      using Call = lab::metrics::AgreementTracker::Call;
      loop_.recorder().OnAppState(r.robot, round, a.new_round ? Call::kNewRound : Call::kEndOfRound, a.epoch,
                                  a.cooperative, a.map_fingerprint, a.state);
      break;
    }
  }
}

// In-round delivery: each robot that reported this round could have
// heard, within the round before, the beacon of every other robot that
// sent one then; its report says whose it did hear.
void RoundReportBook::CountDeliveries(int64_t round, const Reading& read) {
  if (auto previous = round_senders_.find(round - 1); previous != round_senders_.end()) {
    for (const auto& [receiver, heard_set] : read.heard) {
      wire::MemberSet expected = previous->second;
      expected.reset(receiver);
      wire::MemberSet delivered = heard_set;
      delivered &= expected;
      expected_deliveries_ += expected.count();
      in_round_deliveries_ += delivered.count();
    }
    round_senders_.erase(previous);
  }
  round_senders_[round] = read.senders;
}

}  // namespace syrof::sim_dds
