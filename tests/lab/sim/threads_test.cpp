// SimulationOptions::threads (`syrof run --threads`): a run on 2 or 3
// threads writes the same metrics.json and replay, byte for byte, as the run
// on 1, with loss, bursts, partitions, every fault kind, clocks, goal apps,
// apps that fault or misbehave, and 30 to 200 robots. Under the TSan build
// (`make tsan`) these runs also show that the threads share no data unsafely.
#include <gtest/gtest.h>

#include <array>
#include <memory>
#include <sstream>
#include <string>

#include "syrof/lab/apps/catalog.h"
#include "syrof/lab/scenario/scenario.h"
#include "syrof/lab/sim/simulation.h"

namespace syrof::lab::sim {
namespace {

struct Bytes {
  std::string metrics;
  std::string replay;
};

scenario::Scenario Load(const std::string& text, const scenario::Overrides& overrides = {}) {
  const scenario::LoadResult loaded = scenario::LoadScenarioText(text, "threads_test.yaml", overrides);
  EXPECT_TRUE(loaded.ok()) << (loaded.error ? loaded.error->ToString() : "");
  return *loaded.scenario;
}

Bytes RunOn(const scenario::Scenario& scenario, int threads, SimulationOptions options = {}) {
  std::ostringstream replay;
  options.replay = &replay;
  options.threads = threads;
  const RunReport report = Run(scenario, options, 0.0);
  EXPECT_FALSE(report.replay_error.has_value());
  return Bytes{report.metrics_json, replay.str()};
}

// Compares whole files, so a difference fails without printing megabytes.
void ExpectSameBytes(const scenario::Scenario& scenario, const SimulationOptions& options = {}) {
  const Bytes one = RunOn(scenario, 1, options);
  ASSERT_GT(one.replay.size(), 1000u);
  for (const int threads : {2, 3}) {
    const Bytes many = RunOn(scenario, threads, options);
    EXPECT_TRUE(many.metrics == one.metrics) << threads << " threads: metrics.json differs";
    EXPECT_TRUE(many.replay == one.replay) << threads << " threads: the replay differs";
  }
}

// 36 robots on a grid with i.i.d. loss and every fault kind, running the
// circle (a goal app): crashes, a pause, joins, a deaf and a mute robot.
TEST(SimulationThreadsTest, LossAndEveryFaultKindGiveTheSameBytes) {
  const scenario::Scenario scenario = Load(R"(name: threads_faults
seed: 11
arena: { width_m: 8, height_m: 8 }
robots: { count: 36, placement: grid, spacing_m: 1.0 }
timing: { duration_s: 6 }
channel: { model: iid, loss: 0.05 }
faults:
  - { crash: 3, at_s: 1.0 }
  - { crash: 20, at_s: 3.1 }
  - { pause: 7, at_s: 1.5, until_s: 3.5 }
  - { join: 30, at_s: 2.0 }
  - { join: 35, at_s: 2.0 }
  - { deaf: 12, at_s: 1.0, until_s: 4.0 }
  - { mute: 25, at_s: 2.0, until_s: 5.0 }
app: builtin:circle
)");
  ExpectSameBytes(scenario);
}

// Gilbert-Elliott bursts (per-link state, decided by the receiver's block's
// channel copy) and a partition, with robots gathering (collisions, the
// safety filter).
TEST(SimulationThreadsTest, BurstsAndAPartitionGiveTheSameBytes) {
  const scenario::Scenario scenario = Load(R"(name: threads_bursts
seed: 4
arena: { width_m: 6, height_m: 6 }
robots: { count: 32, placement: grid, spacing_m: 0.8 }
timing: { duration_s: 6 }
channel:
  model: gilbert_elliott
  good_to_bad: 0.05
  bad_to_good: 0.25
  loss_good: 0.02
  loss_bad: 0.9
  partitions:
    - { start_s: 2, end_s: 4, groups: [[0, 1, 2, 3, 4, 5, 6, 7, 8, 9, 10, 11, 12, 13, 14, 15]] }
app: builtin:gather
)");
  ExpectSameBytes(scenario);
}

// With clocks the run stays serial (docs/lab.md, "Threads"): still the same bytes.
TEST(SimulationThreadsTest, ClocksGiveTheSameBytes) {
  const scenario::Scenario scenario = Load(R"(name: threads_clocks
seed: 7
arena: { width_m: 5, height_m: 5 }
robots: { count: 30, kind: omni, placement: grid, spacing_m: 0.7 }
timing: { duration_s: 4 }
channel: { model: iid, loss: 0.1 }
clocks: { offset_max_ms: 50, drift_max_ppm: 50, jitter_ms: 0.2, alignment: on }
app: builtin:circle
)");
  ExpectSameBytes(scenario);
}

// A crowd: 200 robots at random places holding still while some crash,
// pause and join (the gather app of adversarial/crowd_200_short.yaml would
// make this test take a minute).
TEST(SimulationThreadsTest, ACrowdOf200GivesTheSameBytes) {
  const scenario::Scenario scenario = Load(R"(name: threads_crowd
seed: 22
arena: { width_m: 12, height_m: 12 }
robots: { count: 200, placement: random, min_separation_m: 0.3 }
timing: { duration_s: 3 }
channel: { model: iid, loss: 0.05 }
faults:
  - { crash: 133, at_s: 1.2 }
  - { crash: 10, at_s: 1.2 }
  - { pause: 150, at_s: 0.5, until_s: 2.0 }
  - { join: 9, at_s: 1.5 }
  - { join: 199, at_s: 2.2 }
app: builtin:idle
)");
  ExpectSameBytes(scenario);
}

// Robots 5, 6 and 29 fault in newRound of epoch 3 (in one batch, on two
// threads); every robot's first newRound refuses a payload and returns an
// unknown command kind; the rest run the circle.
// (Robots 5, 6 and 29, when there are so many.)
class BreakingApp final : public app::App {
 public:
  BreakingApp(uint16_t id, std::unique_ptr<app::App> inner) : id_(id), inner_(std::move(inner)) {}
  const char* name() const override { return "breaking"; }
  app::CallStatus Init(const syrof_app_info& info, app::Platform& platform, uint8_t& global_state) override {
    platform_ = &platform;
    return inner_->Init(info, platform, global_state);
  }
  app::CallStatus NewRound(syrof_car_command& command, const syrof_ldmap& ldmap, uint8_t& global_state,
                           uint32_t clock_ms) override {
    if ((id_ == 5 || id_ == 6 || id_ == 29) && ldmap.epoch == 3) {
      return app::CallStatus::Fault(app::Verdict::kCrashed, "SIGSEGV");
    }
    const app::CallStatus status = inner_->NewRound(command, ldmap, global_state, clock_ms);
    if (!misbehaved_) {
      misbehaved_ = true;
      const std::array<uint8_t, 10> too_long{};
      (void)platform_->SendMessageData(too_long);
      command.kind = 9;
    }
    return status;
  }
  app::CallStatus EndOfRound(const syrof_ldmap& ldmap, uint8_t& global_state, uint32_t clock_ms) override {
    return inner_->EndOfRound(ldmap, global_state, clock_ms);
  }

 private:
  uint16_t id_;
  std::unique_ptr<app::App> inner_;
  app::Platform* platform_ = nullptr;
  bool misbehaved_ = false;
};

TEST(SimulationThreadsTest, AppFaultsInvalidCommandsAndRefusedPayloadsGiveTheSameBytes) {
  const scenario::Scenario scenario = Load(R"(name: threads_apps
seed: 2
arena: { width_m: 8, height_m: 8 }
robots: { count: 36, placement: grid, spacing_m: 1.0 }
timing: { duration_s: 6 }
channel: { model: iid, loss: 0.02 }
app: builtin:circle
)");
  SimulationOptions options;
  options.apps.factory = [](uint16_t id) {
    return std::make_unique<BreakingApp>(id, apps::MakeBuiltinApp("circle", {}));
  };
  options.apps.source = "test:breaking";
  const Bytes one = RunOn(scenario, 1, options);
  ASSERT_NE(one.metrics.find("SIGSEGV"), std::string::npos);  // the faults happened
  ExpectSameBytes(scenario, options);
}

// The run `make tsan` checks under ThreadSanitizer (short: TSan is slow):
// 20 robots, so batches run on the pool, with loss, a crash, a join, a
// deaf robot, and apps that fault and misbehave.
TEST(SimulationThreadsTest, ShortRunWithFaultsOnTwoThreads) {
  const scenario::Scenario scenario = Load(R"(name: threads_short
seed: 5
arena: { width_m: 6, height_m: 6 }
robots: { count: 20, placement: grid, spacing_m: 1.0 }
timing: { duration_s: 1.5 }
channel: { model: gilbert_elliott, good_to_bad: 0.05, bad_to_good: 0.25, loss_good: 0.02, loss_bad: 0.9 }
faults:
  - { crash: 3, at_s: 0.5 }
  - { join: 17, at_s: 0.4 }
  - { deaf: 12, at_s: 0.2, until_s: 1.0 }
app: builtin:circle
)");
  SimulationOptions options;
  options.apps.factory = [](uint16_t id) {
    return std::make_unique<BreakingApp>(id, apps::MakeBuiltinApp("circle", {}));
  };
  const Bytes one = RunOn(scenario, 1, options);
  const Bytes two = RunOn(scenario, 2, options);
  EXPECT_TRUE(two.metrics == one.metrics);
  EXPECT_TRUE(two.replay == one.replay);
}

// More threads than robots: capped at the robot count.
TEST(SimulationThreadsTest, MoreThreadsThanRobotsRun) {
  const scenario::Scenario scenario = Load(R"(name: threads_few
robots: { count: 3, placement: circle, radius_m: 1.0 }
timing: { duration_s: 3 }
app: builtin:circle
)");
  const Bytes one = RunOn(scenario, 1);
  const Bytes many = RunOn(scenario, kMaxThreads);
  EXPECT_TRUE(many.metrics == one.metrics);
  EXPECT_TRUE(many.replay == one.replay);
}

}  // namespace
}  // namespace syrof::lab::sim
