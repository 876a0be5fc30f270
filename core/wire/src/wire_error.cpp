#include "syrof/wire/wire_error.h"

namespace syrof::wire {

const char* ToString(WireError error) {
  switch (error) {
    case WireError::kOk: return "Ok";
    case WireError::kSwarmSizeOutOfRange: return "SwarmSizeOutOfRange";
    case WireError::kBufferTooSmall: return "BufferTooSmall";
    case WireError::kTruncated: return "Truncated";
    case WireError::kTrailingBytes: return "TrailingBytes";
    case WireError::kWrongVersion: return "WrongVersion";
    case WireError::kRobotIdOutOfRange: return "RobotIdOutOfRange";
    case WireError::kPhaseOutOfRange: return "PhaseOutOfRange";
    case WireError::kModeOutOfRange: return "ModeOutOfRange";
    case WireError::kPayloadTooLong: return "PayloadTooLong";
    case WireError::kMemberOutOfRange: return "MemberOutOfRange";
    case WireError::kHeadingOutOfRange: return "HeadingOutOfRange";
    case WireError::kNonZeroPadding: return "NonZeroPadding";
    case WireError::kPresenceOutOfRange: return "PresenceOutOfRange";
    case WireError::kRelayOutOfRange: return "RelayOutOfRange";
  }
  return "?";
}

}  // namespace syrof::wire
