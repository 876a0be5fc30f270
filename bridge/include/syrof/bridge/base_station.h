// The base station: what the bridge (`syrof-bridge`, docs/bridge.md) makes
// of the bytes a base-station radio hands it. Pure: no I/O, no clock, no
// threads, no DDS; the program around it reads the link and says when a
// radio round ends.
//
//   BaseStation station(config, header, {&replay_sink, &live_sink}, {&dds_output});
//   station.Push(bytes_read);         // any split of the stream, any garbage
//   station.EndRound(time_ns);        // every radio round (the caller's clock)
//   station.Finish(true);
//
// The link is the radio link's framing (docs/radio-link.md, FrameDecoder).
// A ReceivedBeacon frame's beacon is decoded with wire::Decode for the
// configured swarm (docs/beacon.md), as every robot and the DDS sample
// checks decode it; an accepted beacon becomes that robot's latest word and
// goes to every BeaconOutput. Frames of other kinds are counted and
// ignored. Everything refused is counted by its reason (Rejections) and
// changes nothing else: not the robots' state, not the rounds, not what the
// outputs and sinks receive.
//
// Each EndRound hands every RoundSink (lab/replay/round_sink.h; the replay
// writer, the live page) one RobotFrame per robot of the header, from what
// its latest beacon says (the mode: its epoch's, which VOTE beacons do not carry) (the robot's own estimate: the bridge has no
// ground truth, so the true pose fields repeat the estimate), and the
// round's events: EPOCH_START when a robot's epoch changes, MEMBER_JOINED /
// MEMBER_REMOVED when the view a robot votes for (its VOTE beacons' set)
// gains or loses a robot. Presence: ABSENT until a robot is first heard,
// RUNNING while it was heard in the last `silent_rounds` rounds, CRASHED
// once it has been silent longer (RUNNING again when it is heard again: a
// base station cannot tell a crash from a broken link).
#pragma once

#include <array>
#include <cstdint>
#include <span>
#include <vector>

#include "syrof/firmware/drivers/radio_link.h"
#include "syrof/lab/replay/replay.h"
#include "syrof/lab/replay/round_sink.h"
#include "syrof/wire/beacon.h"
#include "syrof/wire/wire_error.h"

namespace syrof::bridge {

/// Receives every accepted beacon (the DDS publisher, a test's recorder).
/// Called during Push, on the caller's thread; `wire_bytes` is valid for
/// the call only.
class BeaconOutput {
 public:
  virtual ~BeaconOutput() = default;
  /// `round`: the station's round in progress (BaseStation::round()).
  virtual void OnBeacon(const wire::Beacon& beacon, std::span<const uint8_t> wire_bytes, int8_t rssi_dbm,
                        uint32_t round) = 0;
};

struct StationConfig {
  /// Rounds a robot may go unheard and still be RUNNING; after that it is
  /// CRASHED (silent). The synchronizer's F (sync::Config::silence_rounds).
  uint16_t silent_rounds = 6;
  /// The rounds follow the stream, not a clock: a round ends just before a
  /// beacon from a robot already heard in it (every robot sends one beacon
  /// a round), and round r then ends at (r + 1) * the header's radio
  /// round. For recorded captures (`--input FILE`); live links end rounds
  /// on the wall clock.
  bool rounds_from_stream = false;
};

/// Beacon-decoder reasons counted (wire::WireError values, kOk unused).
inline constexpr size_t kWireErrors = static_cast<size_t>(wire::WireError::kRelayOutOfRange) + 1;
/// Link reasons counted (firmware::drivers::LinkError values, kOk unused).
inline constexpr size_t kLinkErrors = static_cast<size_t>(firmware::drivers::LinkError::kFrameTooShort) + 1;
/// Frame kinds counted (FrameKind values 1 .. 9; index 0 unused).
inline constexpr size_t kFrameKinds = static_cast<size_t>(firmware::drivers::FrameKind::kStart) + 1;

/// What was refused, by reason. Nothing else of the station changes when
/// one of these rises.
struct Rejections {
  std::array<uint64_t, kLinkErrors> frames{};   ///< damaged frames, by LinkError (bad COBS, CRC, length, kind, ...)
  std::array<uint64_t, kWireErrors> beacons{};  ///< ReceivedBeacon frames whose beacon wire::Decode refused, by WireError
  uint64_t bytes_discarded = 0;                 ///< bytes skipped while looking for a frame's start (0x00)

  /// Damaged frames plus refused beacons (bytes_discarded not included).
  uint64_t total() const;
  friend bool operator==(const Rejections&, const Rejections&) = default;
};

/// What was accepted and ignored.
struct StationCounts {
  uint64_t bytes = 0;                          ///< link bytes pushed
  uint64_t frames = 0;                         ///< valid frames, any kind
  std::array<uint64_t, kFrameKinds> by_kind{}; ///< valid frames by FrameKind value
  uint64_t beacons = 0;                        ///< beacons accepted (ReceivedBeacon frames that decoded)
  uint32_t rounds = 0;                         ///< rounds ended
  uint64_t events = 0;                         ///< events handed to the sinks
  friend bool operator==(const StationCounts&, const StationCounts&) = default;
};

/// One robot as the station knows it.
struct HeardRobot {
  bool heard = false;             ///< at least one beacon accepted
  bool joining = false;           ///< its latest beacon was presence-only (a joiner's position report)
  bool has_sync_state = false;    ///< a beacon that is not presence-only was accepted
  /// The mode of the epoch it is in: its PROGRESS and WAIT beacons carry it;
  /// a VOTE beacon's mode is its vote for the next epoch (docs/protocol.md,
  /// "Beacon"), so it changes this only when it is the first heard of an epoch.
  wire::Mode epoch_mode = wire::Mode::kCooperative;
  wire::Beacon latest{};          ///< its latest beacon; a presence-only one changes only the pose
  int8_t rssi_dbm = 0;            ///< the latest beacon's RSSI
  uint32_t last_heard_round = 0;  ///< the round it was last heard in
  uint64_t beacons = 0;           ///< beacons accepted from it
  uint32_t epoch_starts = 0;      ///< EPOCH_START events recorded for it
  uint32_t cooperative_starts = 0;  ///< of which in COOPERATIVE mode
  bool has_hears = false;         ///< it sent a PROGRESS beacon
  wire::MemberSet hears;          ///< the set of its latest PROGRESS beacon: whom it hears well (docs/protocol.md, "Connectivity")
  bool has_view = false;          ///< it sent a VOTE beacon
  wire::MemberSet view;           ///< the set of its latest VOTE beacon
};

class BaseStation {
 public:
  /// `header` says which robots there are (ids 0 .. N-1, N <=
  /// wire::kMaxSwarmSize: SYROF_CHECK) and the radio round; beacons are
  /// decoded for a swarm of N. Calls OnHeader on every sink. Sinks and
  /// outputs are not owned and must outlive the station.
  BaseStation(const StationConfig& config, const lab::replay::Header& header,
              std::vector<lab::replay::RoundSink*> sinks, std::vector<BeaconOutput*> outputs);
  BaseStation(const BaseStation&) = delete;
  BaseStation& operator=(const BaseStation&) = delete;

  /// Feeds link bytes, in order; any split, any content.
  void Push(std::span<const uint8_t> bytes);
  /// Ends the round in progress at `time_ns` (not below the previous
  /// round's; the caller's clock) and hands it to the sinks.
  void EndRound(int64_t time_ns);
  /// With rounds_from_stream, ends the round in progress if any beacon was
  /// heard in it. Then OnFinish(complete) on every sink; later calls do nothing.
  void Finish(bool complete);

  /// The round in progress (0 first); stamps the beacons handed to outputs.
  uint32_t round() const { return round_; }
  const Rejections& rejections() const { return rejections_; }
  const StationCounts& counts() const { return counts_; }
  const std::vector<HeardRobot>& robots() const { return robots_; }
  const lab::replay::Header& header() const { return header_; }

 private:
  void OnFrame(const firmware::drivers::Frame& frame);
  void Accept(const wire::Beacon& beacon, std::span<const uint8_t> wire_bytes, int8_t rssi_dbm);
  void AddViewEvents(uint16_t robot, uint16_t epoch, const wire::MemberSet& before, const wire::MemberSet& after,
                     int64_t time_ns);

  const StationConfig config_;
  const lab::replay::Header header_;
  const uint16_t swarm_size_;
  std::vector<lab::replay::RoundSink*> sinks_;
  std::vector<BeaconOutput*> outputs_;
  firmware::drivers::FrameDecoder decoder_;
  firmware::drivers::LinkCounters seen_link_{};  // the decoder's counters at the last Push
  Rejections rejections_;
  StationCounts counts_;
  std::vector<HeardRobot> robots_;
  std::vector<bool> heard_this_round_;
  std::vector<lab::replay::Event> events_;  // the round in progress
  std::vector<lab::replay::RobotFrame> frames_;
  uint32_t round_ = 0;
  int64_t last_time_ns_ = 0;
  bool any_this_round_ = false;
  bool finished_ = false;
};

/// Names for reports: "BadStuffing", ... (LinkError), "Truncated", ...
/// (WireError), "ReceivedBeacon", ... (FrameKind), as their ToString.
const char* LinkReasonName(size_t index);
const char* BeaconReasonName(size_t index);
const char* FrameKindName(size_t index);

}  // namespace syrof::bridge
