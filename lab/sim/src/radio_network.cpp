#include "syrof/lab/sim/radio_network.h"

#include <span>

#include "syrof/base/check.h"
#include "syrof/wire/beacon_codec.h"

namespace syrof::lab::sim {

RadioNetwork::RadioNetwork(const world::ChannelSpec& channel, uint16_t robots, uint64_t seed)
    : channel_(channel, robots, seed), outbox_(robots), sent_(robots, 0), inflight_(robots) {
  radios_.reserve(robots);
  for (uint16_t id = 0; id < robots; ++id) radios_.emplace_back(*this, id);
}

void RadioNetwork::LabRadio::Broadcast(const wire::Beacon& beacon) {
  network_->outbox_[id_] = beacon;
  network_->sent_[id_] = 1;
}

void RadioNetwork::SetRadioFaults(std::span<const scenario::FaultSpec> faults) {
  radio_faults_.clear();
  for (const scenario::FaultSpec& fault : faults) {
    if (scenario::IsRadioFault(fault.kind)) radio_faults_.push_back(fault);
  }
}

bool RadioNetwork::Silenced(scenario::FaultKind kind, uint16_t robot, double at_s) const {
  for (const scenario::FaultSpec& fault : radio_faults_) {
    if (fault.kind == kind && fault.robot == robot && fault.at_s <= at_s && at_s < fault.until_s) return true;
  }
  return false;
}

void RadioNetwork::Deliver(int64_t round, double sent_at_s, BeaconReceivers& receivers) {
  const uint16_t swarm_size = size();
  for (uint16_t sender = 0; sender < swarm_size; ++sender) {
    if (sent_[sender] == 0) continue;
    sent_[sender] = 0;
    const auto encoded = wire::Encode(outbox_[sender], swarm_size, frame_bytes_);
    SYROF_CHECK(encoded.ok());
    const auto decoded = wire::Decode(std::span<const uint8_t>(frame_bytes_.data(), encoded.value()), swarm_size);
    if (!decoded.ok()) {
      ++beacons_malformed_;
      continue;
    }
    inflight_[sender] = decoded.value();
    const bool mute = !radio_faults_.empty() && Silenced(scenario::FaultKind::kMute, sender, sent_at_s);
    for (uint16_t receiver = 0; receiver < swarm_size; ++receiver) {
      if (receiver == sender || !receivers.Listening(receiver)) continue;
      if (!channel_.Delivers(sender, receiver, round, sent_at_s)) continue;
      if (mute || (!radio_faults_.empty() && Silenced(scenario::FaultKind::kDeaf, receiver, sent_at_s))) continue;
      receivers.Receive(receiver, inflight_[sender]);
    }
  }
}

}  // namespace syrof::lab::sim
