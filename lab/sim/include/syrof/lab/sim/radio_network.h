// The simulated lab's radio: every robot's Radio (its outbox slot), the
// beacons in flight, and the channel (lab/world/channel.h) that decides which
// receiver hears which beacon.
//
// One radio round's life of a beacon:
//   1. the robot's round task calls Broadcast() at the end of round r: the
//      beacon waits in the sender's outbox slot (one per robot; a second
//      broadcast in the same round replaces the first);
//   2. at the end of round r + 1 (before the round tasks of that instant),
//      Deliver() takes every waiting beacon in sender order and encodes and
//      decodes it once (the wire format is exercised on every beacon; a
//      beacon that does not survive is counted in beacons_malformed()); then,
//      receiver by receiver, it hands each listening receiver every decoded
//      beacon the channel lets it hear, by address, in sender order;
//   3. the receivers' round tasks step with it. The decoded beacon stays in
//      flight (valid) until the sender's next delivery.
// Determinism: the channel's draws depend on (seed, round, link) only, and
// deliveries go in (receiver, sender) order: each receiver gets its beacons
// of the round in one run of calls, in sender order.
//
// With real clocks (UseClocks, docs/clocks.md) rounds no longer share
// boundaries, so a beacon travels when it is sent instead: Broadcast encodes
// and decodes it at once, and hands it, with its arrival time (its send
// slot, half a round after the boundary that broadcast it, plus a seeded
// jitter), to every receiver the channel lets hear it;
// each receiver's robot steps it in its own round that contains the arrival
// (runtime::Robot::Receive with a time). The channel's round is the true
// round the send falls in, minus one (what the shared clock gives for a
// beacon sent at the end of a round). The decoded beacon stays valid for
// kClockedSlots of the sender's broadcasts.
#pragma once

#include <array>
#include <cstdint>
#include <functional>
#include <span>
#include <vector>

#include "syrof/lab/scenario/scenario.h"
#include "syrof/lab/world/channel.h"
#include "syrof/runtime/radio.h"
#include "syrof/wire/beacon.h"
#include "syrof/wire/beacon_layout.h"
#include "syrof/base/state_digest.h"

namespace syrof::lab::sim {

/// Who receives: the engine's robots, or a test's recorder.
class BeaconReceivers {
 public:
  /// Whether `robot` is on and hears the radio now (not crashed, paused or
  /// absent). Deliver() asks once per robot, before it hands any beacon over.
  virtual bool Listening(uint16_t robot) const = 0;
  /// Hands `robot` the beacons it hears of one round, in sender order
  /// (never none); each is valid until its sender's next delivery. One call
  /// per receiver and round, not one per beacon: a swarm hears N^2 beacons
  /// a round.
  virtual void Receive(uint16_t robot, std::span<const wire::Beacon* const> beacons) = 0;
  /// With real clocks: `beacon` reaches `robot` at `arrival_ns` (true
  /// time); valid for the sender's next kClockedSlots - 1 broadcasts.
  virtual void ReceiveAt(uint16_t robot, const wire::Beacon& beacon, int64_t arrival_ns) = 0;

 protected:
  ~BeaconReceivers() = default;
};

class RadioNetwork {
 public:
  /// A network of `robots` radios (ids 0 .. robots - 1) over a channel built
  /// from `channel` and `seed`. Everything is allocated here.
  RadioNetwork(const world::ChannelSpec& channel, uint16_t robots, uint64_t seed);
  RadioNetwork(const RadioNetwork&) = delete;
  RadioNetwork& operator=(const RadioNetwork&) = delete;

  /// Robot `robot`'s radio; it outlives the robot (it lives as long as the network).
  runtime::Radio& radio(uint16_t robot) { return radios_[robot]; }

  /// Delivers the beacons broadcast in radio round `round`, sent at
  /// `sent_at_s` (the channel's partitions are in seconds), to `receivers`.
  /// BeginDelivery and then DeliverToBlock of every block.
  void Deliver(int64_t round, double sent_at_s, BeaconReceivers& receivers);

  /// Splits the receivers into `starts.size()` blocks of consecutive ids,
  /// block b from starts[b] (starts[0] == 0, increasing), each with its own
  /// copy of the channel: a link is always decided by its receiver's block,
  /// and a copy's draws and Gilbert-Elliott states for its links are those
  /// of the one channel, so deliveries are unchanged. Before the first
  /// delivery; without it there is one block.
  void SplitReceivers(std::span<const uint16_t> starts);
  size_t blocks() const { return block_starts_.size(); }
  /// Deliver() in parts, for a caller that runs blocks on threads:
  /// BeginDelivery asks who listens; EncodeBlock encodes and decodes the
  /// round's beacons of block `block`'s senders (the ids of its receivers);
  /// EndEncoding lists the decoded beacons in sender order; DeliverToBlock
  /// then hands block `block`'s listening receivers their beacons as
  /// Deliver does. The EncodeBlock calls of one round may run at the same
  /// time, each touching only its senders' slots and its own frame buffer,
  /// and so may its DeliverToBlock calls, each touching only its receivers
  /// its channel copy and its own list of beacons heard
  /// (`receivers.Receive` is called for its receivers only); EndEncoding
  /// runs between them, on one thread.
  void BeginDelivery(int64_t round, double sent_at_s, BeaconReceivers& receivers);
  void EncodeBlock(size_t block);
  void EndEncoding();
  void DeliverToBlock(size_t block, BeaconReceivers& receivers);

  /// Applies the scenario's deaf and mute faults (other kinds are ignored): a
  /// beacon sent at t is not heard by a robot deaf at t, and nobody hears a
  /// robot mute at t, where deaf or mute from T to U means T <= t < U. The
  /// channel still draws for those links, so the other links are unchanged.
  void SetRadioFaults(std::span<const scenario::FaultSpec> faults);

  /// Switches to sending at once (above). `now_ns` tells the true time;
  /// jitter_ns: a beacon leaves uniformly 0 .. jitter_ns after its send
  /// slot (half a round after the broadcast), drawn from `seed`, the sender
  /// and its broadcast count.
  void UseClocks(std::function<int64_t()> now_ns, BeaconReceivers& receivers, int64_t round_ns, int64_t jitter_ns,
                 uint64_t seed);

  /// How many of a sender's decoded beacons stay valid with real clocks.
  static constexpr size_t kClockedSlots = 8;

  /// Whether `robot` broadcast since the last delivery.
  bool waiting(uint16_t robot) const { return sent_[robot] != 0; }
  /// Beacons that did not decode after encoding (never, unless the codec is broken).
  uint64_t beacons_malformed() const { return beacons_malformed_; }
  uint16_t size() const { return static_cast<uint16_t>(radios_.size()); }

  /// The beacons broadcast and not yet delivered into `digest`
  /// (base/state_digest.h). Not with clocks.
  void AddToDigest(base::StateDigest& digest) const;

 private:
  class LabRadio final : public runtime::Radio {
   public:
    LabRadio(RadioNetwork& network, uint16_t id) : network_(&network), id_(id) {}
    void Broadcast(const wire::Beacon& beacon) override;

   private:
    RadioNetwork* network_;
    uint16_t id_;
  };

  bool Silenced(scenario::FaultKind kind, uint16_t robot, double at_s) const;
  void SendNow(uint16_t sender, const wire::Beacon& beacon);

  // Real clocks (UseClocks).
  std::function<int64_t()> now_ns_;
  BeaconReceivers* clocked_receivers_ = nullptr;
  int64_t round_ns_ = 0;
  int64_t jitter_ns_ = 0;
  uint64_t jitter_seed_ = 0;
  std::vector<wire::Beacon> slots_;     // kClockedSlots per sender
  std::vector<uint64_t> broadcasts_;    // per sender

  world::Channel channel_;
  // SplitReceivers: the first receiver of each block and the blocks'
  // channels (block 0 uses channel_); the round BeginDelivery set up.
  std::vector<uint16_t> block_starts_{0};
  std::vector<world::Channel> block_channels_;
  int64_t delivery_round_ = 0;
  double delivery_sent_at_s_ = 0;
  std::vector<scenario::FaultSpec> radio_faults_;
  std::vector<LabRadio> radios_;
  std::vector<wire::Beacon> outbox_;
  std::vector<uint8_t> sent_;
  std::vector<wire::Beacon> inflight_;
  std::vector<uint8_t> listening_;  // Deliver's scratch: BeaconReceivers::Listening per robot
  struct Sent {
    uint16_t sender;
    bool mute;  // nobody hears it (a mute fault), though the channel still draws
  };
  std::vector<Sent> senders_;  // Deliver's scratch: this round's decoded beacons, in sender order
  std::vector<uint8_t> decoded_;  // per sender: its beacon of this round decoded (EncodeBlock)
  // Per block, what its EncodeBlock writes (a cache line apart, so that
  // blocks encoding side by side do not share one).
  struct alignas(64) BlockCodec {
    std::array<uint8_t, wire::kMaxBeaconBytes> frame_bytes{};
    uint64_t malformed = 0;  // since EndEncoding last added it up
  };
  std::vector<BlockCodec> block_codecs_{1};
  // Per block, DeliverToBlock's scratch: one receiver's beacons of the
  // round (room for every sender).
  std::vector<std::vector<const wire::Beacon*>> block_heard_;
  std::array<uint8_t, wire::kMaxBeaconBytes> frame_bytes_{};  // the clocked radio's (SendNow)
  uint64_t beacons_malformed_ = 0;
};

}  // namespace syrof::lab::sim
