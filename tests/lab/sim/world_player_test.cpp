// WorldPlayer (lab/sim/world_player.h): the robots' lifecycle, the faults
// and the join wait, as every runtime plays them, against a runtime that
// only records what it is told.
#include "syrof/lab/sim/world_player.h"

#include <gtest/gtest.h>

#include <string>
#include <vector>

#include "syrof/lab/sim/run_parts.h"

namespace syrof::lab::sim {
namespace {

constexpr int64_t kPlayerRoundNs = 50'000'000;
constexpr int64_t kPlayerStepNs = 10'000'000;

// Records every call as "start 1 @1000 resume" and the like.
class RecordingRuntime final : public RobotRuntime {
 public:
  bool StartRobot(uint16_t id, int64_t world_ns, bool resume) override {
    calls.push_back("start " + std::to_string(id) + " @" + std::to_string(world_ns / 1'000'000) +
                    (resume ? " resume" : ""));
    return id != refuses;
  }
  void StopRobot(uint16_t id, int64_t world_ns, StopReason reason) override {
    const char* why = reason == StopReason::kCrash ? "crash" : reason == StopReason::kPause ? "pause" : "app";
    calls.push_back("stop " + std::to_string(id) + " @" + std::to_string(world_ns / 1'000'000) + " " + why);
  }
  EventStamp Stamp(uint16_t id) const override { return EventStamp{static_cast<uint16_t>(100 + id), wire::Mode::kAutonomous}; }

  std::vector<std::string> calls;
  uint16_t refuses = 0xFFFF;  // StartRobot fails for this robot
};

scenario::Scenario LoadPlayerScenario(const std::string& text) {
  scenario::LoadResult loaded = scenario::LoadScenarioText(text, "test.yaml");
  EXPECT_TRUE(loaded.ok()) << (loaded.error ? loaded.error->ToString() : "");
  return *loaded.scenario;
}

// Robot 0 stands at (1, 1); robots 1 and 2 far from it; robot 3 joins at 1 s
// at (1.6, 1).
const char* const kFourRobots = R"(
name: player
arena: { width_m: 6, height_m: 6 }
robots:
  placement: explicit
  poses: [{ x_m: 1, y_m: 1 }, { x_m: 4, y_m: 4 }, { x_m: 4, y_m: 1 }, { x_m: 1.6, y_m: 1 }]
timing: { duration_s: 20 }
faults:
  - { join: 3, at_s: 1 }
  - { pause: 1, at_s: 2, until_s: 3 }
  - { crash: 2, at_s: 2.5 }
  - { crash: 1, at_s: 6 }
app: builtin:idle
)";

struct Fixture {
  explicit Fixture(const std::string& text)
      : scenario(LoadPlayerScenario(text)),
        world(scenario.arena, Bodies(scenario)),
        collector(metrics::CollectorConfig{static_cast<uint16_t>(scenario.robots.size()), kPlayerRoundNs, 6}),
        player(scenario, world, collector) {}

  // Plays every physics step up to and including `until_ns`.
  void PlayUntil(int64_t until_ns) {
    for (; now_ns <= until_ns; now_ns += kPlayerStepNs) {
      player.PlayFaults(now_ns, runtime);
      world.Step(now_ns, static_cast<double>(kPlayerStepNs) * 1e-9);
      player.TakeContacts(runtime);
    }
  }

  scenario::Scenario scenario;
  world::World world;
  metrics::Collector collector;
  WorldPlayer player;
  RecordingRuntime runtime;
  int64_t now_ns = 0;
};

std::vector<replay::EventKind> Kinds(const std::vector<replay::Event>& events) {
  std::vector<replay::EventKind> kinds;
  for (const replay::Event& event : events) kinds.push_back(event.kind);
  return kinds;
}

// Robot 0 at (1.5, 1); robot 1, 0.3 m away, joins at 0.5 s: its start disc
// holds robot 0. `more` adds lines (a `safety:` key, faults after the join).
std::string JoinerBesideRobot0(const std::string& more = "", const std::string& faults = "") {
  return "name: joiner\n"
         "arena: { width_m: 6, height_m: 6 }\n"
         "robots:\n"
         "  placement: explicit\n"
         "  poses: [{ x_m: 1.5, y_m: 1 }, { x_m: 1.8, y_m: 1 }]\n"
         "timing: { duration_s: 20 }\n"
         "app: builtin:idle\n" +
         more +
         "faults:\n"
         "  - { join: 1, at_s: 0.5 }\n" +
         faults;
}

TEST(WorldPlayerTest, RobotsPresentAtStartStartAtZeroWithoutEvents) {
  Fixture f(kFourRobots);

  f.player.StartPresentRobots(f.runtime);

  EXPECT_EQ(f.runtime.calls, (std::vector<std::string>{"start 0 @0", "start 1 @0", "start 2 @0"}));
  EXPECT_EQ(f.player.lifecycle(0), Lifecycle::kRunning);
  EXPECT_EQ(f.player.lifecycle(3), Lifecycle::kAbsent);
  EXPECT_EQ(f.player.scored_from_ns(0), kEstimationWarmupNs);
  EXPECT_EQ(f.world.presence(3), world::BodyPresence::kAbsent);
  EXPECT_TRUE(f.player.TakeEvents().empty());
}

TEST(WorldPlayerTest, FaultsPlayOnTheGridWithOneStampedEventEach) {
  Fixture f(kFourRobots);
  f.player.StartPresentRobots(f.runtime);
  f.runtime.calls.clear();

  f.PlayUntil(7'000'000'000);

  EXPECT_EQ(f.runtime.calls, (std::vector<std::string>{
                                 "start 3 @1000",          // join, disc clear (0.6 m from robot 0)
                                 "stop 1 @2000 pause",     //
                                 "stop 2 @2500 crash",     //
                                 "start 1 @2950 resume",   // one round before the grid point after 3 s
                                 "stop 1 @6000 crash",     //
                             }));
  const std::vector<replay::Event> events = f.player.TakeEvents();
  EXPECT_EQ(Kinds(events), (std::vector<replay::EventKind>{replay::EventKind::kJoin, replay::EventKind::kPause,
                                                           replay::EventKind::kCrash, replay::EventKind::kResume,
                                                           replay::EventKind::kCrash}));
  EXPECT_EQ(events[0].robot, 3);
  EXPECT_EQ(events[0].time_ns, 1'000'000'000);
  EXPECT_EQ(events[0].epoch, 103);
  EXPECT_EQ(events[0].mode, static_cast<uint8_t>(wire::Mode::kAutonomous));
  EXPECT_EQ(events[0].other, replay::kNoRobot);
  EXPECT_EQ(f.player.lifecycle(1), Lifecycle::kCrashed);
  EXPECT_EQ(f.player.lifecycle(2), Lifecycle::kCrashed);
  EXPECT_EQ(f.player.lifecycle(3), Lifecycle::kRunning);
  EXPECT_EQ(f.player.scored_from_ns(1), 2'950'000'000 + kEstimationWarmupNs);
  EXPECT_EQ(f.world.presence(2), world::BodyPresence::kStopped);  // a crashed body stays an obstacle
  EXPECT_EQ(f.world.presence(3), world::BodyPresence::kActive);
}

// Robot 1's start disc holds robot 0: it waits (one JOIN_WAIT, counted in
// the metrics) and is switched on at the first step that finds the disc
// clear, once robot 0 has driven away.
TEST(WorldPlayerTest, AJoinerWaitsForItsStartDiscToClear) {
  Fixture f(JoinerBesideRobot0());
  f.player.StartPresentRobots(f.runtime);
  f.runtime.calls.clear();

  f.PlayUntil(1'000'000'000);
  EXPECT_EQ(f.player.lifecycle(1), Lifecycle::kWaitingToJoin);
  EXPECT_EQ(f.player.presence(1), replay::Presence::kAbsent);
  EXPECT_TRUE(f.runtime.calls.empty());
  motion::DriveCommand away{};
  away.vx_mps = -0.3f;
  f.world.SetDrive(0, away);
  f.PlayUntil(3'000'000'000);
  f.world.SetDrive(0, motion::DriveCommand{});
  f.PlayUntil(6'000'000'000);

  ASSERT_EQ(f.runtime.calls.size(), 1u);
  EXPECT_EQ(f.player.lifecycle(1), Lifecycle::kRunning);
  const std::vector<replay::Event> events = f.player.TakeEvents();
  ASSERT_EQ(Kinds(events), (std::vector<replay::EventKind>{replay::EventKind::kJoinWait, replay::EventKind::kJoin}));
  EXPECT_EQ(events[0].time_ns, 500'000'000);
  EXPECT_GT(events[1].time_ns, 1'000'000'000);
  const metrics::SafetyMetrics safety = f.collector.Finish(metrics::RunFacts{}).safety;
  EXPECT_EQ(safety.join_waits, 1);
  // The wait's start and end reach the metrics (safety.joiner_waits).
  ASSERT_EQ(safety.joiner_waits.size(), 1u);
  EXPECT_EQ(safety.joiner_waits[0].robot, 1);
  EXPECT_EQ(safety.joiner_waits[0].from_ns, 500'000'000);
  EXPECT_EQ(safety.joiner_waits[0].joined_ns, std::optional<int64_t>(events[1].time_ns));
}

// With safety off nobody waits.
TEST(WorldPlayerTest, WithoutSafetyAJoinerStartsAtOnce) {
  Fixture f(JoinerBesideRobot0("safety: off\n"));
  f.player.StartPresentRobots(f.runtime);

  f.PlayUntil(500'000'000);

  EXPECT_EQ(f.player.lifecycle(1), Lifecycle::kRunning);
  EXPECT_EQ(Kinds(f.player.TakeEvents()), (std::vector<replay::EventKind>{replay::EventKind::kJoin}));
}

TEST(WorldPlayerTest, ACrashWhileWaitingToJoinMeansItNeverStarts) {
  Fixture f(JoinerBesideRobot0("", "  - { crash: 1, at_s: 1 }\n"));
  f.player.StartPresentRobots(f.runtime);
  f.runtime.calls.clear();

  f.PlayUntil(1'500'000'000);

  EXPECT_TRUE(f.runtime.calls.empty());
  EXPECT_EQ(f.player.lifecycle(1), Lifecycle::kCrashed);
  EXPECT_EQ(f.world.presence(1), world::BodyPresence::kAbsent);  // it never arrived
  EXPECT_EQ(Kinds(f.player.TakeEvents()),
            (std::vector<replay::EventKind>{replay::EventKind::kJoinWait, replay::EventKind::kCrash}));
  // It never joined: its wait has no end.
  const metrics::SafetyMetrics safety = f.collector.Finish(metrics::RunFacts{}).safety;
  ASSERT_EQ(safety.joiner_waits.size(), 1u);
  EXPECT_FALSE(safety.joiner_waits[0].joined_ns.has_value());
}

TEST(WorldPlayerTest, ARobotThatCannotStartCountsAsCrashed) {
  Fixture f(kFourRobots);
  f.runtime.refuses = 3;
  f.player.StartPresentRobots(f.runtime);

  f.PlayUntil(1'000'000'000);

  EXPECT_EQ(f.player.lifecycle(3), Lifecycle::kCrashed);
  EXPECT_EQ(f.world.presence(3), world::BodyPresence::kStopped);
}

TEST(WorldPlayerTest, AnAppFaultStopsTheRobotForGood) {
  Fixture f(kFourRobots);
  f.player.AppFaulted(3, 0, f.runtime);  // in init, before its join
  f.player.StartPresentRobots(f.runtime);
  f.runtime.calls.clear();

  f.player.AppFaulted(0, 500'000'000, f.runtime);
  f.PlayUntil(3'500'000'000);

  EXPECT_EQ(f.player.lifecycle(0), Lifecycle::kCrashed);
  EXPECT_EQ(f.world.presence(0), world::BodyPresence::kStopped);
  // Robot 3's join finds its app faulted: it arrives crashed, never started.
  EXPECT_EQ(f.player.lifecycle(3), Lifecycle::kCrashed);
  EXPECT_EQ(f.world.presence(3), world::BodyPresence::kStopped);
  ASSERT_GE(f.runtime.calls.size(), 1u);
  EXPECT_EQ(f.runtime.calls[0], "stop 0 @500 app");
  for (const std::string& call : f.runtime.calls) EXPECT_EQ(call.find("start 3"), std::string::npos) << call;
}

// The goal is judged over the robots running with a working app: a paused,
// crashed, absent or app-faulted robot is no part of it (the firmware host
// used to count every robot).
TEST(WorldPlayerTest, TheGoalSeesOnlyRobotsRunningWithAWorkingApp) {
  Fixture f(kFourRobots);
  f.player.StartPresentRobots(f.runtime);
  f.PlayUntil(2'000'000'000);  // robot 3 joined, robot 1 paused
  f.player.NoteAppFault(0);    // a robot that stopped its own app

  std::vector<uint16_t> running;
  for (const goals::RobotPose& pose : f.player.RunningPoses()) running.push_back(pose.id);
  const std::vector<apps::GoalPose> final_poses = f.player.FinalPoses();

  EXPECT_EQ(running, (std::vector<uint16_t>{2, 3}));
  ASSERT_EQ(final_poses.size(), 4u);
  EXPECT_FALSE(final_poses[0].present);
  EXPECT_FALSE(final_poses[1].present);
  EXPECT_TRUE(final_poses[2].present);
  EXPECT_TRUE(final_poses[3].present);
  EXPECT_DOUBLE_EQ(final_poses[3].x_m, 1.6);
  EXPECT_EQ(f.player.lifecycle(0), Lifecycle::kRunning);  // noted only: the robot stopped its app itself
}

// At an instant captured earlier (the DDS world's boundary truth), the goal
// sees the robots running then, where they were then; an app fault noted
// since counts as well.
TEST(WorldPlayerTest, TheGoalAtACapturedInstantSeesWhoRanThenWhereTheyWere) {
  Fixture f(kFourRobots);
  f.player.StartPresentRobots(f.runtime);
  f.PlayUntil(500'000'000);  // robots 0, 1 and 2 running; 3 not joined yet
  std::vector<replay::Presence> presence;
  std::vector<world::BodyState> bodies;
  for (uint16_t id = 0; id < 4; ++id) {
    presence.push_back(f.player.presence(id));
    bodies.push_back(f.world.state(id));
  }
  bodies[2].x_m = 3.25;  // where the snapshot says robot 2 was
  f.PlayUntil(2'000'000'000);  // now robot 3 joined, robot 1 paused
  f.player.NoteAppFault(0);

  std::vector<uint16_t> ids;
  std::vector<double> xs;
  for (const goals::RobotPose& pose : f.player.RunningPoses(presence, bodies)) {
    ids.push_back(pose.id);
    xs.push_back(pose.x_m);
  }

  EXPECT_EQ(ids, (std::vector<uint16_t>{1, 2}));
  EXPECT_EQ(xs, (std::vector<double>{4.0, 3.25}));
  std::vector<uint16_t> now;
  for (const goals::RobotPose& pose : f.player.RunningPoses()) now.push_back(pose.id);
  EXPECT_EQ(now, (std::vector<uint16_t>{2, 3}));
}

TEST(WorldPlayerTest, ContactsGoToTheMetricsAndTheReplay) {
  Fixture f(R"(
name: bump
arena: { width_m: 6, height_m: 6 }
robots:
  placement: explicit
  poses: [{ x_m: 1, y_m: 1 }, { x_m: 1.5, y_m: 1 }]
timing: { duration_s: 20 }
app: builtin:idle
)");
  f.player.StartPresentRobots(f.runtime);
  motion::DriveCommand towards{};
  towards.vx_mps = 0.4f;
  f.world.SetDrive(0, towards);

  f.PlayUntil(3'000'000'000);

  const std::vector<replay::Event> events = f.player.TakeEvents();
  ASSERT_FALSE(events.empty());
  EXPECT_EQ(events.front().kind, replay::EventKind::kCollision);
  EXPECT_EQ(events.front().robot, 0);
  EXPECT_EQ(events.front().other, 1);
  EXPECT_EQ(events.front().epoch, 100);
  EXPECT_EQ(f.collector.Finish(metrics::RunFacts{}).collisions.count, 1);
}

}  // namespace
}  // namespace syrof::lab::sim
