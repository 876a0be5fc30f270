// libFuzzer target for the checks a received Beacon_ sample passes
// (sim_dds/sample_check.h): the path from an untrusted DDS sample to a
// beacon the robot steps.
//
// Input: swarm size (2 bytes, little-endian, clamped to 1 .. kMaxDdsSwarm),
// receiver id (2 bytes, taken modulo the swarm size), the sample's sender
// (2 bytes) and round (4 bytes), the receiver's current round (4 bytes, as
// a signed number: negative is "not started"), then the sample's wire
// bytes. An accepted sample must come from a robot of the swarm other than
// the receiver, be the beacon of that robot, lie in the round window and
// re-encode to exactly its bytes; the same sample a second time must be a
// duplicate. Anything else stops the run.
#include <algorithm>
#include <cstddef>
#include <cstdint>
#include <cstring>
#include <span>

#include "syrof/sim_dds/sample_check.h"
#include "syrof/wire/beacon_codec.h"

namespace {

using syrof::sim_dds::kMaxDdsSwarm;
using syrof::sim_dds::kRoundWindow;
using syrof::sim_dds::SampleFilter;
using syrof::sim_dds::SampleVerdict;

constexpr size_t kHeaderBytes = 14;

void require(bool condition) {
  if (!condition) __builtin_trap();
}

uint32_t Little(const uint8_t* data, int bytes) {
  uint32_t value = 0;
  for (int i = bytes - 1; i >= 0; --i) value = (value << 8) | data[i];
  return value;
}

}  // namespace

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, size_t size) {
  if (size < kHeaderBytes) return 0;
  const auto swarm_size = static_cast<uint16_t>(std::clamp<uint32_t>(Little(data, 2), 1, kMaxDdsSwarm));
  const auto self = static_cast<uint16_t>(Little(data + 2, 2) % swarm_size);
  const auto sender = static_cast<uint16_t>(Little(data + 4, 2));
  const uint32_t round = Little(data + 6, 4);
  const auto current_round = static_cast<int64_t>(static_cast<int32_t>(Little(data + 10, 4)));
  const std::span<const uint8_t> wire(data + kHeaderBytes, size - kHeaderBytes);

  SampleFilter filter(self, swarm_size);
  syrof::wire::Beacon beacon;
  const SampleVerdict verdict = filter.Check(sender, round, wire, current_round, beacon);
  require(filter.counters().count(verdict) == 1);
  if (verdict != SampleVerdict::kAccepted) {
    require(filter.counters().rejected() == 1);
    return 0;
  }
  require(sender < swarm_size && sender != self && beacon.robot_id == sender);
  require(current_round < 0 ||
          (static_cast<int64_t>(round) >= current_round - kRoundWindow &&
           static_cast<int64_t>(round) <= current_round + kRoundWindow));
  uint8_t again[syrof::wire::kMaxBeaconBytes];
  const auto length = syrof::wire::Encode(beacon, swarm_size, again);
  require(length.ok() && length.value() == wire.size() && std::memcmp(again, wire.data(), wire.size()) == 0);

  syrof::wire::Beacon replayed;
  require(filter.Check(sender, round, wire, current_round, replayed) == SampleVerdict::kDuplicate);
  return 0;
}
