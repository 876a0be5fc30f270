// What the bridge's tests share: beacons and link frames for a small swarm,
// and a RoundSink and a BeaconOutput that remember everything they get.
#pragma once

#include <cstdint>
#include <span>
#include <tuple>
#include <vector>

#include "syrof/bridge/base_station.h"
#include "syrof/firmware/drivers/radio_link.h"
#include "syrof/lab/replay/replay.h"
#include "syrof/lab/replay/round_sink.h"
#include "syrof/wire/beacon_codec.h"

namespace syrof::bridge::testing {

inline constexpr uint16_t kSwarm = 4;

inline lab::replay::Header HeaderFor(uint16_t robots) {
  lab::replay::Header header;
  header.radio_round_ns = 50'000'000;
  header.arena_width_m = 4;
  header.arena_height_m = 4;
  header.scenario_name = "bridge-test";
  header.app_name = "robots on the air";
  for (uint16_t i = 0; i < robots; ++i) header.robots.push_back(lab::replay::RobotInfo{i, 0, 0.1f, {}});
  return header;
}

inline wire::Beacon MakeBeacon(uint16_t robot, uint16_t epoch, wire::Phase phase = wire::Phase::kProgress,
                               wire::Mode mode = wire::Mode::kCooperative) {
  wire::Beacon beacon;
  beacon.robot_id = robot;
  beacon.epoch = epoch;
  beacon.phase = phase;
  beacon.mode = mode;
  beacon.snapshot.x_mm = static_cast<int16_t>(100 * robot + epoch);
  beacon.snapshot.y_mm = static_cast<int16_t>(-50 * robot);
  beacon.snapshot.heading_mrad = static_cast<int16_t>(10 * robot);
  for (uint16_t member = 0; member < kSwarm; ++member) beacon.waiting.set(member);
  return beacon;
}

inline std::vector<uint8_t> EncodeBeacon(const wire::Beacon& beacon, uint16_t swarm = kSwarm) {
  std::vector<uint8_t> bytes(wire::EncodedSize(swarm));
  const auto encoded = wire::Encode(beacon, swarm, bytes);
  if (!encoded.ok()) bytes.clear();
  return bytes;
}

/// The wire bytes of one frame (0x00, stuffed body, 0x00).
inline std::vector<uint8_t> FrameBytes(const firmware::drivers::Frame& frame) {
  uint8_t out[firmware::drivers::kMaxWireBytes];
  const auto encoded = firmware::drivers::EncodeFrame(frame, out);
  if (!encoded.ok()) return {};
  return std::vector<uint8_t>(out, out + encoded.value());
}

inline std::vector<uint8_t> ReceivedFrame(const std::vector<uint8_t>& beacon_bytes, uint8_t sequence = 0,
                                          int8_t rssi_dbm = -60) {
  return FrameBytes(firmware::drivers::MakeReceivedBeacon(sequence, rssi_dbm, beacon_bytes));
}

inline void Append(std::vector<uint8_t>& stream, const std::vector<uint8_t>& bytes) {
  stream.insert(stream.end(), bytes.begin(), bytes.end());
}

/// Every call a RoundSink received.
class RecordingSink final : public lab::replay::RoundSink {
 public:
  void OnHeader(const lab::replay::Header& header) override { headers.push_back(header); }
  void OnRound(uint32_t index, int64_t time_ns, std::span<const lab::replay::RobotFrame> robots,
               std::span<const lab::replay::Event> events, std::span<const lab::replay::RobotMap>) override {
    lab::replay::Round round;
    round.index = index;
    round.time_ns = time_ns;
    round.robots.assign(robots.begin(), robots.end());
    round.events.assign(events.begin(), events.end());
    rounds.push_back(round);
  }
  void OnFinish(bool complete) override { finishes.push_back(complete); }

  std::vector<lab::replay::Header> headers;
  std::vector<lab::replay::Round> rounds;
  std::vector<bool> finishes;
};

/// Every beacon a BeaconOutput received: (robot id, wire bytes, rssi, round).
class RecordingOutput final : public BeaconOutput {
 public:
  void OnBeacon(const wire::Beacon& beacon, std::span<const uint8_t> wire_bytes, int8_t rssi_dbm,
                uint32_t round) override {
    beacons.emplace_back(beacon.robot_id, std::vector<uint8_t>(wire_bytes.begin(), wire_bytes.end()), rssi_dbm, round);
  }
  std::vector<std::tuple<uint16_t, std::vector<uint8_t>, int8_t, uint32_t>> beacons;
};

}  // namespace syrof::bridge::testing
