// What every runtime that plays a scenario's world shares with the lab's
// engine, so a scenario means the same in each (the lab, the DDS world of
// `syrof swarm`): the seeds derived from the scenario seed, the bodies,
// when an estimate starts being scored, the replay's copy of a map and
// metrics.json's `goal` from the scenario's declared checks.
#pragma once

#include <cstdint>
#include <map>
#include <memory>
#include <string>
#include <vector>

#include "syrof/app/app.h"
#include "syrof/lab/apps/builtin_goals.h"
#include "syrof/lab/goals/goals.h"
#include "syrof/lab/metrics/metrics.h"
#include "syrof/lab/replay/replay.h"
#include "syrof/lab/scenario/scenario.h"
#include "syrof/lab/world/world.h"
#include "syrof/queries/queries.h"
#include "syrof/sync/ldmap.h"

namespace syrof::lab::sim {

/// An estimate is scored only this long after its robot started or resumed:
/// the filter converges from the known start pose within it.
inline constexpr int64_t kEstimationWarmupNs = 1'000'000'000;

/// The seed of robot `robot`'s sensor noise: one stream per robot, derived
/// from the scenario seed, so adding a robot does not change another robot's
/// noise.
uint64_t SensorSeed(uint64_t seed, uint16_t robot);

/// The channel's seed (its loss draws), one stream of the scenario seed: the
/// lab's radio and every DDS robot's receiver draw the same losses from it.
uint64_t ChannelSeed(uint64_t seed);

/// The seed of the radio's delivery jitter with real clocks (docs/clocks.md).
uint64_t JitterSeed(uint64_t seed);

/// The scenario's robots as the world's bodies, at their start poses; robots
/// that join later start absent.
std::vector<world::BodySpec> Bodies(const scenario::Scenario& scenario);

/// The replay's header for a run of `scenario`: seed, round, arena, names,
/// robots with their body radii, anchors.
replay::Header ReplayHeader(const scenario::Scenario& scenario);

/// The replay's copy of an LDMap: every member's snapshot and phase.
std::shared_ptr<const replay::EpochMap> ToEpochMap(const sync::LDMap& ldmap);

/// Whether `map` equals ToEpochMap(ldmap), found without building it (the
/// lab shares one map between robots that start an epoch with equal ones).
bool MatchesEpochMap(const replay::EpochMap& map, const sync::LDMap& ldmap);

/// metrics.json's `goal` from the scenario's checks: reached when every
/// check passed; the detail names the first that failed.
metrics::GoalResult DeclaredGoal(const std::string& app, const std::vector<goals::CheckResult>& results);

/// metrics.json's run facts that a run of `scenario` takes from it and from
/// its world at the end: seed, robots, scenario name, safety, the app's name
/// and source ("builtin:NAME" or the library), the smallest separation. The
/// runtime adds its times, rounds and goal.
metrics::RunFacts ScenarioFacts(const scenario::Scenario& scenario, const world::World& world);

/// Robot `robot`'s private inputs (the scenario's `inputs`, its own value of
/// each) as syrofAppInput answers them: names view the scenario's keys, so
/// the scenario must outlive the table (RobotConfig::app_inputs).
std::vector<app::Parameter> InputsOf(const scenario::Scenario& scenario, uint16_t robot);

/// Every robot's kind by id (the scenario's robots' `kind:`), what each
/// robot's app reads as its members' kinds (RobotConfig::member_kinds).
std::vector<motion::RobotKind> MemberKindsOf(const scenario::Scenario& scenario);

/// The same by name, owned: for a host process (HostOptions::inputs).
std::map<std::string, double> InputValuesOf(const scenario::Scenario& scenario, uint16_t robot);

/// metrics.json's `goal` from the built-in app's own goal (apps::EvaluateGoal)
/// for the robots' final true poses; for a library app, not judged.
metrics::GoalResult BuiltinGoal(const scenario::Scenario& scenario, const std::vector<apps::GoalPose>& poses);

/// The queries' scratch memory (syrof/queries.h's workspace), owned. The lab
/// shares one among every app of a run (it runs one callback at a time, and
/// a workspace holds nothing between queries); a robot process has its own.
class QueriesWorkspace {
 public:
  QueriesWorkspace();
  ~QueriesWorkspace();
  QueriesWorkspace(const QueriesWorkspace&) = delete;
  QueriesWorkspace& operator=(const QueriesWorkspace&) = delete;
  syrof_queries_workspace* handle() const { return handle_; }

 private:
  unsigned char* memory_;
  syrof_queries_workspace* handle_ = nullptr;
};

}  // namespace syrof::lab::sim
