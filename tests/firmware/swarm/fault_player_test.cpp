// HostActions: a scenario's faults, played by the lab's WorldPlayer, turned
// into what the swarm host does to its qemu processes, on the radio-round
// grid of world time.
#include "syrof/firmware/swarm/fault_player.h"

#include <gtest/gtest.h>

#include <string>
#include <vector>

#include "syrof/lab/metrics/collector.h"
#include "syrof/lab/scenario/scenario.h"
#include "syrof/lab/sim/run_parts.h"
#include "syrof/lab/world/world.h"

namespace syrof::firmware::swarm {
namespace {

constexpr int64_t kGridNs = 50'000'000;
constexpr int64_t kPhysicsStepNs = 10'000'000;

lab::scenario::Scenario Load(const std::string& faults) {
  const std::string text =
      "robots: { count: 4, kind: omni, placement: grid, spacing_m: 0.6 }\n"
      "timing: { radio_round_s: 0.05, app_round_s: 1.0, duration_s: 20 }\n"
      "app: builtin:circle\n"
      "faults:\n" + faults;
  const lab::scenario::LoadResult loaded = lab::scenario::LoadScenarioText(text, "test.yaml");
  EXPECT_TRUE(loaded.ok()) << (loaded.error ? loaded.error->ToString() : "");
  return *loaded.scenario;
}

// Every action with the world time it came at, stepping as the host does.
struct Timed {
  int64_t world_ns;
  HostAction action;
  bool operator==(const Timed&) const = default;
};

// The host's side of a run: the world player over HostActions that only
// record (the robots present at start count as launched before the world).
struct Host {
  explicit Host(const lab::scenario::Scenario& s)
      : scenario(s),
        world(scenario.arena, lab::sim::Bodies(scenario)),
        collector(lab::metrics::CollectorConfig{static_cast<uint16_t>(scenario.robots.size()), kGridNs, 6}),
        player(scenario, world, collector),
        actions([this](const HostAction& action, int64_t world_ns) {
          if (world_ns > 0) done.push_back({world_ns, action});
          return true;
        }) {
    player.StartPresentRobots(actions);
  }

  std::vector<Timed> Play(int64_t until_ns) {
    for (int64_t t = kPhysicsStepNs; t <= until_ns; t += kPhysicsStepNs) player.PlayFaults(t, actions);
    return done;
  }

  lab::scenario::Scenario scenario;
  lab::world::World world;
  lab::metrics::Collector collector;
  lab::sim::WorldPlayer player;
  HostActions actions;
  std::vector<Timed> done;
};

TEST(FaultPlayerTest, EachFaultBecomesItsHostActionOnTheRadioRoundGrid) {
  // The join at 2.01 s takes effect at the next boundary, 2.05 s; the pause
  // from 4 to 6 s resumes one round before 6 s (lab::sim::FaultSchedule).
  Host host(Load("  - { join: 3, at_s: 2.01 }\n"
                 "  - { pause: 2, at_s: 4, until_s: 6 }\n"
                 "  - { crash: 1, at_s: 10 }\n"));
  EXPECT_EQ(host.player.lifecycle(3), lab::sim::Lifecycle::kAbsent);
  EXPECT_EQ(host.player.lifecycle(1), lab::sim::Lifecycle::kRunning);

  const std::vector<Timed> actions = host.Play(12'000'000'000);

  const std::vector<Timed> expected = {
      {2'050'000'000, {HostAction::Kind::kSwitchOn, 3}},
      {4'000'000'000, {HostAction::Kind::kStop, 2}},
      {5'950'000'000, {HostAction::Kind::kContinue, 2}},
      {10'000'000'000, {HostAction::Kind::kKill, 1}},
  };
  EXPECT_EQ(actions, expected);
  EXPECT_EQ(host.player.lifecycle(0), lab::sim::Lifecycle::kRunning);
  EXPECT_EQ(host.player.lifecycle(1), lab::sim::Lifecycle::kCrashed);
  EXPECT_EQ(host.player.lifecycle(2), lab::sim::Lifecycle::kRunning);
  EXPECT_EQ(host.player.lifecycle(3), lab::sim::Lifecycle::kRunning);
}

TEST(FaultPlayerTest, APauseRunningPastTheEndIsNeverContinuedAndACrashAfterAPauseKills) {
  // The loader refuses a crash inside a pause; one right at its end comes
  // after the resume. A pause may end after the run (robot 2).
  Host host(Load("  - { pause: 1, at_s: 1, until_s: 3 }\n"
                 "  - { crash: 1, at_s: 3 }\n"
                 "  - { pause: 2, at_s: 3.5, until_s: 30 }\n"));

  const std::vector<Timed> actions = host.Play(5'000'000'000);

  const std::vector<Timed> expected = {
      {1'000'000'000, {HostAction::Kind::kStop, 1}},
      {2'950'000'000, {HostAction::Kind::kContinue, 1}},
      {3'000'000'000, {HostAction::Kind::kKill, 1}},
      {3'500'000'000, {HostAction::Kind::kStop, 2}},
  };
  EXPECT_EQ(actions, expected);
  EXPECT_EQ(host.player.lifecycle(1), lab::sim::Lifecycle::kCrashed);
  EXPECT_EQ(host.player.lifecycle(2), lab::sim::Lifecycle::kPaused);
}

TEST(FaultPlayerTest, DeafAndMuteBlockBeaconsOnlyInTheirWindow) {
  const lab::scenario::Scenario scenario = Load("  - { mute: 0, at_s: 1, until_s: 2 }\n"
                                                "  - { deaf: 3, at_s: 5, until_s: 6 }\n");
  const RadioFaults radio(scenario);

  EXPECT_FALSE(radio.Blocked(0, 1, 0.95));
  EXPECT_TRUE(radio.Blocked(0, 1, 1.0));
  EXPECT_TRUE(radio.Blocked(0, 3, 1.95));
  EXPECT_FALSE(radio.Blocked(0, 1, 2.0));
  EXPECT_FALSE(radio.Blocked(1, 0, 1.5));  // mute: 0 still hears
  EXPECT_TRUE(radio.Blocked(1, 3, 5.5));
  EXPECT_FALSE(radio.Blocked(3, 1, 5.5));  // deaf: 3 is still heard
  // Radio faults change no process.
  EXPECT_TRUE(Host(scenario).Play(7'000'000'000).empty());
}

TEST(FaultPlayerTest, ARobotSwitchedOnLateRunsUntilTheOthersStop) {
  EXPECT_EQ(RemainingMs(14, 0), 14'000u);              // present at the start
  EXPECT_EQ(RemainingMs(14, 2'050'000'000), 11'950u);  // a join at 2.05 s
  EXPECT_EQ(RemainingMs(5, 6'000'000'000), 1u);        // at least a millisecond: 0 would be for ever
}

}  // namespace
}  // namespace syrof::firmware::swarm
