// FaultPlayer: a scenario's faults turned into what the swarm host does to
// its qemu processes, on the radio-round grid of world time.
#include "syrof/firmware/swarm/fault_player.h"

#include <gtest/gtest.h>

#include <string>
#include <vector>

#include "syrof/lab/scenario/scenario.h"

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

std::vector<Timed> Play(FaultPlayer& player, int64_t until_ns) {
  std::vector<Timed> all;
  for (int64_t t = kPhysicsStepNs; t <= until_ns; t += kPhysicsStepNs) {
    for (const HostAction& action : player.Advance(t)) all.push_back({t, action});
  }
  return all;
}

TEST(FaultPlayerTest, EachFaultBecomesItsHostActionOnTheRadioRoundGrid) {
  // The join at 2.01 s takes effect at the next boundary, 2.05 s; the pause
  // from 4 to 6 s resumes one round before 6 s (lab::sim::FaultSchedule).
  FaultPlayer player(Load("  - { join: 3, at_s: 2.01 }\n"
                          "  - { pause: 2, at_s: 4, until_s: 6 }\n"
                          "  - { crash: 1, at_s: 10 }\n"),
                     kGridNs);
  EXPECT_EQ(player.presence(3), Presence::kAbsent);
  EXPECT_EQ(player.presence(1), Presence::kRunning);

  const std::vector<Timed> actions = Play(player, 12'000'000'000);

  const std::vector<Timed> expected = {
      {2'050'000'000, {HostAction::Kind::kLaunch, 3}},
      {4'000'000'000, {HostAction::Kind::kStop, 2}},
      {5'950'000'000, {HostAction::Kind::kContinue, 2}},
      {10'000'000'000, {HostAction::Kind::kKill, 1}},
  };
  EXPECT_EQ(actions, expected);
  EXPECT_EQ(player.presence(0), Presence::kRunning);
  EXPECT_EQ(player.presence(1), Presence::kCrashed);
  EXPECT_EQ(player.presence(2), Presence::kRunning);
  EXPECT_EQ(player.presence(3), Presence::kRunning);
}

TEST(FaultPlayerTest, APauseRunningPastTheEndIsNeverContinuedAndACrashAfterAPauseKills) {
  // The loader refuses a crash inside a pause; one right at its end comes
  // after the resume. A pause may end after the run (robot 2).
  FaultPlayer player(Load("  - { pause: 1, at_s: 1, until_s: 3 }\n"
                          "  - { crash: 1, at_s: 3 }\n"
                          "  - { pause: 2, at_s: 3.5, until_s: 30 }\n"),
                     kGridNs);

  const std::vector<Timed> actions = Play(player, 5'000'000'000);

  const std::vector<Timed> expected = {
      {1'000'000'000, {HostAction::Kind::kStop, 1}},
      {2'950'000'000, {HostAction::Kind::kContinue, 1}},
      {3'000'000'000, {HostAction::Kind::kKill, 1}},
      {3'500'000'000, {HostAction::Kind::kStop, 2}},
  };
  EXPECT_EQ(actions, expected);
  EXPECT_EQ(player.presence(1), Presence::kCrashed);
  EXPECT_EQ(player.presence(2), Presence::kPaused);
}

TEST(FaultPlayerTest, DeafAndMuteBlockBeaconsOnlyInTheirWindow) {
  FaultPlayer player(Load("  - { mute: 0, at_s: 1, until_s: 2 }\n"
                          "  - { deaf: 3, at_s: 5, until_s: 6 }\n"),
                     kGridNs);

  EXPECT_FALSE(player.Blocked(0, 1, 0.95));
  EXPECT_TRUE(player.Blocked(0, 1, 1.0));
  EXPECT_TRUE(player.Blocked(0, 3, 1.95));
  EXPECT_FALSE(player.Blocked(0, 1, 2.0));
  EXPECT_FALSE(player.Blocked(1, 0, 1.5));  // mute: 0 still hears
  EXPECT_TRUE(player.Blocked(1, 3, 5.5));
  EXPECT_FALSE(player.Blocked(3, 1, 5.5));  // deaf: 3 is still heard
  // Radio faults change no process.
  EXPECT_TRUE(Play(player, 7'000'000'000).empty());
}

TEST(FaultPlayerTest, ALateRobotRunsUntilTheOthersStop) {
  EXPECT_EQ(FaultPlayer::RemainingSeconds(14, 2'000'000'000), 12);
  EXPECT_EQ(FaultPlayer::RemainingSeconds(14, 2'050'000'000), 12);  // rounded up: it may stop a little later
  EXPECT_EQ(FaultPlayer::RemainingSeconds(5, 6'000'000'000), 1);    // at least a second
}

}  // namespace
}  // namespace syrof::firmware::swarm
