#include "syrof/lab/sim/run_parts.h"

#include <algorithm>
#include <cmath>
#include <limits>
#include <new>
#include <span>

#include "syrof/app.h"
#include "syrof/base/check.h"
#include "syrof/base/split_mix64.h"
#include "syrof/lab/apps/catalog.h"

namespace syrof::lab::sim {

static_assert(replay::kMaxPayloadBytes == wire::kMaxPayloadBytes);
static_assert(replay::kMaxInputsPerRobot == SYROF_APP_MAX_INPUTS);

uint64_t SensorSeed(uint64_t seed, uint16_t robot) {
  return base::SplitMix64Hash(seed ^ base::SplitMix64Hash(0x53454e534f52ULL + robot));
}

uint64_t ChannelSeed(uint64_t seed) { return base::SplitMix64Hash(seed ^ 0x4348414e4e454cULL); }

uint64_t JitterSeed(uint64_t seed) { return base::SplitMix64Hash(seed ^ 0x4a4954544552ULL); }

replay::Header ReplayHeader(const scenario::Scenario& scenario) {
  replay::Header header;
  header.seed = scenario.seed;
  header.radio_round_ns = std::llround(scenario.timing.radio_round_s * 1e9);
  header.arena_width_m = static_cast<float>(scenario.arena.width_m);
  header.arena_height_m = static_cast<float>(scenario.arena.height_m);
  header.scenario_name = scenario.name;
  header.app_name = scenario.app.name;
  for (const scenario::RobotSpec& spec : scenario.robots) {
    replay::RobotInfo robot{spec.id, static_cast<uint8_t>(spec.kind),
                            static_cast<float>(scenario.kind_spec(spec.kind).body_radius_m), {}};
    for (const auto& [name, value] : InputValuesOf(scenario, spec.id)) robot.inputs.push_back({name, value});
    header.robots.push_back(std::move(robot));
  }
  header.message = scenario.message;
  for (const world::AnchorSpec& anchor : scenario.arena.anchors) {
    header.anchors.push_back(replay::AnchorInfo{static_cast<float>(anchor.x_m), static_cast<float>(anchor.y_m)});
  }
  return header;
}

std::shared_ptr<const replay::EpochMap> ToEpochMap(const sync::LDMap& ldmap) {
  auto map = std::make_shared<replay::EpochMap>();
  map->epoch = ldmap.epoch;
  map->mode = static_cast<uint8_t>(ldmap.mode);
  for (const uint16_t id : ldmap.members) {
    const wire::Snapshot& snapshot = ldmap.snapshots[id];
    const std::span<const uint8_t> payload = snapshot.payload_bytes();
    map->members.push_back(replay::MapMember{id, static_cast<uint8_t>(ldmap.phases[id]), snapshot.x_mm,
                                             snapshot.y_mm, snapshot.heading_mrad, snapshot.vx_mm_s,
                                             snapshot.vy_mm_s, std::vector<uint8_t>(payload.begin(), payload.end())});
  }
  return map;
}

// Field by field what ToEpochMap copies, without copying.
bool MatchesEpochMap(const replay::EpochMap& map, const sync::LDMap& ldmap) {
  if (map.epoch != ldmap.epoch || map.mode != static_cast<uint8_t>(ldmap.mode)) return false;
  size_t index = 0;
  for (const uint16_t id : ldmap.members) {
    if (index == map.members.size()) return false;
    const replay::MapMember& member = map.members[index++];
    const wire::Snapshot& snapshot = ldmap.snapshots[id];
    if (member.id != id || member.phase != static_cast<uint8_t>(ldmap.phases[id]) || member.x_mm != snapshot.x_mm ||
        member.y_mm != snapshot.y_mm || member.heading_mrad != snapshot.heading_mrad ||
        member.vx_mm_s != snapshot.vx_mm_s || member.vy_mm_s != snapshot.vy_mm_s) {
      return false;
    }
    const std::span<const uint8_t> payload = snapshot.payload_bytes();
    if (!std::equal(member.payload.begin(), member.payload.end(), payload.begin(), payload.end())) return false;
  }
  return index == map.members.size();
}

metrics::RunFacts ScenarioFacts(const scenario::Scenario& scenario, const world::World& world) {
  metrics::RunFacts facts;
  facts.seed = scenario.seed;
  facts.robots = static_cast<uint16_t>(scenario.robots.size());
  facts.min_separation_m = world.min_separation_m();
  facts.scenario = scenario.name;
  facts.safety_enabled = scenario.safety;
  facts.app_name = scenario.app.name;
  facts.app_source = scenario.app.is_library() ? scenario.app.library : scenario.app.name;
  return facts;
}

std::vector<app::Parameter> InputsOf(const scenario::Scenario& scenario, uint16_t robot) {
  std::vector<app::Parameter> inputs;
  for (const auto& [name, values] : scenario.inputs) {
    if (robot < values.size()) inputs.push_back(app::Parameter{name, values[robot]});
  }
  return inputs;
}

std::vector<motion::RobotKind> MemberKindsOf(const scenario::Scenario& scenario) {
  std::vector<motion::RobotKind> kinds(scenario.robots.size(), motion::RobotKind::kOmni);
  for (const scenario::RobotSpec& robot : scenario.robots) {
    if (robot.id < kinds.size()) kinds[robot.id] = robot.kind;
  }
  return kinds;
}

std::map<std::string, double> InputValuesOf(const scenario::Scenario& scenario, uint16_t robot) {
  std::map<std::string, double> inputs;
  for (const app::Parameter& input : InputsOf(scenario, robot)) inputs[std::string(input.name)] = input.value;
  return inputs;
}

metrics::GoalResult BuiltinGoal(const scenario::Scenario& scenario, const std::vector<apps::GoalPose>& poses) {
  const apps::GoalReport goal = apps::EvaluateGoal(apps::BareAppName(scenario.app.name), scenario.app.params,
                                                   apps::ArenaSize{scenario.arena.width_m, scenario.arena.height_m},
                                                   scenario.omni.body_radius_m, poses);
  metrics::GoalResult result;
  result.app = scenario.app.name;
  result.reached = goal.reached;
  result.error_m = goal.error_m;
  result.detail = goal.detail;
  return result;
}

metrics::GoalResult DeclaredGoal(const std::string& app, const std::vector<goals::CheckResult>& results) {
  metrics::GoalResult goal;
  goal.app = app;
  goal.source = "scenario";
  goal.error_m = std::numeric_limits<double>::quiet_NaN();
  size_t passed = 0;
  std::string first_failure;
  for (const goals::CheckResult& result : results) {
    metrics::GoalCheckResult check;
    check.name = result.name;
    check.check = std::string(goals::ToString(result.kind));
    check.when = std::string(goals::ToString(result.when));
    check.passed = result.passed;
    check.value = result.value;
    check.limit = result.limit;
    check.unit = std::string(goals::Unit(result.kind));
    check.reason = result.reason;
    check.samples = result.samples;
    check.deadline_s = result.deadline_s;
    if (result.held_from_epoch) check.held_from_epoch = *result.held_from_epoch;
    check.held_from_s = result.held_from_s;
    goal.checks.push_back(std::move(check));
    if (result.passed) {
      ++passed;
    } else if (first_failure.empty()) {
      first_failure = result.name + ": " + result.reason;
    }
  }
  goal.reached = passed == results.size();
  goal.detail = std::to_string(passed) + " of " + std::to_string(results.size()) + " checks passed" +
                (first_failure.empty() ? "" : "; " + first_failure);
  return goal;
}

std::vector<world::BodySpec> Bodies(const scenario::Scenario& scenario) {
  std::vector<world::BodySpec> bodies;
  for (const scenario::RobotSpec& robot : scenario.robots) {
    world::BodySpec body{};
    body.id = robot.id;
    body.kind = robot.kind;
    body.spec = scenario.kind_spec(robot.kind);
    body.x_m = robot.x_m;
    body.y_m = robot.y_m;
    body.heading_rad = robot.heading_rad;
    body.presence = robot.present_at_start ? world::BodyPresence::kActive : world::BodyPresence::kAbsent;
    bodies.push_back(body);
  }
  return bodies;
}

QueriesWorkspace::QueriesWorkspace()
    : memory_(static_cast<unsigned char*>(
          ::operator new(syrof_queries_workspace_size(), std::align_val_t(syrof_queries_workspace_alignment())))) {
  SYROF_CHECK(syrof_queries_workspace_init(memory_, syrof_queries_workspace_size(), &handle_) == SYROF_QUERIES_OK);
}

QueriesWorkspace::~QueriesWorkspace() {
  ::operator delete(memory_, std::align_val_t(syrof_queries_workspace_alignment()));
}

}  // namespace syrof::lab::sim
