// The beacon's byte layout, defined once.
//
// DescribeBeacon() lists the fields in wire order with their widths, valid
// ranges and the error for a value outside them. Everything else is derived
// by walking that list with a "codec": the encoder and decoder
// (beacon_codec.h), EncodedSize(), and the layout table that
// RenderLayoutTable() prints for docs/beacon.md. Change the layout here and
// bump kBeaconVersion; nothing else needs to agree by hand.
//
// The layout is a little-endian bit stream: fields are packed from bit 0 of
// byte 0 upward, so a multi-byte integer goes least significant byte first
// and fields narrower than a byte fill a byte from its low bits. Signed fields
// are two's complement. The size depends only on the swarm size N: robot_id
// takes one byte up to 256 robots and two above, and the waiting set takes
// ceil(N/8) bytes.
#pragma once

#include <array>
#include <cstddef>
#include <cstdint>
#include <span>

#include "syrof/base/result.h"
#include "syrof/wire/beacon.h"
#include "syrof/wire/member_set.h"
#include "syrof/wire/wire_error.h"

namespace syrof::wire {

/// A field's name and meaning, for the layout table.
struct FieldInfo {
  const char* name;
  const char* meaning;
};

/// Width of robot_id on the wire: one byte for swarms of up to 256 robots, else two.
constexpr unsigned RobotIdBits(uint16_t swarm_size) { return swarm_size <= 256 ? 8 : 16; }

/// Width of a relay's slot (0 or 1 + a robot id, so swarm size + 1 values):
/// one byte for swarms of up to 255 robots, else two.
constexpr unsigned RelaySlotBits(uint16_t swarm_size) { return swarm_size <= 255 ? 8 : 16; }

/// Bytes of a member set on the wire for a swarm of `swarm_size` robots.
constexpr size_t MemberSetBytes(uint16_t swarm_size) { return (size_t{swarm_size} + 7) / 8; }

/// The layout of version kBeaconVersion for a swarm of `swarm_size` robots
/// (1 .. kMaxSwarmSize, which callers check), in wire order. `beacon` is a
/// Beacon when decoding, a const Beacon otherwise. A Codec provides:
///   constant(info, bits, value, error): a fixed value; any other is `error`.
///   number(info, bits, field): an integer filling its type, 8 * sizeof bits.
///   number(info, bits, field, min, max, error): an integer or enum narrower
///     or equal to its type; a value outside [min, max] is `error`.
///   members(info, set, swarm_size, error): MemberSetBytes() bytes, bit i % 8
///     of byte i / 8 is robot i; a bit for an id >= swarm_size is `error`.
///   bytes(info, array, used, error): the whole array; a non-zero byte at an
///     index >= used is `error`.
/// A decoder fills fields in this order, so a later field may depend on an
/// earlier one (the payload on payload_length). The snapshot's fields keep
/// their own names in the table (x_mm, not snapshot.x_mm).
template <typename Codec, typename BeaconT>
constexpr void DescribeBeacon(Codec& codec, BeaconT& beacon, uint16_t swarm_size) {
  codec.constant({"version", "layout version"}, 8, kBeaconVersion, WireError::kWrongVersion);
  codec.number({"robot_id", "sender's robot id"}, RobotIdBits(swarm_size), beacon.robot_id,
               uint16_t{0}, static_cast<uint16_t>(swarm_size - 1), WireError::kRobotIdOutOfRange);
  codec.number({"epoch", "maneuver number, wraps to 0"}, 16, beacon.epoch);
  codec.number({"phase", "synchronizer phase"}, 2, beacon.phase, Phase::kProgress, Phase::kVote,
               WireError::kPhaseOutOfRange);
  codec.number({"mode", "operation mode"}, 1, beacon.mode, Mode::kCooperative, Mode::kAutonomous,
               WireError::kModeOutOfRange);
  codec.number({"presence_only", "1: a joiner's position report, for safety filters only"}, 1,
               beacon.presence_only, false, true, WireError::kPresenceOutOfRange);
  codec.number({"payload_length", "payload bytes in use"}, 4, beacon.snapshot.payload_length, uint8_t{0},
               uint8_t{kMaxPayloadBytes}, WireError::kPayloadTooLong);
  codec.number({"vote_counter", "rounds counted in VOTE"}, 8, beacon.vote_counter);
  codec.members({"waiting", "WAIT: members known to be waiting; VOTE: the view; PROGRESS: whom the sender hears well"},
                beacon.waiting, swarm_size,
                WireError::kMemberOutOfRange);
  codec.number({"x_mm", "position x, millimetres"}, 16, beacon.snapshot.x_mm);
  codec.number({"y_mm", "position y, millimetres"}, 16, beacon.snapshot.y_mm);
  codec.number({"heading_mrad", "heading, milliradians counter-clockwise from +x"}, 16,
               beacon.snapshot.heading_mrad, kMinHeadingMilliradians, kMaxHeadingMilliradians,
               WireError::kHeadingOutOfRange);
  codec.number({"vx_mm_s", "velocity x, millimetres per second"}, 16, beacon.snapshot.vx_mm_s);
  codec.number({"vy_mm_s", "velocity y, millimetres per second"}, 16, beacon.snapshot.vy_mm_s);
  codec.bytes({"payload", "application bytes, the first payload_length in use"}, beacon.snapshot.payload,
              beacon.snapshot.payload_length, WireError::kNonZeroPadding);
  codec.number({"relay", "0: nothing relayed; else 1 + the id of the robot whose position follows"},
               RelaySlotBits(swarm_size), beacon.relay.slot, uint16_t{0}, swarm_size, WireError::kRelayOutOfRange);
  // Nothing relayed: both coordinates are zero, so the beacon has one encoding.
  const int16_t relay_min = beacon.relay.slot == 0 ? int16_t{0} : kMinRelayUnits;
  const int16_t relay_max = beacon.relay.slot == 0 ? int16_t{0} : kMaxRelayUnits;
  codec.number({"relay_x", "relayed position x, units of 16 mm (0 when relay is 0)"}, 12, beacon.relay.x_16mm,
               relay_min, relay_max, WireError::kRelayOutOfRange);
  codec.number({"relay_y", "relayed position y, units of 16 mm (0 when relay is 0)"}, 12, beacon.relay.y_16mm,
               relay_min, relay_max, WireError::kRelayOutOfRange);
}

namespace detail {

// Counts the bits of the layout; EncodedSize() is this codec.
class BitCounter {
 public:
  constexpr void constant(const FieldInfo&, unsigned bits, uint8_t, WireError) { bits_ += bits; }
  template <typename T>
  constexpr void number(const FieldInfo&, unsigned bits, const T&) {
    bits_ += bits;
  }
  template <typename T>
  constexpr void number(const FieldInfo&, unsigned bits, const T&, T, T, WireError) {
    bits_ += bits;
  }
  constexpr void members(const FieldInfo&, const MemberSet&, uint16_t swarm_size, WireError) {
    bits_ += 8 * MemberSetBytes(swarm_size);
  }
  template <size_t kSize>
  constexpr void bytes(const FieldInfo&, const std::array<uint8_t, kSize>&, uint8_t, WireError) {
    bits_ += 8 * kSize;
  }

  constexpr size_t bits() const { return bits_; }

 private:
  size_t bits_ = 0;
};

}  // namespace detail

/// Bytes of an encoded beacon for a swarm of `swarm_size` robots; 0 when
/// `swarm_size` is 0 or above kMaxSwarmSize.
constexpr size_t EncodedSize(uint16_t swarm_size) {
  if (swarm_size == 0 || swarm_size > kMaxSwarmSize) return 0;
  detail::BitCounter counter;
  const Beacon beacon{};
  DescribeBeacon(counter, beacon, swarm_size);
  return counter.bits() / 8;
}

/// Bytes one radio frame of the robots carries: a BLE legacy advertising
/// payload (the nRF51822's), which the firmware's radio link also bounds
/// (firmware/drivers' kMaxLinkBeaconBytes). A swarm whose beacon is longer
/// runs in the lab and over DDS, not on the robots' radio.
inline constexpr size_t kMaxRadioBeaconBytes = 31;

/// The largest swarm whose beacon fits kMaxRadioBeaconBytes (16 in version 4).
constexpr uint16_t LargestRadioSwarm() {
  uint16_t swarm_size = 0;
  while (swarm_size < kMaxSwarmSize && EncodedSize(static_cast<uint16_t>(swarm_size + 1)) <= kMaxRadioBeaconBytes) {
    ++swarm_size;
  }
  return swarm_size;
}

/// The longest encoding this build can produce: a buffer of this size holds
/// any beacon.
inline constexpr size_t kMaxBeaconBytes = EncodedSize(kMaxSwarmSize);

/// Writes the layout for a swarm of `swarm_size` robots into `out` as a
/// Markdown table (offset, size, field, meaning with the valid range), one row
/// per field and a last row with the total, each line ending in '\n', followed
/// by a terminating NUL. Returns the number of characters before the NUL;
/// kSwarmSizeOutOfRange, or kBufferTooSmall when `out` cannot hold the table
/// (about 1.5 KB).
syrof::base::Result<size_t, WireError> RenderLayoutTable(uint16_t swarm_size,
                                                           std::span<char> out);

}  // namespace syrof::wire
