// RoundRecorder (lab/sim/round_recorder.h): what every runtime records of its
// rounds, fed by hand as a runtime would, and read back from the metrics,
// the goal and the replay it writes.
#include "syrof/lab/sim/round_recorder.h"

#include <gtest/gtest.h>

#include <span>
#include <sstream>
#include <string>
#include <vector>

#include "syrof/lab/replay/reader.h"
#include "syrof/lab/sim/run_parts.h"

namespace syrof::lab::sim {
namespace {

constexpr int64_t kRecorderRoundNs = 50'000'000;

scenario::Scenario LoadRecorderScenario(const std::string& text) {
  scenario::LoadResult loaded = scenario::LoadScenarioText(text, "test.yaml");
  EXPECT_TRUE(loaded.ok()) << (loaded.error ? loaded.error->ToString() : "");
  return *loaded.scenario;
}

// Two robots 0.4 m apart: gathered within 0.5 m.
const char* const kTwoRobots = R"(
name: recorder
arena: { width_m: 4, height_m: 4 }
robots:
  placement: explicit
  poses: [{ x_m: 1, y_m: 1 }, { x_m: 1.4, y_m: 1 }]
timing: { duration_s: 10 }
app: builtin:idle
)";

const char* const kTwoRobotsWithGoal = R"(
name: recorder
arena: { width_m: 4, height_m: 4 }
robots:
  placement: explicit
  poses: [{ x_m: 1, y_m: 1 }, { x_m: 1.4, y_m: 1 }]
timing: { duration_s: 10 }
app: builtin:idle
goal:
  - { check: gathered, name: together, radius_m: 0.5, deadline_s: 9 }
)";

// A runtime's round of its robots, every one running, a member, with an
// estimate `error_m` off its true x.
struct RoundParts {
  std::vector<metrics::RobotRound> robots;
  std::vector<replay::RobotFrame> frames;
  std::vector<int64_t> boundaries_ns;
  std::vector<replay::Event> events;
  std::vector<replay::RobotMap> maps;

  RoundParts(const scenario::Scenario& scenario, int64_t round, double error_m) {
    for (const scenario::RobotSpec& spec : scenario.robots) {
      metrics::RobotRound entry;
      entry.id = spec.id;
      entry.running = entry.member = entry.sync_member = true;
      entry.epoch_mode = wire::Mode::kCooperative;
      entry.estimate_valid = true;
      entry.true_x_m = spec.x_m;
      entry.true_y_m = spec.y_m;
      entry.est_x_m = spec.x_m + error_m;
      entry.est_y_m = spec.y_m;
      robots.push_back(entry);
      replay::RobotFrame frame;
      frame.id = spec.id;
      frame.presence = replay::Presence::kRunning;
      frames.push_back(frame);
      boundaries_ns.push_back(round * kRecorderRoundNs);
    }
  }

  RecordedRound Round(int64_t round, std::function<std::vector<goals::RobotPose>()> poses) {
    return RecordedRound{round, (round + 1) * kRecorderRoundNs, robots, boundaries_ns, frames, events, maps, std::move(poses)};
  }
};

std::vector<goals::RobotPose> PosesGathered() { return {{0, 1.0, 1.0, 0.1}, {1, 1.4, 1.0, 0.1}}; }
std::vector<goals::RobotPose> PosesApart() { return {{0, 1.0, 1.0, 0.1}, {1, 3.0, 3.0, 0.1}}; }

sync::LDMap RecorderMap(uint16_t epoch, std::initializer_list<uint16_t> members) {
  sync::LDMap map{};
  map.epoch = epoch;
  map.mode = wire::Mode::kCooperative;
  for (const uint16_t id : members) map.members.set(id);
  return map;
}

replay::Event RecorderEvent(int64_t time_ns, uint16_t robot) {
  replay::Event event{};
  event.kind = replay::EventKind::kBecameJoiner;
  event.robot = robot;
  event.other = replay::kNoRobot;
  event.time_ns = time_ns;
  return event;
}

// Every robot starts when asked.
class StartingRuntime final : public RobotRuntime {
 public:
  bool StartRobot(uint16_t /*id*/, int64_t /*world_ns*/, bool /*resume*/) override { return true; }
  void StopRobot(uint16_t /*id*/, int64_t /*world_ns*/, StopReason /*reason*/) override {}
};

// A run's recorder and its world, the robots running.
struct RecorderFixture {
  explicit RecorderFixture(const char* text)
      : scenario(LoadRecorderScenario(text)),
        world(scenario.arena, Bodies(scenario)),
        recorder(scenario, CollectorConfigFor(scenario)),
        player(scenario, world, recorder.collector()) {
    player.StartPresentRobots(runtime);
  }

  metrics::Metrics Finish(int64_t rounds) {
    const RunEnd end{static_cast<double>(rounds * kRecorderRoundNs) * 1e-9, 2.5, rounds};
    return recorder.Finish(recorder.Facts(end, player, world));
  }

  scenario::Scenario scenario;
  world::World world;
  RoundRecorder recorder;
  WorldPlayer player;
  StartingRuntime runtime;
};

TEST(RoundRecorder, CollectorConfigForTakesTheScenariosRoundAndSilence) {
  scenario::Scenario scenario = LoadRecorderScenario(kTwoRobots);
  scenario.timing.radio_round_s = 0.04;
  scenario.timing.silence_rounds = 9;

  const metrics::CollectorConfig config = CollectorConfigFor(scenario);

  EXPECT_EQ(config.robots, 2);
  EXPECT_EQ(config.radio_round_ns, 40'000'000);
  EXPECT_EQ(config.silence_rounds, 9);
}

TEST(RoundRecorder, EveryRoundReachesTheCollector) {
  RecorderFixture fixture(kTwoRobots);

  for (int64_t round = 0; round < 3; ++round) {
    RoundParts parts(fixture.scenario, round, 0.1);
    fixture.recorder.RecordRound(parts.Round(round, [] { return PosesApart(); }));
  }
  const metrics::Metrics metrics = fixture.Finish(3);

  EXPECT_EQ(metrics.estimation.samples, 6);  // two robots, three rounds
  ASSERT_TRUE(metrics.estimation.max_error_m.has_value());
  EXPECT_NEAR(*metrics.estimation.max_error_m, 0.1, 1e-9);
  EXPECT_EQ(metrics.round_phase.rounds_measured, 3);
}

TEST(RoundRecorder, EpochStartsReachTheCollector) {
  RecorderFixture fixture(kTwoRobots);

  fixture.recorder.OnEpochStart(0, 0, 10'000'000, RecorderMap(1, {0, 1}));
  fixture.recorder.OnEpochStart(1, 0, 20'000'000, RecorderMap(1, {0, 1}));
  RoundParts parts(fixture.scenario, 0, 0);
  fixture.recorder.RecordRound(parts.Round(0, [] { return PosesGathered(); }));
  const metrics::Metrics metrics = fixture.Finish(1);

  EXPECT_EQ(metrics.epochs_started, 1);
  EXPECT_EQ(metrics.epoch_starts, 2);
}

TEST(RoundRecorder, WithoutGoalChecksThePosesAreNotAskedFor) {
  RecorderFixture fixture(kTwoRobots);
  int asked = 0;

  fixture.recorder.OnEpochStart(0, 0, 0, RecorderMap(1, {0, 1}));
  RoundParts parts(fixture.scenario, 0, 0);
  fixture.recorder.RecordRound(parts.Round(0, [&] {
    ++asked;
    return PosesGathered();
  }));

  EXPECT_EQ(asked, 0);
}

// The goal is judged on the epoch samples: with robots apart at epoch 3's
// round and together at epoch 4's, it holds from epoch 4 on.
TEST(RoundRecorder, TheGoalSamplesTheNewestEpochOfARound) {
  RecorderFixture fixture(kTwoRobotsWithGoal);
  RoundParts parts(fixture.scenario, 0, 0);

  fixture.recorder.OnEpochStart(0, 0, 0, RecorderMap(3, {0, 1}));
  fixture.recorder.RecordRound(parts.Round(0, [] { return PosesApart(); }));
  // In one round an older epoch, then two newer ones: one sample, the newest's.
  fixture.recorder.OnEpochStart(1, 1, 0, RecorderMap(2, {0, 1}));
  fixture.recorder.OnEpochStart(0, 1, 0, RecorderMap(4, {0, 1}));
  fixture.recorder.OnEpochStart(1, 1, 0, RecorderMap(5, {0, 1}));
  fixture.recorder.OnEpochStart(0, 1, 0, RecorderMap(4, {0, 1}));
  fixture.recorder.RecordRound(parts.Round(1, [] { return PosesGathered(); }));
  // No newer epoch: no sample, though the robots are apart now.
  fixture.recorder.OnEpochStart(1, 2, 0, RecorderMap(5, {0, 1}));
  fixture.recorder.RecordRound(parts.Round(2, [] { return PosesApart(); }));
  const metrics::Metrics metrics = fixture.Finish(3);

  EXPECT_EQ(metrics.goal.source, "scenario");
  ASSERT_EQ(metrics.goal.checks.size(), 1U);
  const metrics::GoalCheckResult& check = metrics.goal.checks[0];
  EXPECT_EQ(check.samples, 2);
  ASSERT_TRUE(check.held_from_epoch.has_value());
  EXPECT_EQ(*check.held_from_epoch, 5);
  ASSERT_TRUE(check.held_from_s.has_value());
  EXPECT_DOUBLE_EQ(*check.held_from_s, 0.1);  // the end of round 1
  EXPECT_TRUE(check.passed) << check.reason;   // the final poses are the world's: gathered
}

// Epochs wrap from 65535 to 0: 0 is newer and sampled.
TEST(RoundRecorder, AnEpochAfterTheWrapIsNewer) {
  RecorderFixture fixture(kTwoRobotsWithGoal);
  RoundParts parts(fixture.scenario, 0, 0);

  fixture.recorder.OnEpochStart(0, 0, 0, RecorderMap(65535, {0, 1}));
  fixture.recorder.RecordRound(parts.Round(0, [] { return PosesApart(); }));
  fixture.recorder.OnEpochStart(0, 1, 0, RecorderMap(0, {0, 1}));
  fixture.recorder.RecordRound(parts.Round(1, [] { return PosesGathered(); }));
  const metrics::Metrics metrics = fixture.Finish(2);

  ASSERT_EQ(metrics.goal.checks.size(), 1U);
  EXPECT_EQ(metrics.goal.checks[0].samples, 2);
  ASSERT_TRUE(metrics.goal.checks[0].held_from_epoch.has_value());
  EXPECT_EQ(*metrics.goal.checks[0].held_from_epoch, 0);
}

TEST(RoundRecorder, FactsCarryTheRunsEndAndTheBuiltinGoalWithoutChecks) {
  RecorderFixture fixture(kTwoRobots);

  const metrics::RunFacts facts = fixture.recorder.Facts(RunEnd{1.5, 2.5, 30}, fixture.player, fixture.world);

  EXPECT_DOUBLE_EQ(facts.sim_seconds, 1.5);
  EXPECT_DOUBLE_EQ(facts.wall_seconds, 2.5);
  EXPECT_EQ(facts.radio_rounds, 30);
  EXPECT_EQ(facts.robots, 2);
  EXPECT_EQ(facts.scenario, "recorder");
  EXPECT_NE(facts.goal.source, "scenario");
  EXPECT_EQ(facts.goal.app, "builtin:idle");
}

// Agreement is measured by the runtimes that see the app's returns (the
// lab, the DDS robots' reports) and null for the one that does not (the
// firmware's consoles), never zeros that read like a measurement.
TEST(RoundRecorder, AgreementIsMeasuredOnlyWhereTheAppsReturnsAreSeen) {
  RecorderFixture unseen(kTwoRobots);
  RecorderFixture measured(kTwoRobots);
  measured.recorder.MeasureAgreement();
  RecorderFixture split(kTwoRobots);
  using Call = metrics::AgreementTracker::Call;
  split.recorder.OnAppState(0, 10, Call::kNewRound, 3, /*cooperative=*/true, /*map_fingerprint=*/77, /*state=*/1);
  split.recorder.OnAppState(1, 10, Call::kNewRound, 3, true, 77, 2);
  const RunEnd end{1.0, 1.0, 20};

  EXPECT_FALSE(unseen.recorder.Finish(unseen.recorder.Facts(end, unseen.player, unseen.world)).agreement.has_value());
  const auto none = measured.recorder.Finish(measured.recorder.Facts(end, measured.player, measured.world)).agreement;
  ASSERT_TRUE(none.has_value());
  EXPECT_EQ(none->cooperative_epochs, 0);
  const auto two = split.recorder.Finish(split.recorder.Facts(end, split.player, split.world)).agreement;
  ASSERT_TRUE(two.has_value());
  EXPECT_EQ(two->cooperative_epochs, 1);
  EXPECT_EQ(two->agreed_epochs, 0);
}

// The replay's round: frames and events as given (the lab's events are in
// the order they happened, which its times need not show), maps sorted.
TEST(RoundRecorder, WritesTheRoundWithItsMapsInRobotOrder) {
  RecorderFixture fixture(kTwoRobots);
  std::stringstream out;
  fixture.recorder.OpenReplay(out);
  RoundParts parts(fixture.scenario, 0, 0);
  parts.events = {RecorderEvent(30'000'000, 1), RecorderEvent(20'000'000, 0)};
  parts.maps = {replay::RobotMap{1, ToEpochMap(RecorderMap(7, {0, 1}))}, replay::RobotMap{0, ToEpochMap(RecorderMap(7, {0, 1}))}};

  fixture.recorder.RecordRound(parts.Round(0, [] { return PosesGathered(); }));
  fixture.recorder.FinishReplay();

  EXPECT_FALSE(fixture.recorder.replay_error().has_value());
  replay::Reader reader(out);
  replay::Header header;
  ASSERT_TRUE(reader.ReadHeader(header)) << reader.error();
  EXPECT_EQ(header.scenario_name, "recorder");
  replay::Round round;
  ASSERT_TRUE(reader.Next(round)) << reader.error();
  EXPECT_EQ(round.index, 0U);
  EXPECT_EQ(round.time_ns, kRecorderRoundNs);
  ASSERT_EQ(round.robots.size(), 2U);
  ASSERT_EQ(round.events.size(), 2U);
  EXPECT_EQ(round.events[0].robot, 1);
  EXPECT_EQ(round.events[1].robot, 0);
  ASSERT_EQ(round.maps.size(), 2U);
  EXPECT_EQ(round.maps[0].robot, 0);
  EXPECT_EQ(round.maps[1].robot, 1);
  EXPECT_FALSE(reader.Next(round));
  EXPECT_TRUE(reader.complete()) << reader.error();
}

// A RoundSink that keeps what it was told.
struct KeepingSink : replay::RoundSink {
  void OnHeader(const replay::Header& header) override { headers.push_back(header); }
  void OnRound(uint32_t index, int64_t time_ns, std::span<const replay::RobotFrame> robots,
               std::span<const replay::Event> events, std::span<const replay::RobotMap> maps) override {
    replay::Round round;
    round.index = index;
    round.time_ns = time_ns;
    round.robots.assign(robots.begin(), robots.end());
    round.events.assign(events.begin(), events.end());
    round.maps.assign(maps.begin(), maps.end());
    rounds.push_back(round);
  }
  void OnFinish(bool complete) override { finishes.push_back(complete); }
  std::vector<replay::Header> headers;
  std::vector<replay::Round> rounds;
  std::vector<bool> finishes;
};

TEST(RoundRecorder, SinksGetWhatTheReplayGetsWithOrWithoutOne) {
  for (const bool with_replay : {false, true}) {
    RecorderFixture fixture(kTwoRobots);
    KeepingSink sink;
    fixture.recorder.AddSink(&sink);
    std::stringstream out;
    if (with_replay) fixture.recorder.OpenReplay(out);
    EXPECT_TRUE(fixture.recorder.replaying());  // a runtime builds maps for a sink too
    RoundParts parts(fixture.scenario, 0, 0);
    parts.events = {RecorderEvent(30'000'000, 1), RecorderEvent(20'000'000, 0)};
    parts.maps = {replay::RobotMap{1, ToEpochMap(RecorderMap(7, {0, 1}))},
                  replay::RobotMap{0, ToEpochMap(RecorderMap(7, {0, 1}))}};

    fixture.recorder.RecordRound(parts.Round(0, [] { return PosesGathered(); }));
    fixture.recorder.FinishReplay();
    fixture.recorder.FinishReplay();  // once is what the sinks hear

    ASSERT_EQ(sink.headers.size(), 1U);
    EXPECT_EQ(sink.headers[0], ReplayHeader(fixture.scenario));
    ASSERT_EQ(sink.rounds.size(), 1U);
    ASSERT_EQ(sink.rounds[0].maps.size(), 2U);
    EXPECT_EQ(sink.rounds[0].maps[0].robot, 0);  // sorted by robot, as the replay's
    EXPECT_EQ(sink.rounds[0].events[0].robot, 1);  // in the order given
    EXPECT_EQ(sink.finishes, std::vector<bool>{true});
    if (with_replay) {
      replay::Reader reader(out);
      replay::Header header;
      ASSERT_TRUE(reader.ReadHeader(header));
      EXPECT_EQ(header, sink.headers[0]);
      replay::Round round;
      ASSERT_TRUE(reader.Next(round));
      EXPECT_EQ(round.index, sink.rounds[0].index);
      EXPECT_EQ(round.time_ns, sink.rounds[0].time_ns);
      EXPECT_EQ(round.robots, sink.rounds[0].robots);
      EXPECT_EQ(round.events, sink.rounds[0].events);
      ASSERT_EQ(round.maps.size(), 2U);
      EXPECT_EQ(round.maps[1].robot, sink.rounds[0].maps[1].robot);
      EXPECT_EQ(*round.maps[1].map, *sink.rounds[0].maps[1].map);
    }
  }
}

TEST(RoundRecorder, WithoutAReplayNothingIsWrittenAndNothingFails) {
  RecorderFixture fixture(kTwoRobots);
  RoundParts parts(fixture.scenario, 0, 0);
  parts.maps = {replay::RobotMap{0, nullptr}};  // a map the writer would refuse

  fixture.recorder.RecordRound(parts.Round(0, [] { return PosesGathered(); }));
  fixture.recorder.FinishReplay();

  EXPECT_FALSE(fixture.recorder.replaying());
  EXPECT_FALSE(fixture.recorder.replay_error().has_value());
}

TEST(RoundRecorder, AReplayTheFormatCannotHoldSaysWhy) {
  RecorderFixture fixture(kTwoRobots);
  std::stringstream out;
  fixture.recorder.OpenReplay(out);
  RoundParts parts(fixture.scenario, 0, 0);
  parts.frames[1].id = 0;  // ids must increase

  fixture.recorder.RecordRound(parts.Round(0, [] { return PosesGathered(); }));

  ASSERT_TRUE(fixture.recorder.replay_error().has_value());
  EXPECT_FALSE(fixture.recorder.replay_error()->message.empty());
}

TEST(OrderByTime, SortsByTimeAndKeepsTheOrderOfEqualTimes) {
  std::vector<replay::Event> events = {RecorderEvent(30, 0), RecorderEvent(10, 1), RecorderEvent(30, 2), RecorderEvent(10, 3)};

  OrderByTime(events);

  std::vector<uint16_t> robots;
  for (const replay::Event& event : events) robots.push_back(event.robot);
  EXPECT_EQ(robots, (std::vector<uint16_t>{1, 3, 0, 2}));
}

}  // namespace
}  // namespace syrof::lab::sim
