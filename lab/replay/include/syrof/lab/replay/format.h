// The byte layout of a replay file, version kFormatVersion (docs/replay.md
// has the full table). The writer and the reader both build on these
// constants; tests and other tools use them to craft files by hand.
//
// Every integer is little-endian whatever the host, floats are their IEEE-754
// binary32 bit pattern as a little-endian uint32, signed integers two's
// complement. There is no padding and nothing depends on the host or the
// wall clock, so the same run gives the same bytes.
//
//   file   = header, round*, end
//   header = magic[8] version:u16 seed:u64 radio_round_ns:i64
//            arena_width_m:f32 arena_height_m:f32
//            scenario_name:name app_name:name
//            robot_count:u32 (id:u16 kind:u8 body_radius_m:f32)*robot_count
//            anchor_count:u16 (x_m:f32 y_m:f32)*anchor_count
//            inputs*robot_count message
//            crc:u32
//   inputs = input_count:u8 (name:name value:f64)*input_count
//            (one per robot, in the robots' order)
//   message= kind:u8, then only when kind is 2:
//            field_count:u8 (name:name type:u8)*field_count
//            (kind 0: no format declared, 1: `none`, 2: fields; a field's
//            type is a message::FieldType value)
//   name   = length:u16 bytes[length]
//   round  = 'R' index:u32 time_ns:i64 frame_count:u32 event_count:u32
//            map_count:u32 frame*frame_count event*event_count map*map_count
//            crc:u32
//   frame  = id:u16 state:u8 changed:u8 then, for each bit set in `changed`
//            in bit order, that field: epoch:u16 true_x_m:f32 true_y_m:f32
//            true_heading_rad:f32 est_x_m:f32 est_y_m:f32 est_heading_rad:f32
//   event  = kind:u8 robot:u16 other:u16 epoch:u16 mode:u8 time_ns:i64
//            partition:u16
//   map    = robot:u16 same_as:u16, then only when same_as is 0xFFFF:
//            epoch:u16 mode:u8 member_count:u16 member*member_count
//   member = id:u16 phase:u8 x_mm:i16 y_mm:i16 heading_mrad:i16 vx_mm_s:i16
//            vy_mm_s:i16 payload_length:u8 payload[payload_length]
//   end    = 'E' round_count:u32 event_count:u64 frame_count:u64 crc:u32
//
// Versions 1 to 3 had no inputs and no message. Versions 1 and 2 had no anchors, no map_count, no maps and no event partition field
// (a partition event kept its index in `robot`). A map whose same_as names a
// robot equals that robot's latest map, as of this point of the file.
//
// A field missing from a frame equals the same robot's value in its previous
// frame (all zero before its first), compared bit for bit. Each crc is the
// CRC-32 of the record's bytes before it (the header's from the magic on).
#pragma once

#include <array>
#include <cstddef>
#include <cstdint>
#include <span>

namespace syrof::lab::replay::format {

/// The first eight bytes of every replay file.
inline constexpr std::array<uint8_t, 8> kMagic = {'S', 'Y', 'R', 'O', 'F', 'R', 'P', 'L'};

/// The first byte of each record after the header.
inline constexpr uint8_t kRoundTag = 'R';
inline constexpr uint8_t kEndTag = 'E';

/// Frame `state` byte: presence in bits 0-1, status in bit 2, phase in bits
/// 3-4, mode in bit 5; bits 6-7 are zero.
inline constexpr unsigned kPresenceShift = 0;
inline constexpr unsigned kStatusShift = 2;
inline constexpr unsigned kPhaseShift = 3;
inline constexpr unsigned kModeShift = 5;
inline constexpr uint8_t kStateReservedMask = 0xC0;
inline constexpr uint8_t kMaxStatus = 1;  ///< 0 member, 1 joining
inline constexpr uint8_t kMaxPhase = 2;   ///< wire::Phase::kVote
inline constexpr uint8_t kMaxMode = 1;    ///< wire::Mode::kAutonomous

/// Frame `changed` byte: which fields follow; bit 7 is zero.
inline constexpr uint8_t kChangedEpoch = 1u << 0;
inline constexpr uint8_t kChangedTrueX = 1u << 1;
inline constexpr uint8_t kChangedTrueY = 1u << 2;
inline constexpr uint8_t kChangedTrueHeading = 1u << 3;
inline constexpr uint8_t kChangedEstX = 1u << 4;
inline constexpr uint8_t kChangedEstY = 1u << 5;
inline constexpr uint8_t kChangedEstHeading = 1u << 6;
inline constexpr uint8_t kChangedReservedMask = 0x80;

/// Sizes of the fixed parts, in bytes.
inline constexpr size_t kHeaderFixedBytes = 8 + 2 + 8 + 8 + 4 + 4;  ///< magic .. arena_height_m
inline constexpr size_t kRobotInfoBytes = 2 + 1 + 4;
inline constexpr size_t kAnchorBytes = 4 + 4;
inline constexpr size_t kRoundFixedBytes = 1 + 4 + 8 + 4 + 4 + 4;   ///< tag .. map_count
inline constexpr size_t kRoundFixedBytesV2 = 1 + 4 + 8 + 4 + 4;     ///< versions 1, 2: tag .. event_count
inline constexpr size_t kFrameFixedBytes = 2 + 1 + 1;               ///< id, state, changed
inline constexpr size_t kFrameMaxBytes = kFrameFixedBytes + 2 + 6 * 4;
inline constexpr size_t kEventBytes = 1 + 2 + 2 + 2 + 1 + 8 + 2;
inline constexpr size_t kEventBytesV2 = 1 + 2 + 2 + 2 + 1 + 8;      ///< versions 1, 2: no partition
inline constexpr size_t kMapEntryBytes = 2 + 2;                     ///< robot, same_as
inline constexpr size_t kMapBodyFixedBytes = 2 + 1 + 2;             ///< epoch, mode, member_count
inline constexpr size_t kMapMemberFixedBytes = 2 + 1 + 5 * 2 + 1;   ///< id .. payload_length
/// The header's message `kind` byte.
inline constexpr uint8_t kMessageUndeclared = 0;
inline constexpr uint8_t kMessageNone = 1;
inline constexpr uint8_t kMessageFields = 2;
/// A map's same_as when the map itself follows.
inline constexpr uint16_t kSameAsNone = 0xFFFF;
inline constexpr size_t kEndBytes = 1 + 4 + 8 + 8;                  ///< tag .. frame_count
inline constexpr size_t kCrcBytes = 4;

/// CRC-32 (IEEE 802.3, reflected polynomial 0xEDB88320, the one zlib and PNG
/// use) of `bytes`, continuing from `crc` (0 to start): Crc32(b, Crc32(a))
/// equals the CRC of a followed by b.
uint32_t Crc32(std::span<const uint8_t> bytes, uint32_t crc = 0);

}  // namespace syrof::lab::replay::format
