// The queries' own value types: members, targets and answers.
//
// Positions are integer millimetres in int16 range (-32768 .. 32767 mm,
// +-32.767 m), the resolution and range of the beacon every robot's map is
// built from (syrof/wire/beacon.h). Exact integer inputs are what make every
// robot reach the same answer; PointFromMetres() quantizes estimates in
// metres the way the beacon encoder does. Answers that are lengths come back
// in metres as float, each the float nearest to the exact value.
#pragma once

#include <array>
#include <cstdint>

// The build sets this for every target (top-level CMakeLists.txt); the
// default only serves compiling a file on its own.
#ifndef SYROF_MAX_SWARM_SIZE
#define SYROF_MAX_SWARM_SIZE 1024
#endif

namespace syrof::queries {

/// Largest number of members a query accepts; member ids are below it (the
/// swarm size limit of the beacon format, syrof::wire::kMaxSwarmSize).
inline constexpr uint16_t kMaxMembers = SYROF_MAX_SWARM_SIZE;
/// Largest number of targets MinWeightedMatching accepts.
inline constexpr uint16_t kMaxTargets = SYROF_MAX_SWARM_SIZE;
/// "No robot": never a valid id, because ids are below kMaxMembers <= 65535.
inline constexpr uint16_t kNoRobot = 0xFFFF;
/// "No target": never a valid target index (indices are below kMaxTargets).
inline constexpr uint16_t kNoTarget = 0xFFFF;

static_assert(SYROF_MAX_SWARM_SIZE >= 1 && SYROF_MAX_SWARM_SIZE <= 65535, "SYROF_MAX_SWARM_SIZE must be 1..65535");

/// A position in the swarm's frame, in millimetres.
struct Point {
  int16_t x_mm = 0;
  int16_t y_mm = 0;
  friend constexpr bool operator==(const Point&, const Point&) = default;
};

/// One robot of the map: its id (below kMaxMembers) and position.
struct Member {
  uint16_t id = 0;
  Point position;
  friend constexpr bool operator==(const Member&, const Member&) = default;
};

/// The smallest circle holding every member.
struct Circle {
  /// Centre and radius in metres: each the float nearest to the exact value
  /// (round to nearest, ties to even), so identical on every platform.
  float centre_x_m = 0.0f;
  float centre_y_m = 0.0f;
  float radius_m = 0.0f;
  /// How many members define the circle: 1 (every member at one position),
  /// 2 (the ends of a diameter) or 3 (on the circle, not collinear).
  uint8_t support_count = 0;
  /// The defining members' ids in increasing order; kNoRobot past
  /// support_count. Where several members share a defining position, the
  /// smallest of their ids stands for it.
  std::array<uint16_t, 3> support_ids = {kNoRobot, kNoRobot, kNoRobot};
};

/// Where MinWeightedMatching sends one robot.
struct Assignment {
  uint16_t robot_id = kNoRobot;
  /// Index into the targets; kNoTarget when the robot gets none (only when
  /// there are fewer targets than robots).
  uint16_t target_index = kNoTarget;
  friend constexpr bool operator==(const Assignment&, const Assignment&) = default;
};

/// The figures of a matching.
struct MatchingSummary {
  /// Number of matched pairs: min(robots, targets).
  uint16_t matched_count = 0;
  /// The longest matched distance, squared, in mm^2 (exact); 0 if none.
  uint64_t bottleneck_squared_mm2 = 0;
  /// The longest matched distance in metres (nearest float to the exact value).
  float bottleneck_m = 0.0f;
  /// The minimized total: the sum over matched pairs of each distance in
  /// units of 2^-15 mm, rounded down (the tie-break's exact measure).
  uint64_t total_distance_q15_mm = 0;
  /// total_distance_q15_mm in metres (nearest float).
  float total_m = 0.0f;
};

}  // namespace syrof::queries
