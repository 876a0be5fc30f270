// The motion benchmark's crowd: robot 0 at (2, 2) m and, on two rings
// around it, the other robots of a 32-robot swarm, the first `near` of them
// within the safety filter's reach (0.30 to 0.37 m away, the discs' edges
// within a braking distance of robot 0), the rest at least 1 m away. With
// near = 31 every report the registry can hold is within reach: more than
// bodies could fit around one robot, but what a robot with stale or wrong
// estimates of its neighbours may be handed, and so the filter's worst scan.
// Host-tested (tests/bench/m4/motion: each near robot alone limits a command
// aimed at it).
#pragma once

#include <cmath>
#include <cstdint>

#include "syrof/motion/safety_filter.h"

namespace syrof::bench {

inline constexpr uint16_t kCrowdSwarm = 32;
inline constexpr float kCrowdCentreM = 2.0f;

/// Where robot `id` (1 .. kCrowdSwarm - 1) stands: within reach when
/// id <= near.
inline void CrowdPosition(uint16_t id, int near, float& x_m, float& y_m) {
  const float angle = 0.7f * static_cast<float>(id);
  const float radius_m = id <= near ? 0.30f + 0.0025f * static_cast<float>(id) : 1.0f + 0.05f * static_cast<float>(id);
  x_m = kCrowdCentreM + radius_m * std::cos(angle);
  y_m = kCrowdCentreM + radius_m * std::sin(angle);
}

/// Reports for robots 1 .. kCrowdSwarm - 1, as of time 0, every third one
/// parked (a frozen WAIT / VOTE snapshot with a braking allowance).
inline void FillCrowd(motion::SafetyReports& reports, int near) {
  for (uint16_t id = 1; id < kCrowdSwarm; ++id) {
    float x_m = 0, y_m = 0;
    CrowdPosition(id, near, x_m, y_m);
    reports.ReportMetres(id, 0, x_m, y_m, id % 3 == 0, 0.1f, 0.0f, 0.8f);
  }
}

}  // namespace syrof::bench
