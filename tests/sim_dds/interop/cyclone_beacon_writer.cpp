// The Cyclone side of the interoperability test: N robots' BeaconRadios in
// one process (one participant each, on one domain), broadcasting real
// beacons on the round grid for S seconds.
//
// Usage: cyclone_beacon_writer --domain D --robots N [--seconds S] [--round-ms R] [--garbage 1] [--only I]
//        [--run-id R]
// --only I runs robot I alone (of a swarm of N), one process per robot;
// --origin-ms T puts round 0 at T (CLOCK_REALTIME, ms since the epoch), a
// grid shared by processes started apart (default: this process's start).
// --multicast 0 discovers by unicast only (CycloneOptions::multicast).
// --run-id R stamps every sample with run R (BeaconRadioOptions::run_id;
// default 0): the reader counts only its run's beacons, as a robot does.
// At the end it prints the beacons it sent and its radios' receive counters.
// --garbage 1 adds, every round, a raw Beacon_ sample claiming robot 0 whose
// bytes are not a beacon (a wrong version byte): the reader must call it
// invalid, which shows its checks can fail.
#include <chrono>
#include <cstdio>
#include <cstdlib>
#include <memory>
#include <string>
#include <thread>
#include <vector>

#include "syrof/sim_dds/beacon_radio.h"
#include "syrof/sim_dds/participant.h"
#include "syrof/sim_dds/topics.h"

namespace {

int Usage() {
  std::fprintf(stderr, "usage: cyclone_beacon_writer --domain D --robots N [--seconds S] [--round-ms R] [--garbage 1] [--only I] [--origin-ms T] [--multicast 0] [--run-id R]\n");
  return 2;
}

}  // namespace

int main(int argc, char** argv) {
  using namespace syrof::sim_dds;
  long long origin_ms = -1, run_id = 0;
  long domain = -1, robots = 0, seconds = 20, round_ms = 50, garbage = 0, only = -1, multicast = 1;
  for (int i = 1; i + 1 < argc; i += 2) {
    const std::string flag = argv[i];
    char* end = nullptr;
    const long long value = std::strtoll(argv[i + 1], &end, 10);
    if (*end != '\0' || value < 0) return Usage();
    if (flag == "--origin-ms") {
      origin_ms = value;
      continue;
    }
    if (flag == "--run-id") {
      run_id = value;
      continue;
    }
    if (flag == "--domain") domain = value;
    else if (flag == "--robots") robots = value;
    else if (flag == "--seconds") seconds = value;
    else if (flag == "--round-ms") round_ms = value;
    else if (flag == "--garbage") garbage = value;
    else if (flag == "--only") only = value;
    else if (flag == "--multicast") multicast = value;
    else return Usage();
  }
  if (argc % 2 == 0 || domain < 0 || domain > kMaxDomainId || robots < 1 || robots > 64 || round_ms < 1 || only >= robots) return Usage();
  const long first = only >= 0 ? only : 0;
  const long last = only >= 0 ? only + 1 : robots;

  using Clock = std::chrono::system_clock;
  const Clock::time_point start =
      origin_ms >= 0 ? Clock::time_point(std::chrono::milliseconds(origin_ms)) : Clock::now();
  const auto round_length = std::chrono::milliseconds(round_ms);
  auto current_round = [start, round_length] {
    const auto since = Clock::now() - start;
    return since.count() < 0 ? int64_t{-1} : static_cast<int64_t>(since / round_length);
  };
  std::vector<std::unique_ptr<Participant>> participants;
  std::vector<std::unique_ptr<BeaconRadio>> radios;
  for (long robot = first; robot < last; ++robot) {
    CycloneOptions cyclone;
    cyclone.multicast = multicast != 0;
    ParticipantOrError made = Participant::Create(static_cast<uint32_t>(domain), cyclone);
    if (!made.ok()) {
      std::fprintf(stderr, "cyclone_beacon_writer: %s\n", made.error->ToString().c_str());
      return 1;
    }
    BeaconRadioOptions options;
    options.self = static_cast<uint16_t>(robot);
    options.swarm_size = static_cast<uint16_t>(robots);
    options.radio_round_ns = round_ms * 1'000'000;
    options.current_round = current_round;
    options.run_id = static_cast<uint64_t>(run_id);
    BeaconRadioOrError radio =
        BeaconRadio::Create(*made.participant, options, [](std::span<const uint8_t>, uint16_t, uint32_t) {});
    if (!radio.ok()) {
      std::fprintf(stderr, "cyclone_beacon_writer: %s\n", radio.error->ToString().c_str());
      return 1;
    }
    participants.push_back(std::move(made.participant));
    radios.push_back(std::move(radio.radio));
  }
  dds_entity_t garbage_writer = 0;
  if (garbage != 0) {
    const EntityOrError made = CreateWriter(*participants[0], TopicKind::kBeacon);
    if (!made.ok()) {
      std::fprintf(stderr, "cyclone_beacon_writer: %s\n", made.error->ToString().c_str());
      return 1;
    }
    garbage_writer = made.entity;
  }
  // One beacon per robot per round of the grid; a process that starts (or
  // wakes) late skips the rounds it missed rather than sending them in a burst.
  const int64_t rounds = seconds * 1000 / round_ms;
  for (;;) {
    const int64_t round = current_round();
    if (round >= rounds) break;
    if (round < 0) {
      std::this_thread::sleep_until(start);
      continue;
    }
    for (long robot = first; robot < last; ++robot) {
      syrof::wire::Beacon beacon;
      beacon.robot_id = static_cast<uint16_t>(robot);
      beacon.epoch = static_cast<uint16_t>(round / 20);
      beacon.snapshot.x_mm = static_cast<int16_t>(100 * robot);
      beacon.snapshot.y_mm = static_cast<int16_t>(-50 * robot);
      const uint8_t payload[] = {static_cast<uint8_t>(round)};
      (void)beacon.snapshot.SetPayload(payload);
      radios[static_cast<size_t>(robot - first)]->Broadcast(beacon);
    }
    if (garbage_writer != 0) {
      std::vector<uint8_t> bytes(syrof::wire::EncodedSize(static_cast<uint16_t>(robots)), 0);
      bytes[0] = 0x7F;  // not version 4
      syrof_msg_dds__Beacon_ sample{};
      sample.round = static_cast<uint32_t>(round);
      sample.run_id = static_cast<uint64_t>(run_id);
      sample.wire._maximum = sample.wire._length = static_cast<uint32_t>(bytes.size());
      sample.wire._buffer = bytes.data();
      (void)dds_write(garbage_writer, &sample);
    }
    std::this_thread::sleep_until(start + (round + 1) * round_length);
  }
  BeaconRadioCounters total;
  for (const auto& radio : radios) {
    const BeaconRadioCounters counters = radio->counters();
    total.sent += counters.sent;
    total.received += counters.received;
    total.rejected += counters.rejected;
    total.delivered += counters.delivered;
  }
  std::printf("cyclone_beacon_writer: robots %ld sent %llu received %llu rejected %llu delivered %llu\n", last - first,
              static_cast<unsigned long long>(total.sent), static_cast<unsigned long long>(total.received),
              static_cast<unsigned long long>(total.rejected), static_cast<unsigned long long>(total.delivered));
  return 0;
}
