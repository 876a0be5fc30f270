#include "syrof/lab/sim/radio_network.h"

#include <algorithm>
#include <span>

#include "syrof/base/split_mix64.h"

#include "syrof/base/check.h"
#include "syrof/wire/beacon_codec.h"

namespace syrof::lab::sim {

RadioNetwork::RadioNetwork(const world::ChannelSpec& channel, uint16_t robots, uint64_t seed)
    : channel_(channel, robots, seed),
      outbox_(robots),
      sent_(robots, 0),
      inflight_(robots),
      listening_(robots, 0),
      decoded_(robots, 0),
      block_heard_(1, std::vector<const wire::Beacon*>(robots)) {
  radios_.reserve(robots);
  senders_.reserve(robots);
  for (uint16_t id = 0; id < robots; ++id) radios_.emplace_back(*this, id);
}

void RadioNetwork::LabRadio::Broadcast(const wire::Beacon& beacon) {
  if (network_->clocked_receivers_ != nullptr) {
    network_->SendNow(id_, beacon);
    return;
  }
  network_->outbox_[id_] = beacon;
  network_->sent_[id_] = 1;
}

void RadioNetwork::UseClocks(std::function<int64_t()> now_ns, BeaconReceivers& receivers, int64_t round_ns,
                             int64_t jitter_ns, uint64_t seed) {
  SYROF_CHECK(round_ns > 0 && jitter_ns >= 0);
  now_ns_ = std::move(now_ns);
  clocked_receivers_ = &receivers;
  round_ns_ = round_ns;
  jitter_ns_ = jitter_ns;
  jitter_seed_ = seed;
  slots_.assign(radios_.size() * kClockedSlots, wire::Beacon{});
  broadcasts_.assign(radios_.size(), 0);
}

void RadioNetwork::SendNow(uint16_t sender, const wire::Beacon& beacon) {
  const uint16_t swarm_size = size();
  const int64_t now = now_ns_();
  const uint64_t count = broadcasts_[sender]++;
  int64_t jitter = 0;
  if (jitter_ns_ > 0) {
    const uint64_t hash = base::SplitMix64Hash(jitter_seed_ ^ base::SplitMix64Hash((uint64_t{sender} << 40) ^ count));
    jitter = static_cast<int64_t>(hash % static_cast<uint64_t>(jitter_ns_ + 1));
  }
  // The radio transmits in its slot, half a round after the boundary that
  // handed it the beacon: a receiver whose boundary is within half a round
  // of the sender's steps it in the round after the send, as the shared clock does.
  const int64_t arrival = now + round_ns_ / 2 + jitter;
  const int64_t round = std::max<int64_t>(0, now / round_ns_ - 1);
  const double sent_at_s = static_cast<double>(round * round_ns_) * 1e-9;
  const auto encoded = wire::Encode(beacon, swarm_size, frame_bytes_);
  SYROF_CHECK(encoded.ok());
  const auto decoded = wire::Decode(std::span<const uint8_t>(frame_bytes_.data(), encoded.value()), swarm_size);
  if (!decoded.ok()) {
    ++beacons_malformed_;
    return;
  }
  wire::Beacon& slot = slots_[sender * kClockedSlots + count % kClockedSlots];
  slot = decoded.value();
  const bool mute = !radio_faults_.empty() && Silenced(scenario::FaultKind::kMute, sender, sent_at_s);
  for (uint16_t receiver = 0; receiver < swarm_size; ++receiver) {
    if (receiver == sender || !clocked_receivers_->Listening(receiver)) continue;
    if (!channel_.Delivers(sender, receiver, round, sent_at_s)) continue;
    if (mute || (!radio_faults_.empty() && Silenced(scenario::FaultKind::kDeaf, receiver, sent_at_s))) continue;
    clocked_receivers_->ReceiveAt(receiver, slot, arrival);
  }
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

void RadioNetwork::SplitReceivers(std::span<const uint16_t> starts) {
  SYROF_CHECK(!starts.empty() && starts[0] == 0);
  for (size_t b = 1; b < starts.size(); ++b) SYROF_CHECK(starts[b] > starts[b - 1] && starts[b] < size());
  block_starts_.assign(starts.begin(), starts.end());
  block_channels_.assign(starts.size() - 1, channel_);
  block_codecs_.assign(starts.size(), BlockCodec{});
  block_heard_.assign(starts.size(), std::vector<const wire::Beacon*>(size()));
}

void RadioNetwork::Deliver(int64_t round, double sent_at_s, BeaconReceivers& receivers) {
  BeginDelivery(round, sent_at_s, receivers);
  for (size_t block = 0; block < block_starts_.size(); ++block) EncodeBlock(block);
  EndEncoding();
  for (size_t block = 0; block < block_starts_.size(); ++block) DeliverToBlock(block, receivers);
}

void RadioNetwork::BeginDelivery(int64_t round, double sent_at_s, BeaconReceivers& receivers) {
  const uint16_t swarm_size = size();
  delivery_round_ = round;
  delivery_sent_at_s_ = sent_at_s;
  // Receiving hands a beacon over and changes no robot's power, so who
  // listens is asked once per receiver, not once per (sender, receiver).
  for (uint16_t receiver = 0; receiver < swarm_size; ++receiver) listening_[receiver] = receivers.Listening(receiver);
}

// Every beacon of the round is encoded and decoded before any is handed
// over: a block's senders here, the senders' list in EndEncoding.
void RadioNetwork::EncodeBlock(size_t block) {
  const uint16_t swarm_size = size();
  const uint16_t first = block_starts_[block];
  const uint16_t end = block + 1 < block_starts_.size() ? block_starts_[block + 1] : swarm_size;
  BlockCodec& codec = block_codecs_[block];
  for (uint16_t sender = first; sender < end; ++sender) {
    decoded_[sender] = 0;
    if (sent_[sender] == 0) continue;
    sent_[sender] = 0;
    const auto encoded = wire::Encode(outbox_[sender], swarm_size, codec.frame_bytes);
    SYROF_CHECK(encoded.ok());
    const auto decoded = wire::Decode(std::span<const uint8_t>(codec.frame_bytes.data(), encoded.value()), swarm_size);
    if (!decoded.ok()) {
      ++codec.malformed;
      continue;
    }
    inflight_[sender] = decoded.value();
    decoded_[sender] = 1;
  }
}

void RadioNetwork::EndEncoding() {
  const uint16_t swarm_size = size();
  for (BlockCodec& codec : block_codecs_) {
    beacons_malformed_ += codec.malformed;
    codec.malformed = 0;
  }
  senders_.clear();
  for (uint16_t sender = 0; sender < swarm_size; ++sender) {
    if (decoded_[sender] == 0) continue;
    const bool mute = !radio_faults_.empty() && Silenced(scenario::FaultKind::kMute, sender, delivery_sent_at_s_);
    senders_.push_back({sender, mute});
  }
}

// Each receiver gets all its beacons of the round at once, in sender order:
// its inbox fills as when deliveries went sender by sender, but one robot's
// inbox is touched at a time. The channel is asked about the same links (its
// draws depend on the link and the round, not on the order).
void RadioNetwork::DeliverToBlock(size_t block, BeaconReceivers& receivers) {
  const uint16_t first = block_starts_[block];
  const uint16_t end = block + 1 < block_starts_.size() ? block_starts_[block + 1] : size();
  world::Channel& channel = block == 0 ? channel_ : block_channels_[block - 1];
  const int64_t round = delivery_round_;
  const double sent_at_s = delivery_sent_at_s_;
  const wire::Beacon** const heard = block_heard_[block].data();
  for (uint16_t receiver = first; receiver < end; ++receiver) {
    if (listening_[receiver] == 0) continue;
    const bool deaf = !radio_faults_.empty() && Silenced(scenario::FaultKind::kDeaf, receiver, sent_at_s);
    size_t count = 0;
    for (const Sent& sent : senders_) {
      if (sent.sender == receiver) continue;
      if (!channel.Delivers(sent.sender, receiver, round, sent_at_s)) continue;
      if (deaf || sent.mute) continue;
      heard[count++] = &inflight_[sent.sender];
    }
    if (count > 0) receivers.Receive(receiver, std::span<const wire::Beacon* const>(heard, count));
  }
}

void RadioNetwork::AddToDigest(base::StateDigest& digest) const {
  for (size_t sender = 0; sender < sent_.size(); ++sender) {
    digest.AddValue(sent_[sender]);
    if (sent_[sender] != 0) digest.AddValue(outbox_[sender]);
  }
}

}  // namespace syrof::lab::sim
