// Why a beacon could not be encoded or decoded.
#pragma once

#include <cstdint>

namespace syrof::wire {

/// Errors of the beacon codec and layout renderer. The decoder reports a
/// distinct error for each way a byte string can be malformed; the encoder
/// rejects a Beacon that the decoder would not produce, with the same error.
enum class [[nodiscard]] WireError : uint8_t{
    kOk = 0,
    kSwarmSizeOutOfRange,  // swarm size 0 or above kMaxSwarmSize
    kBufferTooSmall,       // output buffer shorter than the encoding
    kTruncated,            // input ends before the layout does
    kTrailingBytes,        // input longer than the layout
    kWrongVersion,         // version byte is not kBeaconVersion
    kRobotIdOutOfRange,    // robot id >= swarm size
    kPhaseOutOfRange,      // phase bits name no Phase
    kModeOutOfRange,       // mode bits name no Mode
    kPayloadTooLong,       // payload length above 9
    kMemberOutOfRange,     // waiting set names an id >= swarm size
    kHeadingOutOfRange,    // heading outside -3142 .. 3142 mrad
    kNonZeroPadding,       // a payload byte past payload_length is not zero
    kPresenceOutOfRange,   // never produced (a bool is 0 or 1); the layout's range check names it
    kRelayOutOfRange,      // relay slot above the swarm size, or a position with nothing relayed
};

/// The enumerator's name without the k ("Truncated"); "?" for an unknown value.
const char* ToString(WireError error);

}  // namespace syrof::wire
