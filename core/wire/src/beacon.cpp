#include "syrof/wire/beacon.h"

#include <algorithm>

namespace syrof::wire {

const char* ToString(Phase phase) {
  switch (phase) {
    case Phase::kProgress: return "PROGRESS";
    case Phase::kWait: return "WAIT";
    case Phase::kVote: return "VOTE";
  }
  return "?";
}

const char* ToString(Mode mode) {
  switch (mode) {
    case Mode::kCooperative: return "COOPERATIVE";
    case Mode::kAutonomous: return "AUTONOMOUS";
  }
  return "?";
}

WireError Snapshot::SetPayload(std::span<const uint8_t> bytes) {
  if (bytes.size() > payload.size()) return WireError::kPayloadTooLong;
  const auto unused = std::copy(bytes.begin(), bytes.end(), payload.begin());
  std::fill(unused, payload.end(), uint8_t{0});
  payload_length = static_cast<uint8_t>(bytes.size());
  return WireError::kOk;
}

std::span<const uint8_t> Snapshot::payload_bytes() const {
  return std::span<const uint8_t>(payload).first(std::min<size_t>(payload_length, payload.size()));
}

}  // namespace syrof::wire
