// Encoding and decoding beacons, as laid out in beacon_layout.h.
//
// Both directions accept exactly the same beacons: Decode() returns only
// beacons that Encode() accepts, and Encode() rejects (with the decoder's
// error) every Beacon that no byte string decodes to. So each beacon has one
// encoding, and any byte string Decode() accepts re-encodes to the same bytes.
#pragma once

#include <cstddef>
#include <cstdint>
#include <span>

#include "syrof/base/result.h"
#include "syrof/wire/beacon.h"
#include "syrof/wire/beacon_layout.h"
#include "syrof/wire/wire_error.h"

namespace syrof::wire {

/// Writes `beacon` for a swarm of `swarm_size` robots into the first
/// EncodedSize(swarm_size) bytes of `out` and returns that size. Errors:
/// kSwarmSizeOutOfRange, kBufferTooSmall, then the first field in layout order
/// that the decoder would reject (kRobotIdOutOfRange, kPhaseOutOfRange,
/// kModeOutOfRange, kPayloadTooLong, kMemberOutOfRange, kHeadingOutOfRange,
/// kNonZeroPadding). On error the bytes it would have written are zero.
syrof::base::Result<size_t, WireError> Encode(const Beacon& beacon, uint16_t swarm_size,
                                              std::span<uint8_t> out);

/// Reads one beacon for a swarm of `swarm_size` robots; `in` must be exactly
/// EncodedSize(swarm_size) bytes. Fields are checked in layout order and the
/// first problem is reported: kSwarmSizeOutOfRange, kWrongVersion (checked
/// first, so a beacon of another version is named as such whatever its
/// length), kTruncated where the input runs out, a field's own error, and
/// kTrailingBytes when bytes remain after the layout.
syrof::base::Result<Beacon, WireError> Decode(std::span<const uint8_t> in, uint16_t swarm_size);

}  // namespace syrof::wire
