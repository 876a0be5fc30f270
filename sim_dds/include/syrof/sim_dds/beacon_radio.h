// A robot's radio over DDS: runtime::Radio on rt/syrof/beacon.
//
// Sending: Broadcast() encodes the beacon (wire::Encode, docs/beacon.md) and
// writes one Beacon_ sample {sender, round, run_id, wire bytes}; best effort, it
// never blocks.
//
// Receiving: a listener on the beacon reader (Cyclone's receive thread)
// takes every sample; one of another run (BeaconRadioOptions::run_id) is
// refused at once (kOtherRun); a sample `hold_ns` makes late (the stress's late
// beacons, lab/sim/stress.h) is kept by a thread of the radio's until its
// due instant, as if the network had delivered it then; every sample, on
// arrival or at its due instant, then goes, in order,
//   1. checks it (sample_check.h: size, ids, round window, duplicates);
//      a rejected sample is counted by reason and goes no further;
//   2. applies the lab's channel model for the link sender -> self
//      (lab/world channel.h): Delivers(sender, self, round, round * round
//      length), so a scenario's loss, Gilbert-Elliott bursts, per-link loss
//      and partitions mean the same as in the lab for the same seed;
//   3. hands the wire bytes to the sink: runtime::Robot::ReceiveBytes
//      (thread-safe) or a callback.
// The reader ignores the samples of its own participant.
//
// Why a receiver-only channel gives the lab's decisions: every decision of
// lab::world::Channel is a hash of (seed, round, from, to), and a link's
// Gilbert-Elliott state at round r depends only on the seed, r and the link
// (each directed link has its own chain, advanced lazily). A Channel built
// with the scenario's spec, swarm size and seed answers Delivers(s, self, r,
// t) exactly as the lab's one Channel does, whichever other links it is
// never asked about (tests/sim_dds/beacon_radio_test.cpp checks it).
#pragma once

#include <array>
#include <atomic>
#include <condition_variable>
#include <cstdint>
#include <functional>
#include <map>
#include <memory>
#include <mutex>
#include <optional>
#include <span>
#include <thread>
#include <vector>

#include "syrof/lab/world/channel.h"
#include "syrof/runtime/radio.h"
#include "syrof/sim_dds/participant.h"
#include "syrof/sim_dds/sample_check.h"
#include "syrof/wire/member_set.h"

namespace syrof::runtime {
class Robot;
}

namespace syrof::sim_dds {

struct BeaconRadioOptions {
  uint16_t self = 0;
  uint16_t swarm_size = 1;                ///< 1 .. kMaxDdsSwarm
  /// The run: stamped on every sample this radio writes; a sample of
  /// another run is refused on arrival (kOtherRun), before anything else.
  /// A `syrof swarm` robot gets the world's run id; 0 outside a run.
  uint64_t run_id = 0;
  lab::world::ChannelSpec channel;        ///< the scenario's channel (CheckChannelSpec must pass)
  uint64_t seed = 0;                      ///< the scenario's seed: the lab's channel seed
  int64_t radio_round_ns = 50'000'000;    ///< round length: round r starts at r * this (partitions' time)
  /// The robot's current round on the run's grid (>= 0), or < 0 before the
  /// run starts. Broadcast stamps the sample with it; the reader checks
  /// incoming rounds against it (kRoundWindow). Called from the round task
  /// and from Cyclone's receive thread: must be thread-safe and quick.
  std::function<int64_t()> current_round;
  /// With round alignment, where each robot numbers its own rounds: the
  /// round whose beacons the robot expects now, the one whose window
  /// (centred on the arrival expected from an aligned sender) contains now.
  /// It decides in-round delivery (HeardInRound) and the senders' round
  /// offsets (AgreedRoundOffset). Unset: current_round.
  std::function<int64_t()> expected_round;
  /// How long to hold the sample of `round` from `sender` before it arrives
  /// (ns; 0: not held): a late network delivery, played by the receiver
  /// before the sample checks, so a late beacon is judged by the round in
  /// which it arrives (docs/dds.md, "Stress"). Unset: nothing held.
  std::function<int64_t(uint16_t sender, uint32_t round)> hold_ns;
};

/// Receives an accepted, delivered frame: the wire bytes, valid for the call
/// only, with the sample's sender and round. Runs on Cyclone's receive
/// thread: bounded time, no blocking.
using BeaconSink = std::function<void(std::span<const uint8_t> frame, uint16_t sender, uint32_t round)>;

/// Beacons in and out of one radio; every counter readable from any thread.
struct BeaconRadioCounters {
  uint64_t sent = 0;            ///< samples written
  uint64_t send_failed = 0;     ///< Encode or dds_write refused (the beacon is lost)
  uint64_t received = 0;        ///< samples taken (valid data), before any check
  uint64_t held = 0;            ///< of those, held by hold_ns before they arrived (late)
  uint64_t rejected = 0;        ///< refused by the sample checks (see SampleFilter counters)
  uint64_t lost = 0;            ///< accepted, then dropped by the channel model
  uint64_t delivered = 0;       ///< handed to the sink
};

class BeaconRadio;

struct BeaconRadioOrError {
  std::unique_ptr<BeaconRadio> radio;
  std::optional<Error> error;
  bool ok() const { return radio != nullptr; }
  static BeaconRadioOrError Failed(Error why) { return {nullptr, std::move(why)}; }
};

/// A robot process wires it in two steps, since the Robot takes its Radio
/// when it is built and the radio delivers to the Robot:
///   BeaconRadioOrError radio = BeaconRadio::Create(participant, options);
///   runtime::Robot robot(config, app, *radio.radio, storage);
///   radio.radio->StartReceiving(robot);
/// The robot (or sink) must outlive the radio's receiving: destroy the radio
/// first, or let the participant go before the robot.
class BeaconRadio final : public runtime::Radio {
 public:
  /// A radio that can send; it receives nothing until StartReceiving.
  /// Errors: options that do not hold (swarm size, self, the channel spec:
  /// where = "channel ..."), or Cyclone's refusal to make the writer. The
  /// participant outlives the radio.
  static BeaconRadioOrError Create(const Participant& participant, BeaconRadioOptions options);
  /// Create, then StartReceiving(sink).
  static BeaconRadioOrError Create(const Participant& participant, BeaconRadioOptions options, BeaconSink sink);

  /// Creates the beacon reader: from now on accepted, delivered frames go
  /// to `sink` (or to robot.ReceiveBytes). Once per radio (a second call is
  /// an error, where = "rt/syrof/beacon"); errors: an empty sink, Cyclone's
  /// refusal to make the reader.
  std::optional<Error> StartReceiving(BeaconSink sink);
  std::optional<Error> StartReceiving(runtime::Robot& robot);

  /// Stops receiving (deletes the reader and writer; waits for a listener
  /// call in progress).
  ~BeaconRadio();
  BeaconRadio(const BeaconRadio&) = delete;
  BeaconRadio& operator=(const BeaconRadio&) = delete;

  /// runtime::Radio: encodes and writes this round's beacon.
  void Broadcast(const wire::Beacon& beacon) override;

  BeaconRadioCounters counters() const;
  /// Beacon readers this radio's writer has matched (other robots, and any
  /// other reader of rt/syrof/beacon); 0 on error.
  uint32_t matched_readers() const;
  /// Rejections by reason (SampleVerdict), for the robot's Status_.
  const SampleCounters& sample_counters() const { return filter_.counters(); }

  /// The senders whose beacon of `round` this radio accepted while `round`
  /// was still its own current round (in-round delivery, measured before the
  /// channel's simulated loss). Kept for the newest kHeardRounds rounds; an
  /// older round gives an empty set.
  static constexpr size_t kHeardRounds = 4;
  wire::MemberSet HeardInRound(int64_t round) const;

  /// sim_dds::AgreedRoundOffset over each sender's latest well-formed
  /// sample (in kRoundWindow or not), measured against expected_round.
  int64_t AgreedRoundOffset(int64_t since_round) const;
  /// Forgets every sender's offset: after the robot changed its count, the
  /// offsets measured against the old one are stale.
  void ForgetRoundOffsets();

 private:
  BeaconRadio(const Participant& participant, BeaconRadioOptions options);
  static void OnDataAvailable(dds_entity_t reader, void* self);
  void TakeAll(dds_entity_t reader);
  // One sample arriving now, through the checks, the channel and the sink;
  // under receive_mutex_.
  void Arrive(uint16_t sender, uint32_t round, std::span<const uint8_t> bytes);
  // The holder thread: releases held samples at their due instants.
  void ReleaseHeld();

  const Participant* participant_;
  BeaconRadioOptions options_;
  BeaconSink sink_;  // set before the reader exists, never after
  dds_entity_t writer_ = 0;
  dds_entity_t reader_ = 0;
  std::vector<uint8_t> send_bytes_;

  // The receive side, on Cyclone's threads: one at a time.
  mutable std::mutex receive_mutex_;
  SampleFilter filter_;
  lab::world::Channel channel_;
  struct HeardRound {
    int64_t round = -1;
    wire::MemberSet senders;
  };
  std::array<HeardRound, kHeardRounds> heard_{};  // by round % kHeardRounds; under receive_mutex_
  std::vector<SenderRoundOffset> offsets_;  // per sender; under receive_mutex_
  int64_t ExpectedRound() const;

  // Samples hold_ns made late, by due instant (steady clock, ns), and the
  // thread that lets them arrive; started with the reader when hold_ns is set.
  struct HeldSample {
    uint16_t sender = 0;
    uint32_t round = 0;
    std::vector<uint8_t> bytes;
  };
  std::mutex held_mutex_;
  std::condition_variable held_changed_;
  std::multimap<int64_t, HeldSample> held_;  // under held_mutex_
  bool stop_holding_ = false;                // under held_mutex_
  std::thread holder_;

  std::atomic<uint64_t> sent_{0};
  std::atomic<uint64_t> send_failed_{0};
  std::atomic<uint64_t> received_{0};
  std::atomic<uint64_t> held_count_{0};
  std::atomic<uint64_t> lost_{0};
  std::atomic<uint64_t> delivered_{0};
};

}  // namespace syrof::sim_dds
