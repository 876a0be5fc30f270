#include "app_test_support.h"

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstdlib>
#include <new>

#include "syrof/base/split_mix64.h"
#include "syrof/lab/apps/catalog.h"

namespace syrof::lab::apps::testing {

syrof_queries_workspace* SharedWorkspace() {
  static syrof_queries_workspace* const workspace = [] {
    void* memory = ::operator new(syrof_queries_workspace_size(), std::align_val_t{syrof_queries_workspace_alignment()});
    syrof_queries_workspace* created = nullptr;
    if (syrof_queries_workspace_init(memory, syrof_queries_workspace_size(), &created) != SYROF_QUERIES_OK) {
      std::abort();
    }
    return created;  // lives as long as the test binary
  }();
  return workspace;
}

syrof_app_status FakePlatform::SendMessageData(std::span<const uint8_t> bytes) {
  ++send_count;
  if (bytes.size() > SYROF_APP_MAX_PAYLOAD_BYTES) return SYROF_APP_PAYLOAD_TOO_LONG;
  payload.assign(bytes.begin(), bytes.end());
  return SYROF_APP_OK;
}

syrof_app_info MakeInfo(uint16_t self_id, uint16_t swarm_size) {
  syrof_app_info info{};
  info.abi_version = SYROF_APP_ABI_VERSION;
  info.self_id = self_id;
  info.swarm_size = swarm_size;
  info.radio_round_ms = 50;
  info.maneuver_ms = kManeuverMs;
  info.arena_width_m = static_cast<float>(kArenaM);
  info.arena_height_m = static_cast<float>(kArenaM);
  info.body_radius_m = static_cast<float>(kBodyRadiusM);
  info.max_speed_mps = static_cast<float>(kMaxSpeedMps);
  return info;
}

void MapBuilder::Add(uint16_t id, double x_m, double y_m, std::vector<uint8_t> payload) {
  syrof_member_state member{};
  member.id = id;
  member.x_mm = static_cast<int16_t>(std::lround(x_m * 1000.0));
  member.y_mm = static_cast<int16_t>(std::lround(y_m * 1000.0));
  member.phase = SYROF_PHASE_VOTE;
  member.payload_length = static_cast<uint8_t>(std::min<size_t>(payload.size(), SYROF_APP_MAX_PAYLOAD_BYTES));
  std::copy_n(payload.begin(), member.payload_length, member.payload);
  members.push_back(member);
}

syrof_ldmap MapBuilder::Build(uint16_t self_id, syrof_mode mode, uint16_t epoch) const {
  syrof_ldmap map{};
  map.epoch = epoch;
  map.mode = static_cast<uint8_t>(mode);
  map.self_id = self_id;
  map.member_count = static_cast<uint16_t>(members.size());
  map.members = members.data();
  return map;
}

namespace {

Position MapPosition(const syrof_member_state& member) {
  return {member.x_mm / 1000.0, member.y_mm / 1000.0};
}

Segment SegmentOf(const syrof_car_command& command, Position start) {
  if (command.kind != SYROF_COMMAND_MOVE_TO) return {start, start};
  return {start, {static_cast<double>(command.x_m), static_cast<double>(command.y_m)}};
}

}  // namespace

std::vector<Plan> PlanEveryRobot(std::string_view app, const std::map<std::string, double>& params,
                                 const MapBuilder& map, syrof_mode mode) {
  std::vector<Plan> plans;
  for (const syrof_member_state& member : map.members) {
    FakePlatform platform;
    std::unique_ptr<app::App> instance = MakeBuiltinApp(app, params);
    uint8_t global_state = 0;
    EXPECT_TRUE(instance->Init(MakeInfo(member.id, static_cast<uint16_t>(map.members.size())), platform, global_state).ok());
    Plan plan;
    EXPECT_TRUE(instance->NewRound(plan.command, map.Build(member.id, mode), global_state, 0).ok());
    plan.segment = SegmentOf(plan.command, MapPosition(member));
    plans.push_back(plan);
  }
  return plans;
}

LoopResult RunClosedLoop(std::string_view app, const std::map<std::string, double>& params,
                         const std::vector<Position>& starts, int max_epochs) {
  const size_t count = starts.size();
  std::vector<std::unique_ptr<app::App>> apps;
  std::vector<FakePlatform> platforms(count);
  std::vector<Position> positions = starts;
  std::vector<uint8_t> global_states(count, 0);
  for (size_t i = 0; i < count; ++i) {
    apps.push_back(MakeBuiltinApp(app, params));
    EXPECT_TRUE(apps[i]->Init(MakeInfo(static_cast<uint16_t>(i), static_cast<uint16_t>(count)), platforms[i],
                              global_states[i]).ok());
  }
  LoopResult result;
  std::vector<Segment> segments(count);
  for (int epoch = 1; epoch <= max_epochs; ++epoch) {
    // Every robot holds the same map: positions rounded to millimetres and
    // the payloads frozen at the end of the previous maneuver.
    MapBuilder map;
    for (size_t i = 0; i < count; ++i) {
      map.Add(static_cast<uint16_t>(i), positions[i].x_m, positions[i].y_m, platforms[i].payload);
    }
    for (size_t i = 0; i < count; ++i) {
      syrof_car_command command{};
      const syrof_ldmap ldmap = map.Build(static_cast<uint16_t>(i), SYROF_MODE_COOPERATIVE, static_cast<uint16_t>(epoch));
      EXPECT_TRUE(apps[i]->NewRound(command, ldmap, global_states[i], static_cast<uint32_t>(epoch) * 1400).ok());
      segments[i] = SegmentOf(command, positions[i]);
      if (command.kind == SYROF_COMMAND_MOVE_TO) {
        result.fastest_mps = std::max(result.fastest_mps, static_cast<double>(command.speed_mps));
      }
    }
    for (size_t i = 0; i < count; ++i) {
      result.longest_move_m = std::max(result.longest_move_m, SegmentLengthM(segments[i]));
      for (size_t j = i + 1; j < count; ++j) {
        result.min_segment_distance_m = std::min(result.min_segment_distance_m, SegmentDistanceM(segments[i], segments[j]));
      }
    }
    for (size_t i = 0; i < count; ++i) {
      positions[i] = segments[i].end;
      const syrof_ldmap ldmap = map.Build(static_cast<uint16_t>(i), SYROF_MODE_COOPERATIVE, static_cast<uint16_t>(epoch));
      EXPECT_TRUE(apps[i]->EndOfRound(ldmap, global_states[i], static_cast<uint32_t>(epoch) * 1400 + 1000).ok());
    }
    std::vector<GoalPose> poses;
    for (size_t i = 0; i < count; ++i) poses.push_back({static_cast<uint16_t>(i), positions[i].x_m, positions[i].y_m, 0, true});
    result.final_report = EvaluateGoal(app, params, {kArenaM, kArenaM}, kBodyRadiusM, poses);
    if (result.epochs_to_goal < 0) {
      if (result.final_report.reached) result.epochs_to_goal = epoch;
    } else if (!result.final_report.reached) {
      ++result.epochs_missed_after_goal;
    }
  }
  return result;
}

std::vector<Position> RandomStarts(uint64_t seed, size_t count, double min_separation_m) {
  base::SplitMix64 random(seed);
  std::vector<Position> starts;
  while (starts.size() < count) {
    const Position candidate{random.Between(300, 3700) / 1000.0, random.Between(300, 3700) / 1000.0};
    const bool clear = std::all_of(starts.begin(), starts.end(), [&](const Position& other) {
      return std::hypot(other.x_m - candidate.x_m, other.y_m - candidate.y_m) >= min_separation_m;
    });
    if (clear) starts.push_back(candidate);
  }
  return starts;
}

}  // namespace syrof::lab::apps::testing
