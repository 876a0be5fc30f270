#include "syrof/bridge/base_station.h"

#include <algorithm>
#include <utility>

#include "syrof/base/check.h"
#include "syrof/wire/beacon_codec.h"
#include "syrof/wire/fixed_point.h"

namespace syrof::bridge {

namespace drivers = firmware::drivers;
namespace replay = lab::replay;

uint64_t Rejections::total() const {
  uint64_t sum = 0;
  for (uint64_t count : frames) sum += count;
  for (uint64_t count : beacons) sum += count;
  return sum;
}

BaseStation::BaseStation(const StationConfig& config, const replay::Header& header,
                         std::vector<replay::RoundSink*> sinks, std::vector<BeaconOutput*> outputs)
    : config_(config),
      header_(header),
      swarm_size_(static_cast<uint16_t>(header.robots.size())),
      sinks_(std::move(sinks)),
      outputs_(std::move(outputs)),
      robots_(header.robots.size()),
      heard_this_round_(header.robots.size(), false),
      frames_(header.robots.size()) {
  SYROF_CHECK(!header_.robots.empty() && header_.robots.size() <= wire::kMaxSwarmSize);
  SYROF_CHECK(header_.radio_round_ns > 0);
  for (size_t i = 0; i < header_.robots.size(); ++i) SYROF_CHECK(header_.robots[i].id == i);
  for (replay::RoundSink* sink : sinks_) sink->OnHeader(header_);
}

void BaseStation::Push(std::span<const uint8_t> bytes) {
  if (finished_) return;
  for (uint8_t byte : bytes) {
    const drivers::DecodeEvent event = decoder_.Push(byte);
    if (event == drivers::DecodeEvent::kFrame) {
      OnFrame(decoder_.frame());
    } else if (event == drivers::DecodeEvent::kError) {
      const auto reason = static_cast<size_t>(decoder_.error());
      if (reason < kLinkErrors) ++rejections_.frames[reason];
    }
  }
  counts_.bytes += bytes.size();
  // The decoder's counter wraps at 2^32; the difference still counts right.
  const uint32_t discarded = decoder_.counters().bytes_discarded;
  rejections_.bytes_discarded += static_cast<uint32_t>(discarded - seen_link_.bytes_discarded);
  seen_link_ = decoder_.counters();
}

void BaseStation::OnFrame(const drivers::Frame& frame) {
  ++counts_.frames;
  const auto kind = static_cast<size_t>(frame.kind);
  if (kind < kFrameKinds) ++counts_.by_kind[kind];
  if (frame.kind != drivers::FrameKind::kReceivedBeacon) return;
  const std::span<const uint8_t> wire_bytes(frame.beacon.data(), frame.beacon_length);
  const auto decoded = wire::Decode(wire_bytes, swarm_size_);
  if (!decoded.ok()) {
    const auto reason = static_cast<size_t>(decoded.error());
    if (reason < kWireErrors) ++rejections_.beacons[reason];
    return;
  }
  Accept(decoded.value(), wire_bytes, frame.rssi_dbm);
}

void BaseStation::Accept(const wire::Beacon& beacon, std::span<const uint8_t> wire_bytes, int8_t rssi_dbm) {
  const uint16_t id = beacon.robot_id;
  if (config_.rounds_from_stream && heard_this_round_[id]) {
    EndRound(int64_t{round_ + 1} * header_.radio_round_ns);
  }
  HeardRobot& robot = robots_[id];
  const int64_t round_end_ns = int64_t{round_ + 1} * header_.radio_round_ns;
  if (beacon.presence_only) {
    robot.joining = true;
    robot.latest.snapshot = beacon.snapshot;
  } else {
    if (robot.has_sync_state && beacon.epoch != robot.latest.epoch) {
      events_.push_back(replay::Event{.kind = replay::EventKind::kEpochStart,
                                      .robot = id,
                                      .epoch = beacon.epoch,
                                      .mode = static_cast<uint8_t>(beacon.mode),
                                      .time_ns = round_end_ns});
      ++robot.epoch_starts;
      if (beacon.mode == wire::Mode::kCooperative) ++robot.cooperative_starts;
    }
    if (beacon.phase == wire::Phase::kProgress) {
      robot.hears = beacon.waiting;
      robot.has_hears = true;
    }
    if (beacon.phase == wire::Phase::kVote) {
      if (robot.has_view && robot.view != beacon.waiting) {
        AddViewEvents(id, beacon.epoch, robot.view, beacon.waiting, round_end_ns);
      }
      robot.view = beacon.waiting;
      robot.has_view = true;
    }
    const bool new_epoch = !robot.has_sync_state || beacon.epoch != robot.latest.epoch;
    if (new_epoch || beacon.phase != wire::Phase::kVote) robot.epoch_mode = beacon.mode;
    robot.joining = false;
    robot.latest = beacon;
    robot.has_sync_state = true;
  }
  robot.heard = true;
  robot.rssi_dbm = rssi_dbm;
  robot.last_heard_round = round_;
  ++robot.beacons;
  ++counts_.beacons;
  heard_this_round_[id] = true;
  any_this_round_ = true;
  for (BeaconOutput* output : outputs_) output->OnBeacon(beacon, wire_bytes, rssi_dbm, round_);
}

void BaseStation::AddViewEvents(uint16_t robot, uint16_t epoch, const wire::MemberSet& before,
                                const wire::MemberSet& after, int64_t time_ns) {
  const auto mode = static_cast<uint8_t>(robots_[robot].epoch_mode);
  for (uint16_t member = 0; member < swarm_size_; ++member) {
    const bool was = before.test(member);
    const bool is = after.test(member);
    if (was == is) continue;
    events_.push_back(replay::Event{.kind = is ? replay::EventKind::kMemberJoined : replay::EventKind::kMemberRemoved,
                                    .robot = robot,
                                    .other = member,
                                    .epoch = epoch,
                                    .mode = mode,
                                    .time_ns = time_ns});
  }
}

void BaseStation::EndRound(int64_t time_ns) {
  if (finished_) return;
  time_ns = std::max(time_ns, last_time_ns_);
  last_time_ns_ = time_ns;
  for (uint16_t id = 0; id < swarm_size_; ++id) {
    const HeardRobot& robot = robots_[id];
    replay::RobotFrame& frame = frames_[id];
    frame = replay::RobotFrame{};
    frame.id = id;
    if (!robot.heard) continue;  // ABSENT, all zero
    const bool recent = round_ - robot.last_heard_round <= config_.silent_rounds;
    frame.presence = recent ? replay::Presence::kRunning : replay::Presence::kCrashed;
    frame.status = robot.joining ? 1 : 0;
    if (robot.has_sync_state) {
      frame.phase = static_cast<uint8_t>(robot.latest.phase);
      frame.mode = static_cast<uint8_t>(robot.epoch_mode);
      frame.epoch = robot.latest.epoch;
    }
    const wire::Snapshot& snapshot = robot.latest.snapshot;
    frame.est_x_m = wire::ToMetres(snapshot.x_mm);
    frame.est_y_m = wire::ToMetres(snapshot.y_mm);
    frame.est_heading_rad = wire::ToRadians(snapshot.heading_mrad);
    // No ground truth at a base station: the true pose repeats the estimate.
    frame.true_x_m = frame.est_x_m;
    frame.true_y_m = frame.est_y_m;
    frame.true_heading_rad = frame.est_heading_rad;
  }
  for (replay::Event& event : events_) event.time_ns = time_ns;
  for (replay::RoundSink* sink : sinks_) sink->OnRound(round_, time_ns, frames_, events_, {});
  counts_.events += events_.size();
  ++counts_.rounds;
  ++round_;
  events_.clear();
  std::fill(heard_this_round_.begin(), heard_this_round_.end(), false);
  any_this_round_ = false;
}

void BaseStation::Finish(bool complete) {
  if (finished_) return;
  if (config_.rounds_from_stream && any_this_round_) EndRound(int64_t{round_ + 1} * header_.radio_round_ns);
  finished_ = true;
  for (replay::RoundSink* sink : sinks_) sink->OnFinish(complete);
}

const char* LinkReasonName(size_t index) {
  return drivers::ToString(static_cast<drivers::LinkError>(index));
}
const char* BeaconReasonName(size_t index) { return wire::ToString(static_cast<wire::WireError>(index)); }
const char* FrameKindName(size_t index) { return drivers::ToString(static_cast<drivers::FrameKind>(index)); }

}  // namespace syrof::bridge
