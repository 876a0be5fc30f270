#include "syrof/lab/sim/run_parts.h"

#include <limits>
#include <span>

#include "syrof/base/split_mix64.h"

namespace syrof::lab::sim {

static_assert(replay::kMaxPayloadBytes == wire::kMaxPayloadBytes);

uint64_t SensorSeed(uint64_t seed, uint16_t robot) {
  return base::SplitMix64Hash(seed ^ base::SplitMix64Hash(0x53454e534f52ULL + robot));
}

uint64_t ChannelSeed(uint64_t seed) { return base::SplitMix64Hash(seed ^ 0x4348414e4e454cULL); }

uint64_t JitterSeed(uint64_t seed) { return base::SplitMix64Hash(seed ^ 0x4a4954544552ULL); }

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

}  // namespace syrof::lab::sim
