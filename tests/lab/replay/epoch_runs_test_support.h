// Synthetic runs for the tests of the epoch table, the comparison and `syrof
// compare`: every robot starts epoch after epoch in step, and a test changes
// one thing (a robot's mode or members at one epoch, a position in one round)
// to see it reported.
#pragma once

#include <algorithm>
#include <cstdint>
#include <memory>
#include <string>
#include <vector>

#include "replay_test_support.h"
#include "syrof/lab/replay/replay.h"

namespace syrof::lab::replay::testing {

inline constexpr uint8_t kCooperative = 0;
inline constexpr uint8_t kAutonomous = 1;

struct SyntheticRun {
  Header header;
  std::vector<Round> rounds;

  std::string Bytes() const { return Write(header, rounds).bytes; }
};

// The round in which every robot starts epoch `epoch` in a SteppedRun.
inline uint32_t StartRoundOf(uint16_t epoch) { return 2u * epoch; }

// `robot_count` robots (ids 0 .. n-1) that start epochs first_epoch,
// first_epoch + 1, ... (`epochs` of them, wrapping at 65536) together, one
// every two rounds (round 2e, counting e from 1 for the first epoch), each
// COOPERATIVE with every robot a member (one shared map). Every round has a
// frame per robot: robot i at (i, round/100) m.
inline SyntheticRun SteppedRun(uint16_t robot_count, uint16_t epochs, uint16_t first_epoch = 1) {
  SyntheticRun run;
  run.header = SampleHeader();
  run.header.robots.clear();
  for (uint16_t id = 0; id < robot_count; ++id) run.header.robots.push_back({id, 0, 0.1f, {}});
  std::vector<uint16_t> everyone;
  for (uint16_t id = 0; id < robot_count; ++id) everyone.push_back(id);
  const uint32_t last_round = StartRoundOf(epochs) + 1;
  for (uint32_t index = 1; index <= last_round; ++index) {
    Round round;
    round.index = index;
    round.time_ns = int64_t{50'000'000} * index;
    for (uint16_t id = 0; id < robot_count; ++id) {
      round.robots.push_back(Frame(id, Presence::kRunning, 0, static_cast<float>(id), static_cast<float>(index) / 100));
    }
    if (index % 2 == 0 && index / 2 <= epochs) {
      const auto epoch = static_cast<uint16_t>(first_epoch + index / 2 - 1);
      const std::shared_ptr<const EpochMap> map = Map(epoch, kCooperative, everyone);
      for (uint16_t id = 0; id < robot_count; ++id) {
        round.events.push_back({EventKind::kEpochStart, id, kNoRobot, epoch, kCooperative, round.time_ns});
        round.maps.push_back({id, map});
      }
    }
    run.rounds.push_back(std::move(round));
  }
  return run;
}

// The round of `run` with index `index`.
inline Round& RoundAt(SyntheticRun& run, uint32_t index) {
  return *std::find_if(run.rounds.begin(), run.rounds.end(), [&](const Round& round) { return round.index == index; });
}

// Makes `robot`'s start in round `index` one of `mode` with `members`.
inline void SetStart(SyntheticRun& run, uint32_t index, uint16_t robot, uint8_t mode, std::vector<uint16_t> members) {
  Round& round = RoundAt(run, index);
  for (Event& event : round.events) {
    if (event.kind == EventKind::kEpochStart && event.robot == robot) event.mode = mode;
  }
  for (RobotMap& entry : round.maps) {
    if (entry.robot == robot) entry.map = Map(entry.map->epoch, mode, members);
  }
}

// Gives `member` the app payload `payload` in every map of round `index`
// (every robot's, as the one COOPERATIVE map they share would).
inline void SetPayload(SyntheticRun& run, uint32_t index, uint16_t member, std::vector<uint8_t> payload) {
  for (RobotMap& entry : RoundAt(run, index).maps) {
    auto map = std::make_shared<EpochMap>(*entry.map);
    for (MapMember& holder : map->members) {
      if (holder.id == member) holder.payload = payload;
    }
    entry.map = std::move(map);
  }
}

// Removes `robot`'s start (event and map) from round `index`.
inline void DropStart(SyntheticRun& run, uint32_t index, uint16_t robot) {
  Round& round = RoundAt(run, index);
  std::erase_if(round.events, [&](const Event& event) { return event.kind == EventKind::kEpochStart && event.robot == robot; });
  std::erase_if(round.maps, [&](const RobotMap& entry) { return entry.robot == robot; });
}

// Keeps the rounds up to index `last` only.
inline void CutAfter(SyntheticRun& run, uint32_t last) {
  std::erase_if(run.rounds, [&](const Round& round) { return round.index > last; });
}

}  // namespace syrof::lab::replay::testing
