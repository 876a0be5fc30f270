// Publishes every beacon the base station accepts on the DDS beacon topic
// rt/syrof/beacon, as `syrof swarm`'s robots do (docs/dds.md): one Beacon_
// sample {sender = the beacon's robot id, round = the station's round, wire
// = the bytes as heard}. DDS itself stays in sim_dds (BeaconPublisher); this
// is the adapter, and its header names no DDS type.
#pragma once

#include <cstdint>
#include <memory>
#include <optional>
#include <span>
#include <string>

#include "syrof/bridge/base_station.h"
#include "syrof/lab/base/error.h"

namespace syrof::sim_dds {
class Participant;
class BeaconPublisher;
}  // namespace syrof::sim_dds

namespace syrof::bridge {

class DdsBeaconOutput;

struct DdsOutputOrError {
  std::unique_ptr<DdsBeaconOutput> output;
  std::optional<lab::Error> error;
  bool ok() const { return output != nullptr; }
};

class DdsBeaconOutput final : public BeaconOutput {
 public:
  /// A participant of its own on `domain_id` (0 .. 232) on network
  /// interface `interface` ("lo": this host only), and a beacon writer.
  /// Errors: the options, or Cyclone's refusal.
  static DdsOutputOrError Create(uint32_t domain_id, const std::string& interface);
  ~DdsBeaconOutput() override;

  void OnBeacon(const wire::Beacon& beacon, std::span<const uint8_t> wire_bytes, int8_t rssi_dbm,
                uint32_t round) override;

  uint64_t published() const;
  uint64_t failed() const;
  uint32_t matched_readers() const;

 private:
  DdsBeaconOutput() = default;
  std::unique_ptr<sim_dds::Participant> participant_;
  std::unique_ptr<sim_dds::BeaconPublisher> publisher_;
};

}  // namespace syrof::bridge
