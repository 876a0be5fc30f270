// The scenario's faults on the radio-round grid: what is due at an instant.
//
// A fault at t takes effect at the first radio-round boundary at or after t
// (docs/scenarios.md), so a robot that starts or resumes runs its rounds in
// step with the others. A pause's resume is due one radio round before the
// first boundary at or after until_s: the robot's round task first runs one
// round after it restarts, so its first step is at that boundary and a pause
// from T to U misses exactly (U - T) / alpha round ends (docs/scenarios.md). The schedule only says what is due; the engine applies it
// (and decides, for a resume, whether the robot is still paused: a robot that
// crashed while paused stays crashed).
#pragma once

#include <cstdint>
#include <span>
#include <vector>

#include "syrof/lab/scenario/scenario.h"

namespace syrof::lab::sim {

/// One thing to do to one robot.
struct FaultAction {
  enum class Kind : uint8_t { kCrash, kPause, kJoin, kResume };
  Kind kind = Kind::kCrash;
  uint16_t robot = 0;

  bool operator==(const FaultAction&) const = default;
};

class FaultSchedule {
 public:
  /// `faults` in the scenario's order (the loader sorts them by at_s);
  /// `radio_round_ns` > 0 is the grid.
  FaultSchedule(std::span<const scenario::FaultSpec> faults, int64_t radio_round_ns);

  /// The actions due at `now_ns`, in the order they take effect: the crash,
  /// pause and join faults whose time has come (scenario order), then the
  /// resumes due now (scenario order). Empty off the grid. Call with
  /// non-decreasing times: each crash, pause or join is due once.
  std::span<const FaultAction> Due(int64_t now_ns);

  /// The grid point at or after `time_s`: when a fault at time_s takes effect.
  int64_t EffectiveNs(double time_s) const;

 private:
  std::vector<scenario::FaultSpec> faults_;
  std::vector<int64_t> resume_ns_;  // per fault: a pause's resume on the grid, else -1
  int64_t radio_round_ns_;
  size_t next_ = 0;
  std::vector<FaultAction> due_;
};

}  // namespace syrof::lab::sim
