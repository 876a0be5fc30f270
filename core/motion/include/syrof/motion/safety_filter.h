// The safety filter: the last word on every drive command, in every mode
// (docs/safety.md is the specification, with the proof sketch).
//
// Every robot heard recently is an obstacle disc: centred at its last
// reported position, of radius
//     rho = own radius + the swarm's largest radius + margin + sigma,
//     sigma = others' speed limit * min(age, horizon) + braking allowance,
// where `age` is how old the report's position is and the braking allowance
// (v^2 / 2 a from the report's own velocity) covers a robot that froze its
// snapshot while still moving and then braked (WAIT / VOTE beacons carry the
// snapshot frozen at the end of the maneuver). The walls are obstacles too.
//
// With h the gap between this robot's estimated position and a disc's edge
// and n the unit vector towards the disc's centre, the command's velocity u
// is limited so that:
//   outside (h > 0):  u . n <= min(gain * h, sqrt(a h))   (it can still
//                     brake to a stop at the edge with half its
//                     deceleration a: the other may be closing in too, and
//                     brakes with half of its own);
//   inside (h <= 0):  u moves away from every point where the other robot
//                     can be: u . n <= -sin(phi) |u|, sin(phi) = sigma / d,
//                     d the distance to the centre (no direction when
//                     sigma >= d: the robot stops).
// Walls: u . n <= min(gain * h, sqrt(2 a h)) with h the distance to the wall
// less radius and margin, and u . n <= 0 once there. A stopped robot
// satisfies every constraint, so the filter always has an answer.
// A robot whose velocity lags its setpoint (a drone: ControllerConfig's
// limits.response_lag_s, its tilt time constant tau) goes on for up to tau
// before its braking takes hold, so its stopping distance from v is
// v tau + v^2 / 2a: against a robot u . n <= BrakingSpeed(h, a/2, 2 tau)
// (its half of the gap, v tau + v^2 / 2a <= h / 2), against a wall
// BrakingSpeed(h, a, tau) (motion/controller.h); without a lag these are the
// square roots above, bit for bit. A parked report's braking allowance is
// v lag + v^2 / 2a with the swarm's longest lag (SafetyConfig::others_lag_s).
//
// Each disc also grows by this robot's own position uncertainty beyond half
// the margin (own_sigmas of its EKF's standard deviation), and the command is scaled down until it
// keeps every constraint in every direction within heading_sigmas of the
// heading's standard deviation of the commanded one (the body moves along
// its true heading, not the estimated one).
//
// Omni: u is the velocity setpoint, corrected by cyclic projection onto the
// constraints (a fixed number of passes); if the result still breaks one,
// the robot stops. Rover: only the forward speed is limited (along the
// heading; turning in place moves no point of the disc), by the interval the
// constraints leave; empty interval: forward speed 0, the turn is kept.
//
// Portable: no allocation, no exceptions, no I/O; float math (sqrt only),
// fine on a soft-float core. Cost: one pass over the table (swarm size
// entries; a squared-distance test rejects far robots without a square
// root), then at most kMaxSafetyConstraints constraints times
// kSafetyPasses projections. Plain data, copyable.
#pragma once

#include <array>
#include <cstddef>
#include <cstdint>

#include "syrof/base/state_digest.h"
#include "syrof/estimation/messages.h"
#include "syrof/motion/controller.h"
#include "syrof/motion/drive.h"
#include "syrof/wire/member_set.h"

namespace syrof::motion {

/// The "other" of an intervention against a wall.
inline constexpr uint16_t kWallObstacle = 0xFFFF;
/// The constraints one step keeps (the nearest ones: smallest slack first).
inline constexpr size_t kMaxSafetyConstraints = 16;
/// Projection passes over the kept constraints.
inline constexpr int kSafetyPasses = 4;
/// A hold (a run of limited commands) ends after this long without a
/// limited command; a robot held at a disc's edge is limited on and off
/// from step to step, and that is one hold, not dozens.
inline constexpr int64_t kInterventionReleaseNs = 500'000'000;

/// How many of a robot's own position standard deviations the safety filter
/// allows for its true position error (SafetyConfig::own_sigmas), every kind.
/// A consistent 2-D estimate is further than k sigmas off with probability
/// exp(-k^2 / 2): 13.5% at two, 0.03% at four. The lab's EKF is consistent
/// (position NEES about 2 for 2), and four covers the true error in more
/// than 99.9% of robot-rounds of every kind, where two left it past the
/// allowance in 12% and a mixed swarm collided (mixed/gather_4_4_loss seed
/// 2); measured by bench_lab_margin_coverage (docs/safety.md, "Margin
/// coverage"). At the usual 2.2 cm sigma every disc grows by 5.8 cm.
inline constexpr float kOwnSigmas = 4.0f;

/// What the filter assumes about the swarm. SI units.
struct SafetyConfig {
  bool enabled = true;
  uint16_t self_id = 0;
  float others_max_speed_mps = 0.5f;  ///< the fastest kind in the swarm (a beacon does not say its sender's kind)
  float others_radius_m = 0.12f;      ///< the largest body radius in the swarm
  float others_braking_mps2 = 0.8f;   ///< the weakest deceleration in the swarm (braking allowance)
  /// The longest response lag in the swarm (a drone's tilt time constant;
  /// 0 without drones): a parked report's sender may go on at its frozen
  /// speed this long before it brakes (braking allowance v lag + v^2 / 2a).
  float others_lag_s = 0.0f;
  float margin_m = 0.06f;             ///< covers two estimates' errors, half each (docs/safety.md)
  /// Every disc grows by what this many of this robot's own position
  /// standard deviations (the EKF's, the larger of x and y) exceed half the
  /// margin: the robot may be further from where it believes than the margin
  /// allows for. A lost estimate (sigma capped at max_own_sigma_m) grows the
  /// discs until the robot stops near anyone. kOwnSigmas for every kind
  /// (docs/safety.md, "Margin coverage").
  float own_sigmas = kOwnSigmas;
  /// The rule an app is held to: a limited step is charged to the app (an
  /// intervention, which assignments grade) only where a filter that grows
  /// the discs by this many own sigmas would have limited the command too.
  /// A step held only by the cover own_sigmas adds beyond it is a
  /// precaution: the platform's insurance against its own estimate, not
  /// the app's doing (docs/safety.md, "Interventions and precautions").
  /// At or above own_sigmas every limited step is charged.
  float charged_sigmas = 2.0f;
  float max_own_sigma_m = 0.5f;
  /// The direction the robot really moves may be off its commanded one by
  /// this many heading standard deviations less heading_free_rad (what the
  /// margin absorbs), capped at a right angle: the command must keep every
  /// constraint in all of them. A heading whose filter doubts it slows the
  /// robot near others; a well-known one changes nothing.
  float heading_sigmas = 2.0f;
  float heading_free_rad = 0.1f;
  float horizon_s = 1.0f;             ///< a disc grows for at most this long; older reports keep the capped disc
  float gain_per_s = 4.0f;            ///< approach speed = gain * gap near an edge
  float arena_width_m = 0;            ///< walls at x = 0, x = width, y = 0, y = height; 0: no walls
  float arena_height_m = 0;
};

/// How far this robot's true position may be from `estimate` for the safety
/// filter, in metres: half the margin, or own_sigmas times the larger of the
/// estimate's position standard deviations (capped at max_own_sigma_m; a
/// sigma that is not a number counts as the cap), whichever is more. Every
/// disc grows by what this exceeds half the margin. The consistency bench
/// (bench_lab_margin_coverage) counts the robot-rounds whose true error
/// exceeds it.
float OwnErrorAllowanceM(const SafetyConfig& config, const estimation::StateEstimate& estimate);

/// The last report of one robot: where it was at `time_ns` (port clock), in
/// the beacon's own units, so recording one (every beacon heard, O(N^2) per
/// round in a swarm) is a copy; the filter converts the few it looks at.
struct SafetyReport {
  int64_t time_ns = 0;
  int16_t x_mm = 0;
  int16_t y_mm = 0;
  uint16_t allowance_mm = 0;  ///< added to the disc: the sender may still brake this far
  bool valid = false;
};

/// One report per robot id, by id. Filled by the round task from beacons,
/// read by the motion task.
class SafetyReports {
 public:
  /// Records robot `id`'s position (millimetres, as beacons carry it) at
  /// `time_ns`; `parked` (a frozen WAIT / VOTE snapshot) with velocity (vx,
  /// vy) in mm/s adds its braking distance at `braking_mps2`. Ids >=
  /// wire::kMaxSwarmSize are ignored.
  void Report(uint16_t id, int64_t time_ns, int16_t x_mm, int16_t y_mm, bool parked, int16_t vx_mm_s,
              int16_t vy_mm_s, float braking_mps2, float lag_s = 0.0f) {
    // Inline: the runtime records every beacon heard.
    if (id >= entries_.size()) return;
    SafetyReport& entry = entries_[id];
    entry.time_ns = time_ns;
    entry.x_mm = x_mm;
    entry.y_mm = y_mm;
    entry.allowance_mm =
        parked && (vx_mm_s != 0 || vy_mm_s != 0) ? BrakingMillimetres(vx_mm_s, vy_mm_s, braking_mps2, lag_s) : 0;
    entry.valid = true;
  }
  /// A position another robot relayed for robot `id` (wire::Relay): where
  /// `id` was when the relaying robot last heard of it, at least a horizon
  /// ago. Recorded only where this robot holds no report of `id` at all: a
  /// report heard directly, or relayed before, is never replaced by
  /// hearsay, and `id`'s own next beacon replaces this one. The caller
  /// stamps it at least a horizon old (the capped disc); `allowance_mm`
  /// covers the relay's rounding. Returns whether it was recorded.
  bool Relayed(uint16_t id, int64_t time_ns, int16_t x_mm, int16_t y_mm, uint16_t allowance_mm) {
    if (id >= entries_.size() || entries_[id].valid) return false;
    SafetyReport& entry = entries_[id];
    entry.time_ns = time_ns;
    entry.x_mm = x_mm;
    entry.y_mm = y_mm;
    entry.allowance_mm = allowance_mm;
    entry.valid = true;
    return true;
  }
  /// Looks at up to `limit` robots after `cursor`, going round the ids
  /// below `count` (`cursor` itself last), for one other than `self` whose
  /// report is older than `before_ns`: a robot gone silent, whose position
  /// to relay next. Moves `cursor` to it, or to the last robot looked at,
  /// so the next call goes on from there: a bounded step however large the
  /// swarm. kNoSilentReport when none of them is silent.
  static constexpr uint16_t kNoSilentReport = 0xFFFF;
  uint16_t NextSilent(uint16_t& cursor, uint16_t self, size_t count, int64_t before_ns, size_t limit) const;
  /// The same in metres (tests, benches): rounded to millimetres.
  void ReportMetres(uint16_t id, int64_t time_ns, float x_m, float y_m, bool parked, float vx_mps, float vy_mps,
                    float braking_mps2, float lag_s = 0.0f);
  /// Copies the first `count` entries of `other`, and its listening gap
  /// (the motion task's handoff).
  void CopyFrom(const SafetyReports& other, size_t count);
  const SafetyReport& operator[](size_t id) const { return entries_[id]; }

  /// This robot heard nothing from `start_ns` to `end_ns` (it was paused: its
  /// round task did not run). A robot whose report was fresh when the gap
  /// began may have moved all through it before falling silent, so its disc
  /// grows for the gap's length on top of the horizon (docs/safety.md, "A
  /// robot that was not listening"). Only the latest gap is kept.
  void MarkListeningGap(int64_t start_ns, int64_t end_ns) {
    gap_start_ns_ = start_ns;
    gap_end_ns_ = end_ns;
  }
  int64_t gap_start_ns() const { return gap_start_ns_; }
  int64_t gap_end_ns() const { return gap_end_ns_; }

  /// The first `count` entries and the gap into `digest` (base/state_digest.h).
  void AddToDigest(base::StateDigest& digest, size_t count) const {
    for (size_t i = 0; i < count; ++i) {  // field by field: SafetyReport has padding
      const SafetyReport& entry = entries_[i];
      digest.AddValue(entry.time_ns);
      digest.AddValue(entry.x_mm);
      digest.AddValue(entry.y_mm);
      digest.AddValue(entry.allowance_mm);
      digest.AddValue(entry.valid);
    }
    digest.AddValue(gap_start_ns_);
    digest.AddValue(gap_end_ns_);
  }

 private:
  static uint16_t BrakingMillimetres(int16_t vx_mm_s, int16_t vy_mm_s, float braking_mps2, float lag_s);

  std::array<SafetyReport, wire::kMaxSwarmSize> entries_{};
  int64_t gap_start_ns_ = 0;
  int64_t gap_end_ns_ = 0;
};

/// What one Apply did.
struct SafetyOutcome {
  bool limited = false;  ///< the command was changed
  /// Limited, and a filter at SafetyConfig::charged_sigmas would have
  /// limited it too (the app's command broke the rule it is held to), or
  /// an earlier step of the same hold was charged (later steps of a
  /// charged hold are not checked again: the hold is an intervention).
  bool charged = false;
  /// The first charged step of a hold (limited steps less than
  /// kInterventionReleaseNs apart): an intervention starts. One per hold.
  bool started = false;
  /// The first step of a hold, and not charged: a precaution starts (the
  /// hold may become an intervention later, at its first charged step).
  bool precaution_started = false;
  uint16_t other = 0;    ///< the robot (or kWallObstacle) whose constraint the command broke most
};

class SafetyFilter {
 public:
  /// `controller` gives this robot's kind, radius, speed and braking;
  /// `swarm_size` bounds the table scan.
  SafetyFilter(const SafetyConfig& config, const ControllerConfig& controller, uint16_t swarm_size);

  /// `desired` limited against `reports` from this robot's `estimate` at
  /// `now_ns`. Unchanged when disabled, when the estimate is unusable (the
  /// controller then commands zero anyway) or when nothing binds.
  DriveCommand Apply(const DriveCommand& desired, const estimation::StateEstimate& estimate,
                     const SafetyReports& reports, int64_t now_ns, SafetyOutcome& outcome);

  /// Whether Apply would look at the reports for `desired`: only a command
  /// that moves the robot's centre (a rover turning in place does not). The
  /// runtime hands the reports to the motion task only then.
  bool NeedsReports(const DriveCommand& desired) const;

  const SafetyConfig& config() const { return config_; }
  /// Applies that changed the command; how many of them started an
  /// intervention (charged), and how many a precaution (SafetyOutcome).
  uint32_t limited_steps() const { return limited_steps_; }
  uint32_t interventions() const { return interventions_; }
  uint32_t precautions() const { return precautions_; }

  /// What one Apply leaves for the next into `digest` (base/state_digest.h):
  /// the constraints are rebuilt by every Apply.
  void AddToDigest(base::StateDigest& digest) const {
    digest.AddValue(ever_limited_);
    digest.AddValue(last_limited_ns_);
    digest.AddValue(hold_charged_);
  }

 private:
  struct Constraint {
    float nx, ny;     // unit vector towards the obstacle
    float bound;      // u . n <= bound (linear), or the cone's sin(phi)
    bool cone;        // u . n <= -bound * |u|
    uint16_t other;
    // A robot's disc (not a wall): the squared distance to its centre, that
    // distance, and the other's growth, so the constraint can be rebuilt for
    // a smaller allowance (BreaksChargedRule) without another pass over the
    // reports or another square root.
    float squared_m2;
    float distance_m;
    float sigma_m;
  };
  void Collect(float x, float y, float own_allowance_m, const SafetyReports& reports, int64_t now_ns);
  float DiscBaseM(float own_allowance_m) const;
  void RobotConstraint(Constraint& constraint, float radius_m) const;
  float HeadingRobustScale(float ux, float uy, float doubt_rad) const;
  void Keep(const Constraint& constraint, float slack);
  DriveCommand Limit(const DriveCommand& desired, float hx, float hy, float heading_doubt_rad, float& change) const;
  bool BreaksChargedRule(const DriveCommand& desired, const estimation::StateEstimate& estimate,
                         float own_allowance_m, float hx, float hy, float heading_doubt_rad);
  void LimitOmni(float& vx, float& vy) const;
  float LimitForward(float speed, float hx, float hy) const;
  float ApproachBound(float gap_m, float braking_mps2, float lag_s) const;

  SafetyConfig config_;
  float own_radius_m_;
  float own_max_speed_mps_;
  float own_braking_mps2_;
  float own_lag_s_;
  DriveKind kind_;
  uint16_t swarm_size_;
  std::array<Constraint, kMaxSafetyConstraints> constraints_{};
  std::array<float, kMaxSafetyConstraints> slack_{};
  size_t count_ = 0;
  float reach_m_ = 0;  // Collect's: how far beyond a disc's edge a constraint can bind
  bool ever_limited_ = false;
  int64_t last_limited_ns_ = 0;
  bool hold_charged_ = false;  // the current hold has had its charged step
  uint32_t limited_steps_ = 0;
  uint32_t interventions_ = 0;
  uint32_t precautions_ = 0;
};

}  // namespace syrof::motion
