// What a robot process tells the world on rt/syrof/report (Report_.body):
// every event the lab's observer gets, plus one observation per round, so
// that the world feeds lab/metrics' Collector exactly as the lab does and
// checks P3 from the very maps the robots handed to newRound.
//
// The body is little-endian, fixed layouts per kind (docs/dds.md, "Reports"):
//   kEpochStart     epoch u16, mode u8, count u16, then per member in id order:
//                   id u16, phase u8, x_mm i16, y_mm i16, heading_mrad i16,
//                   vx_mm_s i16, vy_mm_s i16, payload_length u8, payload[9]
//   kMembership     removed: count u16 + ids u16..., joined: the same
//   kBecameJoiner   (empty)
//   kAppFault       callback u8, epoch u16, verdict u8, detail (rest, text)
//   kInvalidCommand epoch u16, what (rest, text)
//   kPayloadRefused epoch u16, length u32
//   kSafety         time_ns i64 (the robot's monotonic clock), other u16
//   kRound          RoundReport (below): round u32, activation_ns i64, status u8,
//                   phase u8, mode u8, estimate_valid u8, epoch u16, est x, y,
//                   heading f32, beacons_heard u32, heard_in_round (count u16
//                   + ids u16...)
//   kAppState       new_round u8, epoch u16, cooperative u8, map
//                   fingerprint u64, global state u8
//   kPrecaution     as kSafety: a precaution's start, not an intervention's
// A sample is untrusted (any participant may write the topic): Decode checks
// the kind, every length and enum, and says what is wrong.
#pragma once

#include <cstdint>
#include <optional>
#include <span>
#include <string>
#include <vector>

#include "syrof/lab/base/error.h"
#include "syrof/sync/ldmap.h"
#include "syrof/wire/member_set.h"

namespace syrof::sim_dds {

enum class ReportKind : uint8_t {
  kEpochStart = 0,
  kMembership = 1,
  kBecameJoiner = 2,
  kAppFault = 3,
  kInvalidCommand = 4,
  kPayloadRefused = 5,
  kSafety = 6,
  kRound = 7,
  kAppState = 8,
  kPrecaution = 9,
};
inline constexpr uint8_t kReportKinds = 10;

/// A robot at the end of one of its rounds (after the synchronizer's step):
/// what the lab's recorder reads from each robot (observation.h).
struct RoundReport {
  uint32_t round = 0;           ///< on the world's grid: (activation - start) / alpha, rounded
  int64_t activation_ns = 0;    ///< when the round's beacon went out, CLOCK_MONOTONIC (the skew's sample)
  uint8_t status = 1;           ///< sync::Status
  uint8_t phase = 1;            ///< wire::Phase
  uint8_t epoch_mode = 1;       ///< wire::Mode
  uint8_t estimate_valid = 0;   ///< initialized and warmed up
  uint16_t epoch = 0;
  float est_x_m = 0;
  float est_y_m = 0;
  float est_heading_rad = 0;
  uint32_t beacons_heard = 0;   ///< beacons the transport delivered so far (the radio's count, before loss)
  /// The robots whose beacon of the previous round reached this robot within
  /// that round (accepted, before the channel's simulated loss): the world's
  /// in-round delivery ratio compares it with who sent one.
  wire::MemberSet heard_in_round;
};

/// What an app's newRound or endOfRound returned, for app-level agreement
/// (lab/metrics/agreement.h): the lab's RecordingApp feed, over DDS.
struct AppStateReport {
  bool new_round = true;      ///< newRound, else endOfRound
  uint16_t epoch = 0;
  bool cooperative = false;   ///< the map's mode
  uint64_t map_fingerprint = 0;  ///< lab::sim::MapFingerprint of the map the app saw
  uint8_t state = 0;          ///< the global state it returned
};

/// One decoded report body.
struct ReportBody {
  ReportKind kind = ReportKind::kBecameJoiner;
  sync::LDMap ldmap;                     ///< kEpochStart
  wire::MemberSet removed, joined;       ///< kMembership
  uint8_t callback = 0;                  ///< kAppFault: app::Callback
  uint8_t verdict = 0;                   ///< kAppFault: app::Verdict
  uint16_t epoch = 0;                    ///< kAppFault, kInvalidCommand, kPayloadRefused
  std::string text;                      ///< kAppFault's detail, kInvalidCommand's what
  uint32_t length = 0;                   ///< kPayloadRefused
  int64_t time_ns = 0;                   ///< kSafety, kPrecaution
  uint16_t other = 0;                    ///< kSafety, kPrecaution
  RoundReport round;                     ///< kRound
  AppStateReport app_state;              ///< kAppState
};

std::vector<uint8_t> EncodeEpochStart(const sync::LDMap& ldmap);
std::vector<uint8_t> EncodeMembership(const wire::MemberSet& removed, const wire::MemberSet& joined);
std::vector<uint8_t> EncodeAppFault(uint8_t callback, uint16_t epoch, uint8_t verdict, std::string_view detail);
std::vector<uint8_t> EncodeInvalidCommand(uint16_t epoch, std::string_view what);
std::vector<uint8_t> EncodePayloadRefused(uint16_t epoch, uint32_t length);
std::vector<uint8_t> EncodeSafety(int64_t time_ns, uint16_t other);
std::vector<uint8_t> EncodePrecaution(int64_t time_ns, uint16_t other);
std::vector<uint8_t> EncodeRound(const RoundReport& round);
std::vector<uint8_t> EncodeAppState(const AppStateReport& app_state);

/// The body of `kind` (a Report_'s kind byte) or what is wrong with it:
/// where the part of the report ("epoch start", "membership removed"; none
/// for the kind or the length), and the message ("member 70 out of order or
/// at or above the swarm size 8", ...). `swarm_size` bounds every robot id.
struct DecodedReport {
  std::optional<ReportBody> body;
  std::optional<lab::Error> error;
  bool ok() const { return body.has_value(); }
};
DecodedReport DecodeReport(uint8_t kind, std::span<const uint8_t> body, uint16_t swarm_size);

/// Report bodies above this are refused by the writer's type (the IDL's
/// REPORT_MAX_BYTES); an epoch start fits it up to kMaxReportMembers members.
inline constexpr size_t kMaxReportBytes = 8192;
inline constexpr size_t kMaxReportMembers = (kMaxReportBytes - 5) / 23;

}  // namespace syrof::sim_dds
