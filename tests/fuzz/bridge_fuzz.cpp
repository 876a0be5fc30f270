// libFuzzer target for the base station (bridge/, docs/bridge.md).
//
// Input: any bytes, pushed into a BaseStation in pieces whose sizes the
// input's first bytes choose, with the rounds taken from the stream. Every
// beacon the station hands its outputs must decode again to a beacon of the
// swarm with that robot's id, every round must hold one frame per robot in
// id order, and after the input a valid ReceivedBeacon frame must still be
// accepted whatever came before it: garbage costs rejections, nothing else.
// Anything else stops the run.
#include <algorithm>
#include <cstddef>
#include <cstdint>
#include <span>
#include <vector>

#include "syrof/bridge/base_station.h"
#include "syrof/firmware/drivers/radio_link.h"
#include "syrof/lab/replay/round_sink.h"
#include "syrof/wire/beacon_codec.h"

namespace {

namespace bridge = syrof::bridge;
namespace drivers = syrof::firmware::drivers;
namespace replay = syrof::lab::replay;
namespace wire = syrof::wire;

constexpr uint16_t kSwarm = 5;

void require(bool condition) {
  if (!condition) __builtin_trap();
}

class CheckingSink final : public replay::RoundSink {
 public:
  void OnHeader(const replay::Header&) override {}
  void OnRound(uint32_t index, int64_t time_ns, std::span<const replay::RobotFrame> robots,
               std::span<const replay::Event> events, std::span<const replay::RobotMap>) override {
    require(rounds == 0 || (index > last_index && time_ns >= last_time_ns));
    require(robots.size() == kSwarm);
    for (size_t i = 0; i < robots.size(); ++i) require(robots[i].id == i && robots[i].phase <= 2 && robots[i].mode <= 1);
    for (const replay::Event& event : events) require(event.robot < kSwarm && event.time_ns == time_ns);
    last_index = index;
    last_time_ns = time_ns;
    ++rounds;
  }
  void OnFinish(bool) override {}
  uint64_t rounds = 0;
  uint32_t last_index = 0;
  int64_t last_time_ns = 0;
};

class CheckingOutput final : public bridge::BeaconOutput {
 public:
  void OnBeacon(const wire::Beacon& beacon, std::span<const uint8_t> wire_bytes, int8_t, uint32_t) override {
    const auto again = wire::Decode(wire_bytes, kSwarm);
    require(again.ok() && again.value() == beacon && beacon.robot_id < kSwarm);
    ++beacons;
  }
  uint64_t beacons = 0;
};

replay::Header Header() {
  replay::Header header;
  header.radio_round_ns = 50'000'000;
  header.arena_width_m = 4;
  header.arena_height_m = 4;
  for (uint16_t i = 0; i < kSwarm; ++i) header.robots.push_back(replay::RobotInfo{i, 0, 0.1f, {}});
  return header;
}

}  // namespace

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, size_t size) {
  CheckingSink sink;
  CheckingOutput output;
  bridge::StationConfig config;
  config.rounds_from_stream = true;
  config.silent_rounds = 2;
  bridge::BaseStation station(config, Header(), {&sink}, {&output});
  const size_t piece = size > 0 ? 1 + data[0] % 64 : 1;
  for (size_t at = 0; at < size; at += piece) station.Push(std::span<const uint8_t>(data + at, std::min(piece, size - at)));
  require(station.counts().beacons == output.beacons);

  wire::Beacon beacon;
  beacon.robot_id = 3;
  beacon.epoch = 9;
  std::vector<uint8_t> beacon_bytes(wire::EncodedSize(kSwarm));
  require(wire::Encode(beacon, kSwarm, beacon_bytes).ok());
  uint8_t frame[drivers::kMaxWireBytes];
  const auto length = drivers::EncodeFrame(drivers::MakeReceivedBeacon(0, -40, beacon_bytes), frame);
  require(length.ok());
  const uint64_t before = output.beacons;
  station.Push(std::span<const uint8_t>(frame, length.value()));
  require(output.beacons == before + 1);
  station.Finish(true);
  return 0;
}
