// StressPlayer (firmware/swarm/stress_player.h): the plan's robot stalls
// become one SIGSTOP and one SIGCONT each, on world time; the world's come
// back as the host's own stall; robots the scenario does not run are left
// alone; nothing stays stopped at the end.
#include "syrof/firmware/swarm/stress_player.h"

#include <gtest/gtest.h>

#include <map>
#include <set>
#include <vector>

namespace syrof::firmware::swarm {
namespace {

constexpr int64_t kTenSeconds = 10'000'000'000;
constexpr int64_t kStepNs = 10'000'000;  // the host's physics step

struct SignalLog {
  std::vector<std::pair<uint16_t, bool>> calls;
  std::map<uint16_t, bool> stopped;

  StressPlayer::Signal signal() {
    return [this](uint16_t robot, bool stop) {
      EXPECT_NE(stopped[robot], stop) << "robot " << robot << (stop ? " stopped twice" : " continued while running");
      stopped[robot] = stop;
      calls.emplace_back(robot, stop);
    };
  }
};

lab::sim::StressOptions Seeded(uint64_t seed) {
  lab::sim::StressOptions options;
  options.seed = seed;
  options.stalls_per_second = 8;
  return options;
}

TEST(StressPlayerTest, EveryRobotStallStopsOnceAndContinuesAtItsEndAndTheWorldsComeBack) {
  const lab::sim::StressOptions options = Seeded(9);
  StressPlayer player(options, kTenSeconds, 4);
  SignalLog log;
  const auto always = [](uint16_t) { return true; };
  int64_t world_stalled_ns = 0;
  int64_t world_stalls_due = 0;
  for (const lab::sim::Stall& stall : player.plan()) world_stalls_due += stall.target == lab::sim::kStallWorld;
  for (int64_t t = 0; t <= kTenSeconds; t += kStepNs) {
    world_stalled_ns += player.Play(t, always, log.signal());
    for (const auto& [robot, stopped] : log.stopped) {
      if (!stopped) continue;
      // Stopped only within some stall of that robot (a step late at most).
      bool inside = false;
      for (const lab::sim::Stall& stall : player.plan()) {
        inside |= stall.target == robot && stall.at_ns <= t && t < stall.at_ns + stall.duration_ns + kStepNs;
      }
      EXPECT_TRUE(inside) << "robot " << robot << " stopped at " << t;
    }
  }
  player.EndAll(always, log.signal());
  ASSERT_EQ(player.plan().size(), 80u);  // 8 a second for 10 s
  EXPECT_GT(player.robot_stalls(), 0);
  EXPECT_EQ(player.world_stalls(), world_stalls_due);
  EXPECT_GT(world_stalled_ns, 0);
  int64_t stops = 0, continues = 0;
  for (const auto& [robot, stop] : log.calls) (stop ? stops : continues) += 1;
  EXPECT_EQ(stops, player.robot_stalls());
  EXPECT_EQ(continues, stops);
  for (const auto& [robot, stopped] : log.stopped) EXPECT_FALSE(stopped) << "robot " << robot;
}

TEST(StressPlayerTest, TheSameSeedSignalsTheSameRobotsAtTheSameWorldTimes) {
  std::vector<std::vector<std::pair<uint16_t, bool>>> runs;
  for (int run = 0; run < 2; ++run) {
    StressPlayer player(Seeded(21), kTenSeconds, 3);
    SignalLog log;
    std::vector<std::pair<uint16_t, bool>> timeline;
    for (int64_t t = 0; t <= kTenSeconds; t += kStepNs) {
      const size_t before = log.calls.size();
      (void)player.Play(t, [](uint16_t) { return true; }, log.signal());
      for (size_t k = before; k < log.calls.size(); ++k) timeline.emplace_back(static_cast<uint16_t>(t / kStepNs), log.calls[k].second);
    }
    runs.push_back(timeline);
  }
  EXPECT_FALSE(runs[0].empty());
  EXPECT_EQ(runs[0], runs[1]);
}

TEST(StressPlayerTest, ARobotTheScenarioDoesNotRunIsNeverSignalled) {
  StressPlayer player(Seeded(3), kTenSeconds, 4);
  SignalLog log;
  // Robot 2 is paused (or crashed, or not yet joined) all along; robot 1
  // stops running at 5 s, while the stress may hold it.
  int64_t now = 0;
  const auto running = [&now](uint16_t robot) { return robot != 2 && !(robot == 1 && now >= 5'000'000'000); };
  for (now = 0; now <= kTenSeconds; now += kStepNs) (void)player.Play(now, running, log.signal());
  player.EndAll(running, log.signal());
  std::set<uint16_t> signalled;
  for (const auto& [robot, stop] : log.calls) signalled.insert(robot);
  EXPECT_EQ(signalled.count(2), 0u);
  EXPECT_EQ(signalled.count(0), 1u);
}

TEST(StressPlayerTest, WithoutASeedNothingHappens) {
  StressPlayer player(lab::sim::StressOptions{}, kTenSeconds, 4);
  SignalLog log;
  for (int64_t t = 0; t <= kTenSeconds; t += kStepNs) EXPECT_EQ(player.Play(t, [](uint16_t) { return true; }, log.signal()), 0);
  EXPECT_TRUE(log.calls.empty());
  EXPECT_TRUE(player.plan().empty());
}

}  // namespace
}  // namespace syrof::firmware::swarm
