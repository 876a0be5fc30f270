// RemoteWorld (lab/sim/remote_world.h): one instant in the order
// core/registry/tasks.h declares, the boundary truth a round is recorded
// with once its reports are in, the robots' newest reports in the frames and
// the stamps, and the round-start skew; against a runtime and links that
// only record what they are told.
#include "syrof/lab/sim/remote_world.h"

#include <gtest/gtest.h>

#include <string>
#include <vector>

#include "syrof/lab/sensors/sensor_bank.h"

namespace syrof::lab::sim {
namespace {

constexpr int64_t kRemoteRoundNs = 50'000'000;
constexpr int64_t kRemoteStepNs = 10'000'000;

// Robot 0 present at (1, 1), robot 1 joins at 0.1 s at (3, 3).
const char* const kRemoteTwoRobots = R"(
name: remote
arena: { width_m: 6, height_m: 6 }
robots:
  placement: explicit
  poses: [{ x_m: 1, y_m: 1 }, { x_m: 3, y_m: 3 }]
timing: { duration_s: 5 }
faults:
  - { join: 1, at_s: 0.1 }
app: builtin:idle
)";

scenario::Scenario LoadRemoteScenario(const char* text) {
  scenario::LoadResult loaded = scenario::LoadScenarioText(text, "test.yaml");
  EXPECT_TRUE(loaded.ok()) << (loaded.error ? loaded.error->ToString() : "");
  return *loaded.scenario;
}

// Every call, in order, into one log shared by the runtime and the links.
struct CallLog {
  std::vector<std::string> calls;
};

class LoggingRuntime final : public RobotRuntime {
 public:
  explicit LoggingRuntime(CallLog& log) : log_(log) {}
  bool StartRobot(uint16_t id, int64_t /*world_ns*/, bool /*resume*/) override {
    log_.calls.push_back("start " + std::to_string(id));
    return true;
  }
  void StopRobot(uint16_t id, int64_t /*world_ns*/, StopReason /*reason*/) override {
    log_.calls.push_back("stop " + std::to_string(id));
  }

 private:
  CallLog& log_;
};

class LoggingSink final : public sensors::ReadingSink {
 public:
  LoggingSink(CallLog& log, uint16_t id) : log_(log), id_(id) {}
  void OnImu(const estimation::ImuReading& /*reading*/) override { log_.calls.push_back("imu " + std::to_string(id_)); }
  void OnFlow(const estimation::FlowReading& /*reading*/) override {}
  void OnUwb(const estimation::UwbReading& /*reading*/) override {}

 private:
  CallLog& log_;
  uint16_t id_;
};

// Gives every robot the same drive at every instant, and logs when it is asked.
class LoggingLinks final : public RemoteLinks {
 public:
  explicit LoggingLinks(CallLog& log) : log_(log), sinks_{LoggingSink(log, 0), LoggingSink(log, 1)} {}
  void TakeDrives(const std::function<void(uint16_t, const motion::DriveCommand&)>& apply) override {
    log_.calls.push_back("drives");
    if (!giving) return;
    for (uint16_t id = 0; id < 2; ++id) apply(id, drive);
  }
  sensors::ReadingSink* Readings(uint16_t id) override { return closed[id] ? nullptr : &sinks_[id]; }

  motion::DriveCommand drive{};
  bool giving = true;              // false: no drive comes back
  bool closed[2] = {false, false};  // a robot's reading link closed

 private:
  CallLog& log_;
  LoggingSink sinks_[2];
};

class KeptRounds final : public replay::RoundSink {
 public:
  struct Kept {
    uint32_t index = 0;
    int64_t time_ns = 0;
    std::vector<replay::RobotFrame> frames;
    std::vector<replay::Event> events;
  };
  void OnHeader(const replay::Header& /*header*/) override {}
  void OnRound(uint32_t index, int64_t time_ns, std::span<const replay::RobotFrame> robots,
               std::span<const replay::Event> events, std::span<const replay::RobotMap> /*maps*/) override {
    rounds.push_back(Kept{index, time_ns, {robots.begin(), robots.end()}, {events.begin(), events.end()}});
  }
  void OnFinish(bool /*complete*/) override {}
  std::vector<Kept> rounds;
};

struct RemoteFixture {
  explicit RemoteFixture(RemoteRules rules = {})
      : scenario(LoadRemoteScenario(kRemoteTwoRobots)),
        loop(scenario, CollectorConfigFor(scenario), rules),
        runtime(log),
        links(log) {
    loop.recorder().AddSink(&kept);
    loop.player().StartPresentRobots(runtime);
  }

  // Steps every instant up to and including `until_ns`, faults at their instant.
  void StepUntil(int64_t until_ns) {
    for (; now_ns <= until_ns; now_ns += kRemoteStepNs) {
      loop.StepInstant({now_ns, now_ns, static_cast<double>(kRemoteStepNs) * 1e-9, now_ns / kRemoteRoundNs}, runtime,
                       links);
    }
  }

  scenario::Scenario scenario;
  RemoteWorld loop;
  CallLog log;
  LoggingRuntime runtime;
  LoggingLinks links;
  KeptRounds kept;
  int64_t now_ns = kRemoteStepNs;
};

TEST(RemoteWorld, OneInstantPlaysFaultsThenDrivesThenPhysicsThenTheRunningRobotsSensors) {
  RemoteFixture fixture;
  EXPECT_EQ(fixture.log.calls, (std::vector<std::string>{"start 0"}));
  fixture.StepUntil(90'000'000);
  fixture.log.calls.clear();

  fixture.StepUntil(100'000'000);  // robot 1's join is due at this instant

  // The joiner is switched on before the drives are applied and the
  // readings taken: it gets its first reading at the instant it joins.
  EXPECT_EQ(fixture.log.calls, (std::vector<std::string>{"start 1", "drives", "imu 0", "imu 1"}));
}

TEST(RemoteWorld, DrivesReachOnlyRunningRobots) {
  RemoteFixture fixture;
  fixture.links.drive.vx_mps = 0.5f;
  fixture.StepUntil(90'000'000);  // robot 1 absent: its drives are dropped
  EXPECT_GT(fixture.loop.world().state(0).x_m, 1.001);
  EXPECT_DOUBLE_EQ(fixture.loop.world().state(1).x_m, 3.0);

  fixture.links.giving = false;
  fixture.StepUntil(300'000'000);  // joined at 100 ms, it never had a drive: it stands
  EXPECT_DOUBLE_EQ(fixture.loop.world().state(1).x_m, 3.0);
  EXPECT_GT(fixture.loop.world().state(0).x_m, 1.01);  // robot 0 keeps its last drive
}

TEST(RemoteWorld, ARoundIsRecordedWithTheTruthOfItsBoundaryNotTheWorldNow) {
  RemoteFixture fixture;
  fixture.links.drive.vx_mps = 0.5f;
  fixture.StepUntil(100'000'000);  // rounds 1 and 2 begin at 50 and 100 ms
  const double x_at_100ms = fixture.loop.world().state(0).x_m;
  fixture.StepUntil(140'000'000);  // the reports of round 2 arrive later
  ASSERT_GT(fixture.loop.world().state(0).x_m, x_at_100ms + 0.001);

  RemoteRound read;
  fixture.loop.RecordRound(2, /*time_ns_without_truth=*/999, read);

  ASSERT_EQ(fixture.kept.rounds.size(), 1U);
  const KeptRounds::Kept& round = fixture.kept.rounds[0];
  EXPECT_EQ(round.time_ns, 100'000'000);
  EXPECT_FLOAT_EQ(round.frames[0].true_x_m, static_cast<float>(x_at_100ms));
  EXPECT_EQ(round.frames[1].presence, replay::Presence::kRunning);  // joined at 100 ms, at the boundary
  // The world's own events since the boundary before: robot 1's join.
  ASSERT_EQ(round.events.size(), 1U);
  EXPECT_EQ(round.events[0].kind, replay::EventKind::kJoin);

  // A round without a kept truth is the world now, at the time given.
  RemoteRound later;
  fixture.loop.RecordRound(9, 450'000'000, later);
  ASSERT_EQ(fixture.kept.rounds.size(), 2U);
  EXPECT_EQ(fixture.kept.rounds[1].time_ns, 450'000'000);
  EXPECT_FLOAT_EQ(fixture.kept.rounds[1].frames[0].true_x_m, static_cast<float>(fixture.loop.world().state(0).x_m));
}

TEST(RemoteWorld, FramesAndStampsFollowEachRobotsNewestReport) {
  RemoteFixture fixture;
  fixture.StepUntil(60'000'000);
  EXPECT_EQ(fixture.loop.Stamp(0).epoch, 0);  // nothing reported yet

  RemoteRobotState state;
  state.reported = true;
  state.status = 0;
  state.epoch = 4;
  state.epoch_mode = static_cast<uint8_t>(wire::Mode::kCooperative);
  state.est_x_m = 1.25f;
  fixture.loop.NoteRound(0, state);
  EXPECT_EQ(fixture.loop.Stamp(0).epoch, 4);
  EXPECT_EQ(fixture.loop.Stamp(0).mode, wire::Mode::kCooperative);

  RemoteRound read;
  replay::Event became_joiner{};
  became_joiner.kind = replay::EventKind::kBecameJoiner;
  became_joiner.robot = 0;
  became_joiner.time_ns = 55'000'000;
  read.events.push_back(became_joiner);
  fixture.loop.RecordRound(1, 0, read);
  ASSERT_EQ(fixture.kept.rounds.size(), 1U);
  const replay::RobotFrame& frame = fixture.kept.rounds[0].frames[0];
  EXPECT_EQ(frame.status, 0);
  EXPECT_EQ(frame.epoch, 4);
  EXPECT_FLOAT_EQ(frame.est_x_m, 1.25f);
  EXPECT_EQ(fixture.kept.rounds[0].frames[1].status, 1);  // robot 1 never reported: not a member
  EXPECT_EQ(fixture.kept.rounds[0].events.back().kind, replay::EventKind::kBecameJoiner);
}

TEST(RemoteWorld, EachRoundWithTwoReportsGivesOneSkewSampleItsSpread) {
  RemoteFixture fixture;
  RemoteRound first;
  first.activations_ns = {1'000'000'040'000, 1'000'000'010'000, 1'000'000'025'000};
  fixture.loop.RecordRound(1, 50'000'000, first);
  RemoteRound alone;
  alone.activations_ns = {1'050'000'000'000};
  fixture.loop.RecordRound(2, 100'000'000, alone);

  const metrics::SkewStats skew = fixture.loop.skew();
  EXPECT_EQ(skew.samples, 1);
  EXPECT_DOUBLE_EQ(skew.max_us, 30.0);
}

// The run's metrics carry the same figure, for DDS and the firmware alike
// (metrics.json round_start_skew_us); a lab run has none.
TEST(RemoteWorld, TheRunsMetricsCarryTheRoundStartSkew) {
  RemoteFixture fixture;
  RemoteRound first;
  first.activations_ns = {2'000'000, 2'120'000};
  fixture.loop.RecordRound(1, 50'000'000, first);
  RemoteRound second;
  second.activations_ns = {52'030'000, 52'000'000, 52'010'000};
  fixture.loop.RecordRound(2, 100'000'000, second);

  const metrics::Metrics run = fixture.loop.Finish(RunEnd{0.1, 0.1, 2});

  ASSERT_TRUE(run.round_start_skew.has_value());
  EXPECT_EQ(run.round_start_skew->samples, 2);
  EXPECT_DOUBLE_EQ(run.round_start_skew->p50_us, 30.0);
  EXPECT_DOUBLE_EQ(run.round_start_skew->max_us, 120.0);
}

TEST(RemoteWorld, ARobotWhoseReadingLinkIsClosedIsNotSampled) {
  RemoteFixture fixture;
  fixture.StepUntil(90'000'000);
  fixture.log.calls.clear();
  fixture.links.closed[0] = true;

  fixture.StepUntil(100'000'000);

  EXPECT_EQ(fixture.log.calls, (std::vector<std::string>{"start 1", "drives", "imu 1"}));
}

TEST(RemoteWorld, WithEveryRobotsDrivesARobotNotRunningKeepsItsDriveForWhenItRuns) {
  RemoteRules rules;
  rules.drives = RemoteRules::Drives::kEveryRobot;
  RemoteFixture fixture(rules);
  fixture.links.drive.vx_mps = 0.5f;
  fixture.StepUntil(90'000'000);  // robot 1 absent: it takes the drive, its body does not move
  EXPECT_DOUBLE_EQ(fixture.loop.world().state(1).x_m, 3.0);

  fixture.links.giving = false;
  fixture.StepUntil(300'000'000);  // joined at 100 ms, it drives on the drive it kept
  EXPECT_GT(fixture.loop.world().state(1).x_m, 3.01);
}

TEST(RemoteWorld, WithoutBoundaryTruthsARoundIsTheWorldNowItsEventsNoLaterThanItsTime) {
  RemoteRules rules;
  rules.boundary_truths = false;
  RemoteFixture fixture(rules);
  fixture.links.drive.vx_mps = 0.5f;
  fixture.StepUntil(140'000'000);  // robot 1 joins at 100 ms

  RemoteRound read;
  replay::Event late{};
  late.kind = replay::EventKind::kBecameJoiner;
  late.robot = 0;
  late.time_ns = 130'000'000;  // after the round's time
  read.events.push_back(late);
  fixture.loop.RecordRound(2, 100'000'000, read);

  ASSERT_EQ(fixture.kept.rounds.size(), 1U);
  const KeptRounds::Kept& round = fixture.kept.rounds[0];
  EXPECT_EQ(round.time_ns, 100'000'000);
  EXPECT_FLOAT_EQ(round.frames[0].true_x_m, static_cast<float>(fixture.loop.world().state(0).x_m));
  // The world's own event (the join), then the robots', none after 100 ms.
  ASSERT_EQ(round.events.size(), 2U);
  EXPECT_EQ(round.events[0].kind, replay::EventKind::kJoin);
  EXPECT_EQ(round.events[1].kind, replay::EventKind::kBecameJoiner);
  EXPECT_EQ(round.events[1].time_ns, 100'000'000);

  RemoteRound next;  // the join was the last round's
  fixture.loop.RecordRound(3, 150'000'000, next);
  ASSERT_EQ(fixture.kept.rounds.size(), 2U);
  EXPECT_TRUE(fixture.kept.rounds[1].events.empty());
}

TEST(RemoteWorld, ARunningRobotWhoseReportsStoppedIsRecordedAbsent) {
  RemoteFixture fixture;
  fixture.StepUntil(60'000'000);
  RemoteRobotState state;
  state.reported = true;
  state.status = 0;
  state.reporting = false;
  fixture.loop.NoteRound(0, state);

  RemoteRound read;
  fixture.loop.RecordRound(1, 50'000'000, read);

  ASSERT_EQ(fixture.kept.rounds.size(), 1U);
  EXPECT_EQ(fixture.kept.rounds[0].frames[0].presence, replay::Presence::kAbsent);
  state.reporting = true;  // its reports come again
  fixture.loop.NoteRound(0, state);
  RemoteRound next;
  fixture.loop.RecordRound(2, 100'000'000, next);
  EXPECT_EQ(fixture.kept.rounds.at(1).frames[0].presence, replay::Presence::kRunning);
}

TEST(RemoteWorld, WithoutReportedHeadingsAFrameShowsTheTrueHeadingAsTheEstimate) {
  RemoteRules rules;
  rules.reports_heading = false;
  RemoteFixture fixture(rules);
  fixture.links.drive.vx_mps = 0.5f;
  fixture.links.drive.yaw_rate_radps = 1.0f;
  fixture.StepUntil(60'000'000);
  RemoteRobotState state;
  state.reported = true;
  state.est_heading_rad = 2.5f;
  fixture.loop.NoteRound(0, state);

  RemoteRound read;
  fixture.loop.RecordRound(1, 50'000'000, read);

  const replay::RobotFrame& frame = fixture.kept.rounds.at(0).frames[0];
  EXPECT_NE(frame.true_heading_rad, 0.0f);
  EXPECT_FLOAT_EQ(frame.est_heading_rad, frame.true_heading_rad);
}

}  // namespace
}  // namespace syrof::lab::sim
