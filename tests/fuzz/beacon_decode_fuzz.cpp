// libFuzzer target for the beacon decoder.
//
// Input: two bytes of swarm size (little-endian, clamped to
// 1 .. kMaxSwarmSize), then the bytes to decode. Whatever the decoder accepts
// must re-encode to exactly those bytes and decode again to the same beacon;
// anything else stops the run.
#include <algorithm>
#include <cstddef>
#include <cstdint>
#include <cstring>
#include <span>

#include "syrof/wire/beacon_codec.h"

namespace {

using syrof::wire::Decode;
using syrof::wire::Encode;
using syrof::wire::kMaxBeaconBytes;
using syrof::wire::kMaxSwarmSize;

constexpr size_t kSwarmSizeBytes = 2;

void require(bool condition) {
  if (!condition) __builtin_trap();
}

}  // namespace

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, size_t size) {
  if (size < kSwarmSizeBytes) return 0;
  const unsigned requested = data[0] | (unsigned{data[1]} << 8);
  const auto swarm_size = static_cast<uint16_t>(std::clamp<unsigned>(requested, 1, kMaxSwarmSize));
  const std::span<const uint8_t> in(data + kSwarmSizeBytes, size - kSwarmSizeBytes);

  const auto beacon = Decode(in, swarm_size);
  if (!beacon.ok()) return 0;

  uint8_t again[kMaxBeaconBytes];
  const auto length = Encode(beacon.value(), swarm_size, again);
  require(length.ok());
  require(length.value() == in.size());
  require(std::memcmp(again, in.data(), in.size()) == 0);
  const auto decoded_again = Decode(std::span<const uint8_t>(again, length.value()), swarm_size);
  require(decoded_again.ok() && decoded_again.value() == beacon.value());
  return 0;
}
