// Beacons and swarm sizes shared by the wire tests.
#pragma once

#include <array>
#include <cstdint>
#include <limits>
#include <random>
#include <vector>

#include "syrof/wire/beacon.h"
#include "syrof/wire/member_set.h"

namespace syrof::wire::testing {

// The swarm sizes the round-trip tests cover, limited to what this build
// supports (32 on the Teensy): the bounds of each robot_id width and of
// member-set padding.
inline std::vector<uint16_t> swarm_sizes_under_test() {
  std::vector<uint16_t> sizes;
  for (const uint16_t size : {1, 8, 30, 32, 33, 256, 257, 1024}) {
    if (size <= kMaxSwarmSize) sizes.push_back(size);
  }
  return sizes;
}

// Every field at its lowest valid value.
inline Beacon lowest_beacon() {
  Beacon beacon;
  beacon.robot_id = 0;
  beacon.epoch = 0;
  beacon.phase = Phase::kProgress;
  beacon.mode = Mode::kCooperative;
  beacon.vote_counter = 0;
  beacon.snapshot.x_mm = std::numeric_limits<int16_t>::min();
  beacon.snapshot.y_mm = std::numeric_limits<int16_t>::min();
  beacon.snapshot.heading_mrad = kMinHeadingMilliradians;
  beacon.snapshot.vx_mm_s = std::numeric_limits<int16_t>::min();
  beacon.snapshot.vy_mm_s = std::numeric_limits<int16_t>::min();
  beacon.relay.slot = 1;  // robot 0, the lowest position
  beacon.relay.x_16mm = kMinRelayUnits;
  beacon.relay.y_16mm = kMinRelayUnits;
  return beacon;
}

// Every field at its highest valid value for a swarm of `swarm_size`.
inline Beacon highest_beacon(uint16_t swarm_size) {
  Beacon beacon;
  beacon.robot_id = static_cast<uint16_t>(swarm_size - 1);
  beacon.epoch = std::numeric_limits<uint16_t>::max();
  beacon.phase = Phase::kVote;
  beacon.mode = Mode::kAutonomous;
  beacon.vote_counter = std::numeric_limits<uint8_t>::max();
  for (uint16_t member = 0; member < swarm_size; ++member) beacon.waiting.set(member);
  beacon.snapshot.x_mm = std::numeric_limits<int16_t>::max();
  beacon.snapshot.y_mm = std::numeric_limits<int16_t>::max();
  beacon.snapshot.heading_mrad = kMaxHeadingMilliradians;
  beacon.snapshot.vx_mm_s = std::numeric_limits<int16_t>::max();
  beacon.snapshot.vy_mm_s = std::numeric_limits<int16_t>::max();
  beacon.snapshot.payload_length = kMaxPayloadBytes;
  beacon.snapshot.payload.fill(0xFF);
  beacon.relay.slot = swarm_size;  // robot swarm_size - 1
  beacon.relay.x_16mm = kMaxRelayUnits;
  beacon.relay.y_16mm = kMaxRelayUnits;
  return beacon;
}

// A valid beacon for a swarm of `swarm_size` with every field drawn at random.
inline Beacon random_beacon(std::mt19937& random, uint16_t swarm_size) {
  auto uniform = [&random](int lowest, int highest) {
    return std::uniform_int_distribution<int>(lowest, highest)(random);
  };
  Beacon beacon;
  beacon.robot_id = static_cast<uint16_t>(uniform(0, swarm_size - 1));
  beacon.epoch = static_cast<uint16_t>(uniform(0, 65535));
  beacon.phase = static_cast<Phase>(uniform(0, 2));
  beacon.mode = static_cast<Mode>(uniform(0, 1));
  beacon.vote_counter = static_cast<uint8_t>(uniform(0, 255));
  const int members = uniform(0, swarm_size);
  for (int i = 0; i < members; ++i) {
    beacon.waiting.set(static_cast<uint16_t>(uniform(0, swarm_size - 1)));
  }
  beacon.snapshot.x_mm = static_cast<int16_t>(uniform(-32768, 32767));
  beacon.snapshot.y_mm = static_cast<int16_t>(uniform(-32768, 32767));
  beacon.snapshot.heading_mrad =
      static_cast<int16_t>(uniform(kMinHeadingMilliradians, kMaxHeadingMilliradians));
  beacon.snapshot.vx_mm_s = static_cast<int16_t>(uniform(-32768, 32767));
  beacon.snapshot.vy_mm_s = static_cast<int16_t>(uniform(-32768, 32767));
  std::array<uint8_t, kMaxPayloadBytes> bytes{};
  for (uint8_t& byte : bytes) byte = static_cast<uint8_t>(uniform(0, 255));
  const auto length = static_cast<size_t>(uniform(0, kMaxPayloadBytes));
  [[maybe_unused]] const WireError error =
      beacon.snapshot.SetPayload(std::span<const uint8_t>(bytes).first(length));
  if (uniform(0, 1) != 0) {
    beacon.relay.slot = static_cast<uint16_t>(uniform(1, swarm_size));
    beacon.relay.x_16mm = static_cast<int16_t>(uniform(kMinRelayUnits, kMaxRelayUnits));
    beacon.relay.y_16mm = static_cast<int16_t>(uniform(kMinRelayUnits, kMaxRelayUnits));
  }
  return beacon;
}

}  // namespace syrof::wire::testing
