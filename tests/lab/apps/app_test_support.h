// Test fixtures for the built-in apps: a fake Platform, hand-built LDMaps
// and a kinematic closed loop that runs a swarm of point robots epoch after
// epoch with perfect knowledge.
#pragma once

#include <cstdint>
#include <map>
#include <memory>
#include <string>
#include <string_view>
#include <vector>

#include "syrof/app/app.h"
#include "syrof/lab/apps/formation.h"
#include "syrof/lab/apps/builtin_goals.h"
#include "syrof/lab/apps/collision_avoidance.h"

namespace syrof::lab::apps::testing {

inline constexpr double kArenaM = 4.0;
inline constexpr double kBodyRadiusM = 0.1;
inline constexpr double kMaxSpeedMps = 0.5;
inline constexpr uint32_t kManeuverMs = 1000;

/// One queries workspace for the whole test binary (about 4 MB).
syrof_queries_workspace* SharedWorkspace();

/// Records what the app sends; hands out the shared workspace.
class FakePlatform final : public app::Platform {
 public:
  syrof_app_status SendMessageData(std::span<const uint8_t> payload) override;
  syrof_queries_workspace* queries_workspace() override { return SharedWorkspace(); }

  std::vector<uint8_t> payload;  ///< the last accepted payload
  int send_count = 0;
};

/// The facts of a 4 m x 4 m arena, omni robots (R 0.1 m, 0.5 m/s), 1 s maneuvers.
syrof_app_info MakeInfo(uint16_t self_id, uint16_t swarm_size);

/// A map under construction: members must be added in increasing id order.
struct MapBuilder {
  void Add(uint16_t id, double x_m, double y_m, std::vector<uint8_t> payload = {});
  /// The map as robot `self_id` receives it; valid while the builder lives.
  syrof_ldmap Build(uint16_t self_id, syrof_mode mode, uint16_t epoch = 1) const;
  std::vector<syrof_member_state> members;
};

/// What one robot's NewRound asked for, as a straight segment from its map
/// position (zero length for STOP).
struct Plan {
  syrof_car_command command{};
  Segment segment;
};

/// Runs Init and NewRound of a fresh instance of `app` for every member of
/// `map` (each as self) and returns their plans, in member order.
std::vector<Plan> PlanEveryRobot(std::string_view app, const std::map<std::string, double>& params,
                                 const MapBuilder& map, syrof_mode mode);

/// Result of a kinematic closed loop.
struct LoopResult {
  int epochs_to_goal = -1;           ///< first epoch after which the goal held; -1 if never
  int epochs_missed_after_goal = 0;  ///< epochs after epochs_to_goal whose end missed the goal
  double min_segment_distance_m = 1e9;  ///< closest approach of any two robots' swept segments
  double longest_move_m = 0;         ///< longest segment any robot drove in one epoch
  double fastest_mps = 0;            ///< highest commanded speed
  GoalReport final_report;
};

/// Point robots at `starts` (ids 0 ..), each with its own app instance,
/// drive their MOVE_TO segments exactly, epoch after epoch, for
/// `max_epochs`, judging EvaluateGoal on the true positions after each.
LoopResult RunClosedLoop(std::string_view app, const std::map<std::string, double>& params,
                         const std::vector<Position>& starts, int max_epochs);

/// `count` positions uniform in the arena (0.3 m from its walls), at least
/// `min_separation_m` apart, from a seeded SplitMix64.
std::vector<Position> RandomStarts(uint64_t seed, size_t count, double min_separation_m);

}  // namespace syrof::lab::apps::testing
