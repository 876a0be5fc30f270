// A writer of other robots' beacons on rt/syrof/beacon: what a relay (the
// base station's bridge, docs/bridge.md) uses to put beacons it heard on the
// air onto DDS. Each sample is {sender, round, run_id, wire} as BeaconRadio
// writes it, with run_id 0 (no swarm run: a BeaconRadio of run 0 reads them,
// a `syrof swarm` robot does not), and the sender the beacon's own robot id,
// not this process's, so a DDS reader (BeaconRadio, a ROS 2 node) sees every
// robot's beacon under its own key. The bytes are published as they were
// heard; the caller checks them first (the bridge decodes every beacon with
// wire::Decode).
//
//   BeaconPublisherOrError made = BeaconPublisher::Create(participant);
//   made.publisher->Publish(beacon.robot_id, round, wire_bytes);
#pragma once

#include <atomic>
#include <cstdint>
#include <memory>
#include <optional>
#include <span>

#include "syrof/sim_dds/participant.h"

namespace syrof::sim_dds {

class BeaconPublisher;

struct BeaconPublisherOrError {
  std::unique_ptr<BeaconPublisher> publisher;
  std::optional<Error> error;
  bool ok() const { return publisher != nullptr; }
  static BeaconPublisherOrError Failed(Error why) { return {nullptr, std::move(why)}; }
};

class BeaconPublisher {
 public:
  /// A writer of rt/syrof/beacon with the topic's QoS (best effort, keep
  /// last 1 per sender). The participant outlives the publisher. Errors:
  /// Cyclone's refusal (where = the topic's name).
  static BeaconPublisherOrError Create(const Participant& participant);

  ~BeaconPublisher();
  BeaconPublisher(const BeaconPublisher&) = delete;
  BeaconPublisher& operator=(const BeaconPublisher&) = delete;

  /// Writes one sample; never blocks (best effort). False when Cyclone
  /// refused it (more than BEACON_MAX_BYTES, or a deleted writer); counted.
  bool Publish(uint16_t sender, uint32_t round, std::span<const uint8_t> wire);

  uint64_t published() const { return published_.load(std::memory_order_relaxed); }
  uint64_t failed() const { return failed_.load(std::memory_order_relaxed); }
  /// Beacon readers matched so far (0 on error).
  uint32_t matched_readers() const;

 private:
  explicit BeaconPublisher(dds_entity_t writer) : writer_(writer) {}

  dds_entity_t writer_;
  std::atomic<uint64_t> published_{0};
  std::atomic<uint64_t> failed_{0};
};

}  // namespace syrof::sim_dds
