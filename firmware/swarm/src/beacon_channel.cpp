#include "syrof/firmware/swarm/beacon_channel.h"

#include <poll.h>
#include <sys/socket.h>
#include <unistd.h>

#include <algorithm>
#include <cerrno>
#include <cmath>
#include <cstdio>

#include "syrof/firmware/swarm/world_grid.h"
#include "syrof/lab/sim/run_parts.h"
#include "syrof/lab/sim/stress.h"
#include "syrof/process/fd.h"
#include "syrof/registry/tasks.h"

namespace syrof::firmware::swarm {

void BaseStationLink::Serve() {
  if (listener < 0) return;
  if (client < 0) {
    client = accept4(listener, nullptr, nullptr, SOCK_NONBLOCK | SOCK_CLOEXEC);
    pending.clear();
  }
  while (client >= 0 && !pending.empty()) {
    const ssize_t written = send(client, pending.data(), pending.size(), MSG_DONTWAIT | MSG_NOSIGNAL);
    if (written < 0 && (errno == EAGAIN || errno == EWOULDBLOCK || errno == EINTR)) return;
    if (written <= 0) {
      close(client);
      client = -1;
      return;
    }
    pending.erase(pending.begin(), pending.begin() + written);
  }
}

void BaseStationLink::Hear(std::span<const uint8_t> beacon) {
  uint8_t wire_bytes[drivers::kMaxWireBytes];
  const auto encoded = drivers::EncodeFrame(drivers::MakeReceivedBeacon(sequence, -50, beacon), wire_bytes);
  if (client < 0 || !encoded.ok() || pending.size() + encoded.value() > kMaxPending) {
    ++dropped;
    return;
  }
  ++sequence;
  ++frames;
  pending.insert(pending.end(), wire_bytes, wire_bytes + encoded.value());
}

BeaconChannel::BeaconChannel(const Options& options, const lab::scenario::Scenario& scenario, std::vector<Robot>& swarm,
                             const lab::sim::WorldPlayer& player)
    : options_(options),
      robots_(static_cast<uint16_t>(swarm.size())),
      period_ns_(syrof::registry::kDefaultRadioRoundNs),
      swarm_(swarm),
      player_(player),
      radio_faults_(scenario),
      channel_(scenario.channel, robots_, lab::sim::ChannelSeed(scenario.seed)),
      latency_ns_(static_cast<int64_t>(options.latency_ms * 1e6)) {}

std::optional<int64_t> BeaconChannel::next_due_ns() const {
  if (in_flight_.empty()) return std::nullopt;
  return in_flight_.begin()->first;
}

void BeaconChannel::CloseBaseStation() {
  if (base_station_.listener < 0) return;
  base_station_.Serve();
  if (base_station_.client >= 0) close(base_station_.client);
  close(base_station_.listener);
  std::fprintf(stderr, "syrof-firmware-swarm: base station: %lld beacons sent to %s, %lld not (no client, or it lagged)\n",
               static_cast<long long>(base_station_.frames), options_.base_station.c_str(),
               static_cast<long long>(base_station_.dropped));
}

BeaconCounts BeaconChannel::counts() const {
  return BeaconCounts{offered_, delivered_, link_errors_, late_beacons_, beacons_past_their_round_};
}

void BeaconChannel::Deliver(int64_t now) {
  while (!in_flight_.empty() && in_flight_.begin()->first <= now) {
    const Delivery& delivery = in_flight_.begin()->second;
    if (swarm_[delivery.to].radio >= 0 && player_.running(delivery.to)) {
      (void)process::WriteAll(swarm_[delivery.to].radio, delivery.bytes.data(), delivery.bytes.size());
    }
    in_flight_.erase(in_flight_.begin());
  }
}

void BeaconChannel::ReadRadio(uint16_t i, short revents, int64_t now, double world_clock_ns, double host_per_world) {
  world_clock_ns_ = world_clock_ns;
  host_per_world_ = host_per_world;
  Robot& robot = swarm_[i];
  if (robot.radio < 0 || (revents & (POLLIN | POLLHUP)) == 0) return;
  uint8_t buffer[4096];
  const ssize_t count = read(robot.radio, buffer, sizeof buffer);
  if (count <= 0) {
    close(robot.radio);
    robot.radio = -1;
  }
  for (ssize_t k = 0; k < count; ++k) {
    const drivers::DecodeEvent event = robot.decoder.Push(buffer[k]);
    if (event == drivers::DecodeEvent::kError) ++link_errors_;
    if (event != drivers::DecodeEvent::kFrame) continue;
    const drivers::Frame& frame = robot.decoder.frame();
    if (frame.kind != drivers::FrameKind::kSendBeacon) continue;
    OnBeacon(i, frame, now);
  }
}

// The world round a beacon of `robot` reaching the host now was sent in
// (world_grid.h). A robot whose round alignment moved its boundaries
// earlier (--align 1) may be counted a round short.
int64_t BeaconChannel::BeaconRound(const Robot& robot) const {
  return swarm::BeaconRound(robot.switched_on_at, world_clock_ns_, period_ns_);
}

// Host time at which a beacon of `robot` (of world round `round`, read now)
// reaches the others. With the robots on the world's grid (no alignment):
// --latency-ms after the sender's boundary on the world's clock, as the
// lab's radio delivers, and at once when that instant has passed. With
// round alignment the boundaries move: --latency-ms of the sender's clock
// after the beacon reached the host.
int64_t BeaconChannel::DeliveryDue(const Robot& robot, int64_t round, int64_t now) const {
  if (*options_.align) return now + robot.clock_rate.ToHost(latency_ns_);
  const double boundary_ns = BoundaryOf(robot.switched_on_at, round, period_ns_);
  const double ahead_ns = (boundary_ns + static_cast<double>(latency_ns_) - world_clock_ns_) * host_per_world_;
  return now + std::max<int64_t>(0, std::llround(ahead_ns));
}

void BeaconChannel::CountLateness(const Robot& robot, int64_t round) {
  if (*options_.align) return;
  const double late_ns = world_clock_ns_ - BoundaryOf(robot.switched_on_at, round, period_ns_);
  if (late_ns > static_cast<double>(latency_ns_)) ++late_beacons_;
  if (late_ns > static_cast<double>(period_ns_)) ++beacons_past_their_round_;
}

// Robot `i`'s SendBeacon frame, read at host time `now`: a ReceivedBeacon
// frame in flight to each robot the channel delivers it to.
void BeaconChannel::OnBeacon(uint16_t i, const drivers::Frame& frame, int64_t now) {
  Robot& robot = swarm_[i];
  robot.beacon_ns.push_back(now);
  robot.last_boundary_ns = now;
  if (base_station_.listener >= 0) {
    base_station_.Hear(std::span<const uint8_t>(frame.beacon.data(), frame.beacon_length));
  }
  const int64_t beacon_round = BeaconRound(robot);
  robot.boundary_ns_of_round.emplace(beacon_round, now);
  const int64_t due_ns = DeliveryDue(robot, beacon_round, now);
  CountLateness(robot, beacon_round);
  // The lab and the DDS world ask the channel about the same (round,
  // sender, receiver), at the round's start.
  const double sent_s = static_cast<double>(beacon_round * period_ns_) * 1e-9;
  for (uint16_t to = 0; to < robots_; ++to) {
    // Paused, crashed and absent robots hear nothing (the lab's Listening).
    if (to == i || swarm_[to].radio < 0 || !player_.running(to)) continue;
    ++offered_;
    // Partitions, deaf and mute are on world time, as the lab's.
    if (!channel_.Delivers(i, to, beacon_round, sent_s) || radio_faults_.Blocked(i, to, sent_s)) continue;
    ++delivered_;
    uint8_t wire_bytes[drivers::kMaxWireBytes];
    const auto encoded = drivers::EncodeFrame(
        drivers::MakeReceivedBeacon(frame.sequence, -60,
                                    std::span<const uint8_t>(frame.beacon.data(), frame.beacon_length)),
        wire_bytes);
    // --stress: this link's beacon late by a seeded 10-200 ms (lab/sim/stress.h).
    const int64_t late_ns =
        lab::sim::SampleDelayNs(options_.stress, lab::sim::DelayedStream::kBeacon, i, to, beacon_round);
    stress_late_beacons_ += late_ns > 0 ? 1 : 0;
    if (encoded.ok()) {
      in_flight_.emplace(due_ns + late_ns,
                         Delivery{due_ns + late_ns, to, std::vector<uint8_t>(wire_bytes, wire_bytes + encoded.value())});
    }
  }
}

}  // namespace syrof::firmware::swarm
