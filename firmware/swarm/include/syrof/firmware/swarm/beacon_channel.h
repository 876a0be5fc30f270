// The channel of syrof-firmware-swarm: the beacons the robots send on their
// radio UARTs, put to the lab's channel model (lab/world/channel.h: a hash
// of seed, the world's round the beacon was sent in, sender and receiver:
// the lab's and the DDS world's decision) and the scenario's radio faults
// (deaf, mute, partitions, on world time), and delivered to each receiver
// as a ReceivedBeacon frame half a radio round of the sender's clock after
// it was sent (scaled to host time by the sender's measured clock rate,
// guest_clock.h), as the lab's radio delivers (the robots' round alignment
// expects that latency: firmware/robot/robot_image.h, kBeaconLatencyNs).
// --base-station: a base station's radio that hears every beacon at once,
// with no loss, on a Unix socket (docs/bridge.md).
#pragma once

#include <cstdint>
#include <map>
#include <optional>
#include <span>
#include <string>
#include <vector>

#include "syrof/firmware/drivers/radio_link.h"
#include "syrof/firmware/swarm/fault_player.h"
#include "syrof/firmware/swarm/firmware_metrics.h"
#include "syrof/firmware/swarm/swarm_options.h"
#include "syrof/firmware/swarm/swarm_robot.h"
#include "syrof/lab/scenario/scenario.h"
#include "syrof/lab/sim/world_player.h"
#include "syrof/lab/world/channel.h"

namespace syrof::firmware::swarm {

// A ReceivedBeacon frame on its way to robot `to`.
struct Delivery {
  int64_t due_ns = 0;
  uint16_t to = 0;
  std::vector<uint8_t> bytes;
};

// --base-station: the listener, the client connected to it (one at a time)
// and the frames it has not taken yet.
struct BaseStationLink {
  static constexpr size_t kMaxPending = 64 * 1024;
  int listener = -1;
  int client = -1;
  std::vector<uint8_t> pending;
  uint8_t sequence = 0;
  int64_t frames = 0;   // ReceivedBeacon frames queued for a client
  int64_t dropped = 0;  // beacons not queued: no client, or it stopped reading

  // Takes a waiting client (non-blocking), then writes what it takes now;
  // a client that went away is closed, and the next one accepted.
  void Serve();
  // One beacon heard on the air, as the base station's radio frames it.
  void Hear(std::span<const uint8_t> beacon);
};

class BeaconChannel {
 public:
  /// The arguments outlive the channel; `swarm` holds the robots' radio
  /// links, `player` says who is running (paused, crashed and absent robots
  /// hear nothing: the lab's Listening).
  BeaconChannel(const Options& options, const lab::scenario::Scenario& scenario, std::vector<Robot>& swarm,
                const lab::sim::WorldPlayer& player);

  /// Reads robot `i`'s radio link, whose poll entry returned `revents`, at
  /// host time `now`, the world's clock at `world_clock_ns` and
  /// `host_per_world` host ns a world ns: each SendBeacon frame is put in
  /// flight to every robot the channel delivers it to.
  void ReadRadio(uint16_t i, short revents, int64_t now, double world_clock_ns, double host_per_world);
  /// Writes the deliveries due by host time `now` to running robots' radios.
  void Deliver(int64_t now);
  /// When the next delivery is due (host time), if one is in flight.
  std::optional<int64_t> next_due_ns() const;

  BaseStationLink& base_station() { return base_station_; }
  /// Serves the base station's client a last time, closes it and says how
  /// many beacons it got.
  void CloseBaseStation();

  BeaconCounts counts() const;
  int64_t stress_late_beacons() const { return stress_late_beacons_; }
  int64_t partitioned_beacons() const { return channel_.partitioned(); }

 private:
  void OnBeacon(uint16_t i, const drivers::Frame& frame, int64_t now);
  int64_t BeaconRound(const Robot& robot) const;
  int64_t DeliveryDue(const Robot& robot, int64_t round, int64_t now) const;
  void CountLateness(const Robot& robot, int64_t round);

  const Options& options_;
  const uint16_t robots_;
  const int64_t period_ns_;
  std::vector<Robot>& swarm_;
  const lab::sim::WorldPlayer& player_;
  // The radio faults, and the scenario's channel (its model, loss and
  // partitions; --loss overrides the loss), drawing from the same seed
  // stream as the lab's.
  const RadioFaults radio_faults_;
  lab::world::Channel channel_;
  int64_t latency_ns_;
  // This pass's world clock (ReadRadio).
  double world_clock_ns_ = 0;
  double host_per_world_ = 1;
  // By due instant: the latency is scaled by each sender's clock rate.
  std::multimap<int64_t, Delivery> in_flight_;
  BaseStationLink base_station_;  // --base-station
  int64_t link_errors_ = 0;
  int64_t offered_ = 0, delivered_ = 0;
  // Without alignment: beacons that reached the host more than the latency
  // after their boundary (delivered at once), and after the next boundary
  // (too late for their round anywhere: a receiver steps them a round late).
  int64_t late_beacons_ = 0, beacons_past_their_round_ = 0;
  int64_t stress_late_beacons_ = 0;  // --stress: beacons it delivered late
};

}  // namespace syrof::firmware::swarm
