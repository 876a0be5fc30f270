// The simulated lab end to end: determinism, every fault kind's effect on
// the metrics, collisions flowing into the metrics, and the built-in apps
// reaching their goals in their example scenarios.
#include "syrof/lab/sim/simulation.h"

#include <gtest/gtest.h>

#include <algorithm>
#include <array>
#include <cmath>
#include <cstdio>
#include <map>
#include <memory>
#include <nlohmann/json.hpp>
#include <sstream>
#include <streambuf>
#include <string>
#include <utility>
#include <vector>

#include "syrof/lab/replay/reader.h"
#include "syrof/lab/scenario/scenario.h"

namespace syrof::lab::sim {
namespace {

using nlohmann::json;

scenario::Scenario Load(const std::string& text, const scenario::Overrides& overrides = {}) {
  const scenario::LoadResult loaded = scenario::LoadScenarioText(text, "test.yaml", overrides);
  EXPECT_TRUE(loaded.ok()) << (loaded.error ? loaded.error->ToString() : "");
  return *loaded.scenario;
}

struct Outcome {
  json metrics;
  std::string metrics_bytes;
  std::string replay_bytes;
};

Outcome RunScenario(const scenario::Scenario& scenario) {
  std::ostringstream replay;
  SimulationOptions options;
  options.replay = &replay;
  const RunReport report = sim::Run(scenario, options, 0.0);
  return Outcome{json::parse(report.metrics_json), report.metrics_json, replay.str()};
}

// Six omni robots on a grid, holding still.
std::string Swarm(const std::string& extra, double loss = 0.0, double duration_s = 12, int robots = 6,
                  const char* app = "builtin:idle") {
  return "seed: 3\nrobots: {count: " + std::to_string(robots) +
         ", placement: grid, spacing_m: 0.6}\ntiming: {duration_s: " + std::to_string(duration_s) +
         "}\nchannel: {model: iid, loss: " + std::to_string(loss) + "}\napp: " + app + "\n" + extra;
}

TEST(SimulationTest, SameScenarioAndSeedGiveTheSameBytes) {
  const scenario::Scenario scenario = Load(Swarm("", 0.1, 8, 6, "builtin:circle"));

  const Outcome first = RunScenario(scenario);
  const Outcome second = RunScenario(scenario);

  EXPECT_EQ(first.metrics_bytes, second.metrics_bytes);
  EXPECT_EQ(first.replay_bytes, second.replay_bytes);
  EXPECT_GT(first.replay_bytes.size(), 1000u);
}

TEST(SimulationTest, AnotherSeedGivesAnotherRun) {
  scenario::Overrides other_seed;
  other_seed.seed = 4;

  const Outcome first = RunScenario(Load(Swarm("", 0.1, 8, 6, "builtin:circle")));
  const Outcome second = RunScenario(Load(Swarm("", 0.1, 8, 6, "builtin:circle"), other_seed));

  EXPECT_NE(first.replay_bytes, second.replay_bytes);
  EXPECT_EQ(second.metrics["seed"], 4);
}

TEST(SimulationTest, ZeroLossGivesSkewZeroAndEveryEpochCooperative) {
  const Outcome run = RunScenario(Load(Swarm("", 0.0)));

  EXPECT_GE(run.metrics["epochs_started"].get<int>(), 8);
  EXPECT_EQ(run.metrics["synchrony"]["max_start_skew_rounds"], 0);
  EXPECT_EQ(run.metrics["common_knowledge"]["violations"], 0);
  EXPECT_DOUBLE_EQ(run.metrics["common_knowledge"]["cooperative_fraction"].get<double>(), 1.0);
  EXPECT_EQ(run.metrics["common_knowledge"]["max_mode_disagreement_rounds"], 0);
  EXPECT_EQ(run.metrics["membership"]["removals"], 0);
  EXPECT_EQ(run.metrics["collisions"]["count"], 0);
  EXPECT_EQ(run.metrics["radio_rounds"], 240);
}

TEST(SimulationTest, EstimatesTrackTheTruth) {
  const Outcome run = RunScenario(Load(Swarm("", 0.05, 20, 6, "builtin:circle")));

  EXPECT_LT(run.metrics["estimation"]["position_rmse_m"].get<double>(), 0.08);
  EXPECT_LT(run.metrics["estimation"]["max_error_m"].get<double>(), 0.5);
}

TEST(SimulationTest, CrashShowsAsRemovalByEveryOtherRobot) {
  const Outcome run = RunScenario(Load(Swarm("faults: [{crash: 2, at_s: 4}]\n")));

  EXPECT_EQ(run.metrics["membership"]["removals"], 5);
  EXPECT_EQ(run.metrics["common_knowledge"]["violations"], 0);
  // Epochs go on after the crash: 12 s of 1.3 s epochs.
  EXPECT_GE(run.metrics["epochs_started"].get<int>(), 8);
}

TEST(SimulationTest, CrashedRobotLeavesTheMapsAndTheOthersStayCooperative) {
  const scenario::Scenario scenario = Load(Swarm("faults: [{crash: 2, at_s: 4}]\n"));
  Simulation simulation(scenario);

  simulation.RunUntil(12);

  for (uint16_t id = 0; id < 6; ++id) {
    if (id == 2) continue;
    EXPECT_FALSE(simulation.robot(id).ldmap().members.test(2)) << "robot " << id;
    EXPECT_EQ(simulation.robot(id).ldmap().mode, wire::Mode::kCooperative) << "robot " << id;
  }
}

TEST(SimulationTest, PartitionGivesAutonomousEpochsThenRecovery) {
  const std::string partition = "channel: {model: iid, loss: 0, partitions: [{start_s: 4, end_s: 9, groups: [[0, 1, 2], [3, 4, 5]]}]}\n";
  std::string text = Swarm("", 0.0, 20);
  text.replace(text.find("channel:"), text.find('\n', text.find("channel:")) - text.find("channel:") + 1, partition);
  const scenario::Scenario scenario = Load(text);
  Simulation simulation(scenario);

  simulation.RunUntil(8);
  const wire::Mode during = simulation.robot(0).ldmap().mode;
  simulation.RunUntil(20);
  const RunReport report = simulation.Finish(0);
  const json metrics = json::parse(report.metrics_json);

  EXPECT_EQ(during, wire::Mode::kAutonomous);  // 3 of 6 is no majority
  EXPECT_GT(metrics["common_knowledge"]["autonomous_starts"].get<int>(), 0);
  EXPECT_LT(metrics["common_knowledge"]["cooperative_fraction"].get<double>(), 1.0);
  EXPECT_EQ(metrics["common_knowledge"]["violations"], 0);
  EXPECT_GT(metrics["membership"]["removals"].get<int>(), 0);
  EXPECT_GT(metrics["membership"]["joins"].get<int>(), 0);
  for (uint16_t id = 0; id < 6; ++id) {
    EXPECT_EQ(simulation.robot(id).ldmap().mode, wire::Mode::kCooperative) << "robot " << id;
    EXPECT_EQ(simulation.robot(id).ldmap().members.count(), 6) << "robot " << id;
  }
}

// Version 2 kept a partition's index in the robot field, so with more
// partitions than robots the writer refused the event, stopped, and the
// replay ended early. Partition events now have their own field.
TEST(SimulationTest, MorePartitionsThanRobotsReadBackWhole) {
  const std::string partitions =
      "channel: {model: iid, loss: 0, partitions: [{start_s: 1, end_s: 2, groups: [[0], [1]]}, "
      "{start_s: 2.5, end_s: 3, groups: [[0], [1]]}, {start_s: 3.5, end_s: 4, groups: [[0], [1]]}]}\n";
  std::string text = Swarm("", 0.0, 5, 2);
  text.replace(text.find("channel:"), text.find('\n', text.find("channel:")) - text.find("channel:") + 1, partitions);
  SimulationOptions options;
  std::stringstream bytes;
  options.replay = &bytes;
  const RunReport report = sim::Run(Load(text), options, 0.0);

  EXPECT_FALSE(report.replay_error.has_value()) << report.replay_error->ToString();
  replay::Reader reader(bytes);
  replay::Header header;
  ASSERT_TRUE(reader.ReadHeader(header));
  ASSERT_EQ(header.robots.size(), 2u);
  replay::Round round;
  std::vector<std::pair<replay::EventKind, uint16_t>> seen;
  while (reader.Next(round)) {
    for (const replay::Event& event : round.events) {
      if (replay::IsPartitionEvent(event.kind)) {
        seen.emplace_back(event.kind, event.partition);
        EXPECT_EQ(event.robot, replay::kNoRobot);
        EXPECT_EQ(event.other, replay::kNoRobot);
      } else {
        EXPECT_EQ(event.partition, replay::kNoPartition);
      }
    }
  }
  EXPECT_TRUE(reader.complete()) << reader.error();
  const std::vector<std::pair<replay::EventKind, uint16_t>> expected = {
      {replay::EventKind::kPartitionStart, 0}, {replay::EventKind::kPartitionEnd, 0},
      {replay::EventKind::kPartitionStart, 1}, {replay::EventKind::kPartitionEnd, 1},
      {replay::EventKind::kPartitionStart, 2}, {replay::EventKind::kPartitionEnd, 2}};
  EXPECT_EQ(seen, expected);
}

// Every EPOCH_START has the map its robot started with; in a COOPERATIVE
// epoch every robot holds the same one, and the file stores it once.
TEST(SimulationTest, ReplayHoldsTheMapEachRobotStartedItsEpochWith) {
  const scenario::Scenario scenario = Load(Swarm("", 0.0, 6));
  SimulationOptions options;
  std::stringstream bytes;
  options.replay = &bytes;
  (void)sim::Run(scenario, options, 0.0);

  replay::Reader reader(bytes);
  replay::Header header;
  ASSERT_TRUE(reader.ReadHeader(header));
  replay::Round round;
  int starts = 0;
  int cooperative = 0;
  std::map<uint16_t, std::shared_ptr<const replay::EpochMap>> by_epoch;  // COOPERATIVE epochs only
  while (reader.Next(round)) {
    std::vector<uint16_t> started;
    for (const replay::Event& event : round.events) {
      if (event.kind == replay::EventKind::kEpochStart) started.push_back(event.robot);
    }
    ASSERT_EQ(round.maps.size(), started.size()) << "round " << round.index;
    for (size_t i = 0; i < round.maps.size(); ++i) {
      const replay::RobotMap& entry = round.maps[i];
      EXPECT_EQ(entry.robot, started[i]);
      ++starts;
      if (entry.map->mode != 0) continue;
      ++cooperative;
      EXPECT_EQ(entry.map->members.size(), 6u);
      auto [it, inserted] = by_epoch.emplace(entry.map->epoch, entry.map);
      if (!inserted) {
        EXPECT_EQ(it->second, entry.map) << "epoch " << entry.map->epoch << " stored twice";
      }
    }
  }
  EXPECT_TRUE(reader.complete()) << reader.error();
  EXPECT_GT(cooperative, 6 * 3);
  EXPECT_GE(starts, cooperative);
}

// A stream that accepts `limit` bytes, then fails as a full disk does.
class FullDisk final : public std::streambuf {
 public:
  explicit FullDisk(size_t limit) : limit_(limit) {}

 protected:
  int overflow(int c) override {
    if (written_ >= limit_) return traits_type::eof();
    ++written_;
    return c;
  }
  std::streamsize xsputn(const char*, std::streamsize count) override {
    const auto room = static_cast<std::streamsize>(limit_ - written_);
    const std::streamsize taken = std::min(count, room);
    written_ += static_cast<size_t>(taken);
    return taken;
  }

 private:
  size_t limit_;
  size_t written_ = 0;
};

TEST(SimulationTest, ReportsAReplayWriterFailure) {
  FullDisk disk(5000);
  std::ostream replay(&disk);
  SimulationOptions options;
  options.replay = &replay;

  const RunReport report = sim::Run(Load(Swarm("", 0.0, 3)), options, 0.0);

  ASSERT_TRUE(report.replay_error.has_value());
  EXPECT_NE(report.replay_error->ToString().find("writing to the output stream failed"), std::string::npos)
      << report.replay_error->ToString();
}

TEST(SimulationTest, PausedRobotIsRemovedThenRejoins) {
  const scenario::Scenario scenario = Load(Swarm("faults: [{pause: 4, at_s: 3, until_s: 6}]\n", 0.0, 14));
  Simulation simulation(scenario);

  simulation.RunUntil(5.5);
  const bool member_while_paused = simulation.robot(0).sync_state().members.test(4);
  simulation.RunUntil(14);
  const json metrics = json::parse(simulation.Finish(0).metrics_json);

  EXPECT_FALSE(member_while_paused);
  EXPECT_EQ(metrics["membership"]["removals"], 5);
  EXPECT_GE(metrics["membership"]["joins"].get<int>(), 5);
  for (uint16_t id = 0; id < 6; ++id) EXPECT_TRUE(simulation.robot(id).ldmap().members.test(4)) << "robot " << id;
}

// Pause timing (docs/scenarios.md, "Faults"): a pause of P radio rounds
// makes the robot miss exactly P round ends, so the others' failure
// detectors (F = 6 by default) keep it for P = F - 1 and remove it for P = F.
// Before, its first step came one round after until_s, so F - 1 removed it.
struct PauseOutcome {
  int removals = 0;
  uint32_t restarts = 0;  // the paused robot's own restarts as a joiner after the gap
};

PauseOutcome AfterPauseOf(int rounds) {
  const double until_s = 3.0 + 0.05 * rounds;
  char fault[96];
  std::snprintf(fault, sizeof fault, "faults: [{pause: 4, at_s: 3, until_s: %.2f}]\n", until_s);
  Simulation simulation(Load(Swarm(fault, 0.0, 6)));
  simulation.RunUntil(6);
  const json metrics = json::parse(simulation.Finish(0).metrics_json);
  EXPECT_EQ(metrics["common_knowledge"]["violations"], 0);
  return PauseOutcome{metrics["membership"]["removals"].get<int>(),
                      simulation.robot(4).sync_state().stats.restarts_after_gap};
}

TEST(SimulationTest, APauseOfFMinusOneRoundsKeepsTheRobotAndOfFRemovesIt) {
  const PauseOutcome f_minus_one = AfterPauseOf(5);
  const PauseOutcome f = AfterPauseOf(6);
  const PauseOutcome f_plus_one = AfterPauseOf(7);
  EXPECT_EQ(f_minus_one.removals, 0);
  EXPECT_EQ(f_minus_one.restarts, 0u);
  EXPECT_EQ(f.removals, 5);
  EXPECT_EQ(f.restarts, 1u) << "the runtime tells the synchronizer it missed F rounds";
  EXPECT_EQ(f_plus_one.removals, 5);
  EXPECT_EQ(f_plus_one.restarts, 1u);
}

// A deaf robot (hears nobody, is heard) or a mute one (hears, is not heard)
// from 5 s to 12 s. Before the exclusion rule the deaf robot's votes vetoed
// every epoch: no COOPERATIVE epoch until it heard again. Now the others
// exclude it: robot 0 starts at most two epochs AUTONOMOUS after the fault,
// then only COOPERATIVE ones until the fault ends (an epoch lasts about
// 1.2 s here), and the silenced robot is back in every map once it hears.
struct SilencedRun {
  int epochs = 0;               // robot 0's epochs started in (5 s, 12 s)
  int autonomous = 0;           // of which AUTONOMOUS
  int last_autonomous = 0;      // the index (1 = first after the fault) of the last one
  bool back_in_every_map = true;
  json metrics;
};

SilencedRun RunSilenced(const char* kind) {
  const std::string fault = std::string("faults: [{") + kind + ": 2, at_s: 5, until_s: 12}]\n";
  Simulation simulation(Load(Swarm(fault, 0.0, 20)));
  SilencedRun run;
  simulation.RunUntil(5.0);
  uint16_t epoch = simulation.robot(0).ldmap().epoch;
  for (double t = 5.05; t < 12.0; t += 0.05) {
    simulation.RunUntil(t);
    const sync::LDMap& map = simulation.robot(0).ldmap();
    if (map.epoch == epoch) continue;
    epoch = map.epoch;
    ++run.epochs;
    if (map.mode != wire::Mode::kCooperative) {
      ++run.autonomous;
      run.last_autonomous = run.epochs;
    }
  }
  simulation.RunUntil(20);
  for (uint16_t id = 0; id < 6; ++id) {
    run.back_in_every_map = run.back_in_every_map && simulation.robot(id).ldmap().members.test(2);
  }
  run.metrics = json::parse(simulation.Finish(0).metrics_json);
  return run;
}

void ExpectCooperativeWithinTwoEpochs(const SilencedRun& run) {
  EXPECT_GE(run.epochs, 5);
  EXPECT_LE(run.autonomous, 2);
  EXPECT_LE(run.last_autonomous, 3) << "AUTONOMOUS after the first two epochs that followed the fault";
  EXPECT_TRUE(run.back_in_every_map);
  EXPECT_EQ(run.metrics["common_knowledge"]["violations"], 0);
}

TEST(SimulationTest, ADeafRobotIsExcludedAndTheRestCooperateWithinTwoEpochs) {
  ExpectCooperativeWithinTwoEpochs(RunSilenced("deaf"));
}

TEST(SimulationTest, AMuteRobotIsRemovedAndTheRestCooperateWithinTwoEpochs) {
  ExpectCooperativeWithinTwoEpochs(RunSilenced("mute"));
}

TEST(SimulationTest, JoiningRobotEntersEveryMap) {
  const scenario::Scenario scenario = Load(Swarm("faults: [{join: 5, at_s: 3}]\n", 0.0, 10));
  Simulation simulation(scenario);

  simulation.RunUntil(2.5);
  const bool member_before = simulation.robot(0).sync_state().members.test(5);
  simulation.RunUntil(10);
  const json metrics = json::parse(simulation.Finish(0).metrics_json);

  EXPECT_FALSE(member_before);
  EXPECT_GE(metrics["membership"]["joins"].get<int>(), 5);
  for (uint16_t id = 0; id < 6; ++id) {
    EXPECT_TRUE(simulation.robot(id).ldmap().members.test(5)) << "robot " << id;
    EXPECT_EQ(simulation.robot(id).ldmap().mode, wire::Mode::kCooperative) << "robot " << id;
  }
}

TEST(SimulationTest, BurstyLossCostsCooperationButNeverCommonKnowledge) {
  std::string text = Swarm("", 0.0, 30);
  const std::string bursty =
      "channel: {model: gilbert_elliott, good_to_bad: 0.05, bad_to_good: 0.3, loss_good: 0.01, loss_bad: 0.9}\n";
  text.replace(text.find("channel:"), text.find('\n', text.find("channel:")) - text.find("channel:") + 1, bursty);

  const Outcome run = RunScenario(Load(text));

  EXPECT_EQ(run.metrics["common_knowledge"]["violations"], 0);
  EXPECT_LT(run.metrics["common_knowledge"]["cooperative_fraction"].get<double>(), 1.0);
  EXPECT_GE(run.metrics["epochs_started"].get<int>(), 10);
}

TEST(SimulationTest, OneDeafLinkRemovesItsSenderOnlyAtItsReceiver) {
  std::string text = Swarm("", 0.0, 8);
  const std::string deaf = "channel: {model: iid, loss: 0, links: [{from: 0, to: 1, loss: 1.0}]}\n";
  text.replace(text.find("channel:"), text.find('\n', text.find("channel:")) - text.find("channel:") + 1, deaf);

  const Outcome run = RunScenario(Load(text));

  EXPECT_EQ(run.metrics["common_knowledge"]["violations"], 0);
  EXPECT_GT(run.metrics["membership"]["removals"].get<int>(), 0);
}

// Drives every robot at full speed toward the arena's centre, ignoring the
// others: the world must record the collisions and keep bodies apart.
class RamApp final : public app::App {
 public:
  const char* name() const override { return "ram"; }
  app::CallStatus Init(const syrof_app_info& info, app::Platform&, uint8_t& global_state) override {
    info_ = info;
    global_state = 0;
    return app::CallStatus::Ok();
  }
  app::CallStatus NewRound(syrof_car_command& command, const syrof_ldmap&, uint8_t&, uint32_t) override {
    command.kind = SYROF_COMMAND_MOVE_TO;
    command.x_m = info_.arena_width_m / 2;
    command.y_m = info_.arena_height_m / 2;
    command.speed_mps = info_.max_speed_mps;
    return app::CallStatus::Ok();
  }
  app::CallStatus EndOfRound(const syrof_ldmap&, uint8_t&, uint32_t) override { return app::CallStatus::Ok(); }

 private:
  syrof_app_info info_{};
};

// With the safety filter off (docs/safety.md), as a course teaching
// collisions runs it.
TEST(SimulationTest, CollisionsAreCountedAndBodiesDoNotPassThrough) {
  const scenario::Scenario scenario = Load(Swarm("safety: off\n", 0.0, 8, 4));
  SimulationOptions options;
  options.apps.factory = [](uint16_t) { return std::make_unique<RamApp>(); };
  Simulation simulation(scenario, options);

  const json metrics = json::parse(simulation.Finish(0).metrics_json);

  EXPECT_GE(metrics["collisions"]["count"].get<int>(), 1);
  EXPECT_FALSE(metrics["collisions"]["pairs"].empty());
  // Four robots pushing into one point: after each physics step no two
  // bodies overlap by more than a millimetre (min_separation_m clamps at 0,
  // so only the overlap itself can show a failure).
  EXPECT_LE(simulation.world().max_overlap_m(), 1e-3);
  EXPECT_DOUBLE_EQ(metrics["collisions"]["min_separation_m"].get<double>(), 0.0);
}

// The same rammers with the safety filter on: it keeps every body clear, and
// says so in metrics.json.
TEST(SimulationTest, TheSafetyFilterStopsRammers) {
  const scenario::Scenario scenario = Load(Swarm("", 0.0, 8, 4));
  SimulationOptions options;
  options.apps.factory = [](uint16_t) { return std::make_unique<RamApp>(); };

  const json metrics = json::parse(sim::Run(scenario, options, 0.0).metrics_json);

  EXPECT_EQ(metrics["collisions"]["count"], 0);
  EXPECT_GT(metrics["collisions"]["min_separation_m"].get<double>(), 0.0);
  EXPECT_GT(metrics["safety"]["interventions"].get<int>(), 0);
  EXPECT_EQ(metrics["safety"]["robots_involved"], 4);
}

// Every robot's event carries the robot's epoch and that epoch's mode at the
// moment (docs/replay.md), not the defaults 0 and COOPERATIVE: the same as
// the robot's frame of the round before the event or of the round after it.
TEST(SimulationTest, EventsCarryTheRobotsEpochAndModeThen) {
  const scenario::Scenario scenario =
      Load(Swarm("faults: [{crash: 2, at_s: 4}, {pause: 1, at_s: 3, until_s: 6}, {join: 3, at_s: 2}]\nsafety: off\n",
                 0.0, 9, 5));
  SimulationOptions options;
  options.apps.factory = [](uint16_t) { return std::make_unique<RamApp>(); };
  std::stringstream bytes;
  options.replay = &bytes;
  (void)sim::Run(scenario, options, 0.0);

  replay::Reader reader(bytes);
  replay::Header header;
  ASSERT_TRUE(reader.ReadHeader(header));
  replay::Round previous;
  replay::Round round;
  std::map<replay::EventKind, int> checked;
  while (reader.Next(round)) {
    for (const replay::Event& event : round.events) {
      if (event.robot >= round.robots.size() || event.kind == replay::EventKind::kPartitionStart ||
          event.kind == replay::EventKind::kPartitionEnd) {
        continue;
      }
      const replay::RobotFrame& after = round.robots[event.robot];
      const replay::RobotFrame& before = previous.robots.empty() ? after : previous.robots[event.robot];
      const bool as_before = event.epoch == before.epoch && event.mode == before.mode;
      const bool as_after = event.epoch == after.epoch && event.mode == after.mode;
      EXPECT_TRUE(as_before || as_after) << replay::ToString(event.kind) << " robot " << event.robot << " at "
                                         << event.time_ns << " ns: epoch " << event.epoch << " mode "
                                         << int{event.mode} << ", frames " << before.epoch << "/"
                                         << int{before.mode} << " and " << after.epoch << "/" << int{after.mode};
      ++checked[event.kind];
    }
    previous = round;
  }
  EXPECT_TRUE(reader.complete()) << reader.error();
  for (const replay::EventKind kind : {replay::EventKind::kCollision, replay::EventKind::kCrash,
                                       replay::EventKind::kPause, replay::EventKind::kResume,
                                       replay::EventKind::kJoin, replay::EventKind::kEpochStart}) {
    EXPECT_GT(checked[kind], 0) << replay::ToString(kind);
  }
}

// ---- Apps that fail ------------------------------------------------------------

// Holds still, and breaks as `Plan` says.
struct Plan {
  uint16_t robot = 0xFFFF;     // the robot whose app faults
  uint16_t fault_epoch = 0;    // in newRound of this epoch
  bool fault_in_init = false;  // or in init
  bool misbehave = false;      // every robot's first newRound: a 10-byte payload and an unknown command kind
};

class FaultyApp final : public app::App {
 public:
  FaultyApp(uint16_t id, const Plan& plan) : id_(id), plan_(plan) {}
  const char* name() const override { return "faulty"; }
  app::CallStatus Init(const syrof_app_info&, app::Platform& platform, uint8_t& global_state) override {
    platform_ = &platform;
    global_state = 0;
    if (id_ == plan_.robot && plan_.fault_in_init) return app::CallStatus::Fault(app::Verdict::kLoadFailed, "no entry");
    return app::CallStatus::Ok();
  }
  app::CallStatus NewRound(syrof_car_command& command, const syrof_ldmap& ldmap, uint8_t&, uint32_t) override {
    EXPECT_FALSE(id_ == plan_.robot && plan_.fault_in_init) << "newRound after a failed init";
    if (id_ == plan_.robot && ldmap.epoch == plan_.fault_epoch) {
      return app::CallStatus::Fault(app::Verdict::kCrashed, "SIGSEGV");
    }
    if (plan_.misbehave && !misbehaved_) {
      misbehaved_ = true;
      const std::array<uint8_t, 10> too_long{};
      EXPECT_EQ(platform_->SendMessageData(too_long), SYROF_APP_PAYLOAD_TOO_LONG);
      command.kind = 9;
    }
    return app::CallStatus::Ok();
  }
  app::CallStatus EndOfRound(const syrof_ldmap&, uint8_t&, uint32_t) override { return app::CallStatus::Ok(); }

 private:
  uint16_t id_;
  Plan plan_;
  bool misbehaved_ = false;
  app::Platform* platform_ = nullptr;
};

struct FaultyRun {
  json metrics;
  std::vector<replay::Round> rounds;
  bool replay_complete = false;
  bool robot0_holds_robot2 = true;
};

FaultyRun RunFaulty(const Plan& plan) {
  const scenario::Scenario scenario = Load(Swarm("", 0.0, 10, 4));
  std::ostringstream replay_bytes;
  SimulationOptions options;
  options.replay = &replay_bytes;
  options.apps.factory = [plan](uint16_t id) { return std::make_unique<FaultyApp>(id, plan); };
  options.apps.source = "test:faulty";
  Simulation simulation(scenario, options);
  const RunReport report = simulation.Finish(0.0);
  FaultyRun run;
  run.metrics = json::parse(report.metrics_json);
  run.robot0_holds_robot2 = simulation.robot(0).sync_state().members.test(2);
  std::istringstream in(replay_bytes.str());
  replay::Reader reader(in);
  replay::Header header;
  EXPECT_TRUE(reader.ReadHeader(header)) << reader.error();
  replay::Round round;
  while (reader.Next(round)) run.rounds.push_back(round);
  run.replay_complete = reader.complete();
  return run;
}

// ---- The app that ran is the one named -----------------------------------------

// A library given in the scenario's place (the grader, `--app`) is the app
// the replay and the metrics name, with or without declared goal checks:
// never the scenario's own `app:` (a student read "builtin:idle" as "the
// grader did not run my code").
TEST(SimulationAppNameTest, TheSuppliedAppIsNamedInTheReplayAndTheMetrics) {
  for (const std::string& goal : {std::string("goal:\n  - {check: gathered, radius_m: 5}\n"), std::string()}) {
    // Arrange: the scenario says builtin:idle; the runtime supplies the apps.
    const scenario::Scenario scenario = Load(Swarm(goal, 0.0, 4, 4));
    ASSERT_EQ(scenario.app.name, "builtin:idle");
    std::ostringstream replay_bytes;
    SimulationOptions options;
    options.replay = &replay_bytes;
    options.apps.factory = [](uint16_t id) { return std::make_unique<FaultyApp>(id, Plan{}); };
    options.apps.source = "build/libstudent.so";

    // Act
    const RunReport report = sim::Run(scenario, options, 0.0);

    // Assert
    const json metrics = json::parse(report.metrics_json);
    EXPECT_EQ(metrics["app"]["source"], "build/libstudent.so") << goal;
    EXPECT_EQ(metrics["app"]["name"], "faulty") << goal;
    EXPECT_EQ(metrics["goal"]["app"], "build/libstudent.so") << goal;
    EXPECT_EQ(metrics["goal"]["source"], goal.empty() ? "builtin" : "scenario") << goal;
    std::istringstream in(replay_bytes.str());
    replay::Reader reader(in);
    replay::Header header;
    ASSERT_TRUE(reader.ReadHeader(header)) << reader.error();
    EXPECT_EQ(header.app_name, "build/libstudent.so") << goal;
  }
}

TEST(SimulationAppFaultTest, ARobotWhoseAppFaultsStopsAndTheRunGoesOn) {
  // Act: robot 2's app crashes in newRound of epoch 3.
  const FaultyRun run = RunFaulty(Plan{.robot = 2, .fault_epoch = 3});

  // Assert: the run finished, metrics.json names the fault.
  EXPECT_TRUE(run.replay_complete);
  EXPECT_EQ(run.metrics["sim_seconds"].get<double>(), 10.0);
  const json& app = run.metrics["app"];
  EXPECT_EQ(app["name"], "faulty");
  EXPECT_EQ(app["source"], "test:faulty");
  ASSERT_EQ(app["faults"].size(), 1u);
  EXPECT_EQ(app["faults"][0]["robot"], 2);
  EXPECT_EQ(app["faults"][0]["callback"], "new_round");
  EXPECT_EQ(app["faults"][0]["epoch"], 3);
  EXPECT_EQ(app["faults"][0]["verdict"], "crashed");
  EXPECT_EQ(app["faults"][0]["detail"], "SIGSEGV");
  EXPECT_EQ(app["invalid_commands"]["count"], 0);
  // The others removed it (each of the 3) and went on without it.
  EXPECT_FALSE(run.robot0_holds_robot2);
  EXPECT_EQ(run.metrics["membership"]["removals"], 3);
  EXPECT_EQ(run.metrics["membership"]["robots_removed"], 1);
  EXPECT_GT(run.metrics["epochs_started"].get<int>(), 6);
  // The replay has the event, and robot 2 is CRASHED from then on.
  const replay::Event* fault = nullptr;
  uint32_t fault_round = 0;
  for (const replay::Round& round : run.rounds) {
    for (const replay::Event& event : round.events) {
      if (event.kind == replay::EventKind::kAppFault) {
        fault = &event;
        fault_round = round.index;
      }
    }
  }
  ASSERT_NE(fault, nullptr);
  EXPECT_EQ(fault->robot, 2);
  EXPECT_EQ(fault->epoch, 3);
  EXPECT_DOUBLE_EQ(app["faults"][0]["time_s"].get<double>(), static_cast<double>(fault->time_ns) * 1e-9);
  const replay::Round& last = run.rounds.back();
  EXPECT_GT(last.index, fault_round);
  EXPECT_EQ(last.robots[2].presence, replay::Presence::kCrashed);
  EXPECT_EQ(last.robots[1].presence, replay::Presence::kRunning);
}

TEST(SimulationAppFaultTest, InvalidCommandsAndRefusedPayloadsAreReportedOncePerRobotInTheReplay) {
  const FaultyRun run = RunFaulty(Plan{.misbehave = true});

  const json& app = run.metrics["app"];
  EXPECT_EQ(app["invalid_commands"]["count"], 4);  // every robot's first newRound
  EXPECT_EQ(app["invalid_commands"]["first"]["robot"], 0);
  EXPECT_EQ(app["invalid_commands"]["first"]["what"], "kind 9 is unknown");
  EXPECT_EQ(app["payload_refused"]["count"], 4);
  EXPECT_EQ(app["payload_refused"]["first"]["what"], "10 bytes");
  int invalid_events = 0;
  int refused_events = 0;
  for (const replay::Round& round : run.rounds) {
    for (const replay::Event& event : round.events) {
      invalid_events += event.kind == replay::EventKind::kInvalidCommand ? 1 : 0;
      refused_events += event.kind == replay::EventKind::kPayloadRefused ? 1 : 0;
    }
  }
  EXPECT_EQ(invalid_events, 4);
  EXPECT_EQ(refused_events, 4);
}

TEST(SimulationAppFaultTest, AnAppThatFailsInInitNeverRunsButItsBodyStays) {
  const FaultyRun run = RunFaulty(Plan{.robot = 1, .fault_in_init = true});

  const json& app = run.metrics["app"];
  ASSERT_EQ(app["faults"].size(), 1u);
  EXPECT_EQ(app["faults"][0]["robot"], 1);
  EXPECT_EQ(app["faults"][0]["callback"], "init");
  EXPECT_EQ(app["faults"][0]["verdict"], "load_failed");
  EXPECT_TRUE(run.replay_complete);
  for (const replay::Round& round : run.rounds) EXPECT_EQ(round.robots[1].presence, replay::Presence::kCrashed);
  EXPECT_GT(run.metrics["epochs_started"].get<int>(), 4);  // the other three go on
}

// ---- The built-in apps in their example scenarios --------------------------

json RunExample(const std::string& file) {
  const scenario::LoadResult loaded = scenario::LoadScenarioFile(std::string(SYROF_SCENARIOS_DIR) + "/" + file);
  EXPECT_TRUE(loaded.ok()) << (loaded.error ? loaded.error->ToString() : "");
  return json::parse(sim::Run(*loaded.scenario, SimulationOptions{}, 0.0).metrics_json);
}

void ExpectGoalReachedSafely(const json& metrics) {
  EXPECT_TRUE(metrics["goal"]["reached"].get<bool>()) << metrics["goal"].dump();
  EXPECT_EQ(metrics["collisions"]["count"], 0) << metrics["collisions"].dump();
  EXPECT_EQ(metrics["common_knowledge"]["violations"], 0);
}

TEST(SimulationTest, CircleReachesItsGoalInTheDemo) { ExpectGoalReachedSafely(RunExample("demo_circle.yaml")); }
TEST(SimulationTest, GatherReachesItsGoal) { ExpectGoalReachedSafely(RunExample("gather.yaml")); }
TEST(SimulationTest, LeaderFollowReachesItsGoal) { ExpectGoalReachedSafely(RunExample("leader_follow.yaml")); }

}  // namespace
}  // namespace syrof::lab::sim
