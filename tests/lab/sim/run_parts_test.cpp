// The engine's pure helpers (run_parts.h): the replay's header and its copy
// of an LDMap.
#include "syrof/lab/sim/run_parts.h"

#include "syrof/lab/scenario/scenario.h"

#include <gtest/gtest.h>

#include <array>
#include <functional>
#include <memory>
#include <vector>

namespace syrof::lab::sim {
namespace {

// Members 2, 5 and 9 with distinct snapshots, phases and payloads.
std::unique_ptr<sync::LDMap> SampleLDMap() {
  auto ldmap = std::make_unique<sync::LDMap>();
  ldmap->epoch = 7;
  ldmap->mode = wire::Mode::kCooperative;
  for (const uint16_t id : {2, 5, 9}) {
    ldmap->members.set(id);
    ldmap->phases[id] = wire::Phase::kVote;
    wire::Snapshot& snapshot = ldmap->snapshots[id];
    snapshot.x_mm = static_cast<int16_t>(100 * id);
    snapshot.y_mm = static_cast<int16_t>(-7 * id);
    snapshot.heading_mrad = static_cast<int16_t>(30 + id);
    snapshot.vx_mm_s = static_cast<int16_t>(id);
    snapshot.vy_mm_s = static_cast<int16_t>(-id);
    const std::array<uint8_t, 3> payload{static_cast<uint8_t>(id), 1, 2};
    EXPECT_EQ(snapshot.SetPayload(std::span<const uint8_t>(payload.data(), id % 4)), wire::WireError::kOk);
  }
  return ldmap;
}

TEST(RunPartsTest, TheReplayHeaderCarriesEachRobotsInputsAndTheMessageFormat) {
  const scenario::LoadResult loaded = scenario::LoadScenarioText(
      "robots: {count: 3}\napp: builtin:idle\ninputs:\n  charge: [10, 870, 5]\n"
      "message: {length: 2, fields: [{name: charge, type: u16be}]}\n",
      "header.yaml");
  ASSERT_TRUE(loaded.ok()) << loaded.error->ToString();

  const replay::Header header = ReplayHeader(*loaded.scenario);

  ASSERT_EQ(header.robots.size(), 3u);
  EXPECT_EQ(header.robots[1].inputs, (std::vector<replay::InputValue>{{"charge", 870}}));
  ASSERT_TRUE(header.message.has_value());
  EXPECT_EQ(header.message->ToString(), "2 bytes: charge u16be");
}

TEST(RunPartsTest, AnLDMapMatchesItsOwnEpochMap) {
  const std::unique_ptr<sync::LDMap> ldmap = SampleLDMap();

  const std::shared_ptr<const replay::EpochMap> map = ToEpochMap(*ldmap);

  ASSERT_EQ(map->members.size(), 3u);
  EXPECT_TRUE(MatchesEpochMap(*map, *ldmap));
}

// Every field ToEpochMap copies, changed one at a time, makes the maps
// differ (so a shared map is never one the robot did not hold).
TEST(RunPartsTest, AnyCopiedFieldChangedIsAMismatch) {
  const std::unique_ptr<sync::LDMap> original = SampleLDMap();
  const std::shared_ptr<const replay::EpochMap> map = ToEpochMap(*original);
  const std::vector<std::function<void(sync::LDMap&)>> changes = {
      [](sync::LDMap& m) { m.epoch = 8; },
      [](sync::LDMap& m) { m.mode = wire::Mode::kAutonomous; },
      [](sync::LDMap& m) { m.members.set(11); },
      [](sync::LDMap& m) { m.members.reset(9); },
      [](sync::LDMap& m) { m.members.reset(2); m.members.set(3); m.snapshots[3] = m.snapshots[2]; },
      [](sync::LDMap& m) { m.phases[5] = wire::Phase::kWait; },
      [](sync::LDMap& m) { m.snapshots[5].x_mm += 1; },
      [](sync::LDMap& m) { m.snapshots[5].y_mm += 1; },
      [](sync::LDMap& m) { m.snapshots[9].heading_mrad += 1; },
      [](sync::LDMap& m) { m.snapshots[9].vx_mm_s += 1; },
      [](sync::LDMap& m) { m.snapshots[2].vy_mm_s += 1; },
      [](sync::LDMap& m) { m.snapshots[5].payload[0] ^= 1; },  // 5 sends 1 byte
      [](sync::LDMap& m) { m.snapshots[5].payload_length = 2; },
  };
  for (size_t i = 0; i < changes.size(); ++i) {
    auto changed = std::make_unique<sync::LDMap>(*original);
    changes[i](*changed);

    EXPECT_FALSE(MatchesEpochMap(*map, *changed)) << "change " << i;
    EXPECT_NE(*ToEpochMap(*changed), *map) << "change " << i;
  }
}

// What ToEpochMap does not copy (unused slots) does not count.
TEST(RunPartsTest, SlotsOfNonMembersDoNotCount) {
  const std::unique_ptr<sync::LDMap> original = SampleLDMap();
  auto changed = std::make_unique<sync::LDMap>(*original);
  changed->snapshots[4].x_mm = 123;
  changed->phases[4] = wire::Phase::kWait;

  EXPECT_TRUE(MatchesEpochMap(*ToEpochMap(*original), *changed));
}

}  // namespace
}  // namespace syrof::lab::sim
