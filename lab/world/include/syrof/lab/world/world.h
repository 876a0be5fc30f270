// The physical world of the simulated lab: a walled rectangular arena and
// the robots' bodies (discs), moved by their drive commands within their
// kind's kinematic limits, kept from passing through each other and the
// walls, with every collision recorded.
//
// Units are SI and in the names; double precision; arena frame: origin at
// the lower-left corner, x right, y up, headings counter-clockwise from +x in
// [-pi, pi].
//
// Determinism: a World depends on no container iteration order; pairs are
// processed in increasing (a, b) order, bodies in increasing id. Its only
// randomness is the drones' drift, a counter-based hash of (seed, step time,
// robot, axis), so it does not depend on the order of anything either. The
// same seed and the same calls give the same bits; a world without drones
// draws nothing.
//
// Cost: a uniform grid (about one cell per body, cells at least one contact
// distance wide) finds the pairs near enough to matter, so a step is linear
// in the number of bodies; all storage is sized at construction.
#pragma once

#include <cstdint>
#include <optional>
#include <span>
#include <vector>

#include "syrof/lab/base/error.h"
#include "syrof/lab/sensors/trajectory.h"
#include "syrof/lab/world/arena.h"
#include "syrof/motion/controller.h"
#include "syrof/motion/drive.h"
#include "syrof/base/state_digest.h"

namespace syrof::lab::world {

/// One body's state, arena frame. ax/ay are the actual acceleration over the
/// last step (velocity change after contacts, divided by the step), which is
/// what the simulated IMU should feel.
struct BodyState {
  double x_m = 0;
  double y_m = 0;
  double heading_rad = 0;
  double vx_mps = 0;
  double vy_mps = 0;
  double yaw_rate_radps = 0;
  double ax_mps2 = 0;
  double ay_mps2 = 0;
};

/// Whether a body takes part in the world.
enum class BodyPresence : uint8_t {
  kAbsent = 0,   ///< not in the world (not yet joined): no motion, no contacts, not an obstacle
  kActive = 1,   ///< moves as its drive commands
  kStopped = 2,  ///< crashed or paused: stays as an obstacle, drive ignored, velocity 0, never pushed
};

/// "absent", "active", "stopped"; "?" otherwise.
const char* ToString(BodyPresence presence);

/// A body at construction.
struct BodySpec {
  uint16_t id = 0;  ///< bodies are given in id order 0 .. n-1
  RobotKind kind = RobotKind::kOmni;
  KindSpec spec{};  ///< radius and limits; all > 0
  double x_m = 0;             ///< initial pose
  double y_m = 0;
  double heading_rad = 0;
  BodyPresence presence = BodyPresence::kActive;
};

/// The start of a contact between bodies a < b, stamped with the end time of
/// the step in which it began.
struct Contact {
  int64_t time_ns = 0;
  uint16_t a = 0;
  uint16_t b = 0;
};

/// The start of a contact between a body and any wall.
struct WallContact {
  int64_t time_ns = 0;
  uint16_t robot = 0;
};

/// What World's constructor requires: a positive, finite arena; at most
/// 65535 bodies, each with its index as id, radius and limits > 0 and a
/// finite pose; a drone's tilt time constant, drift and flight height
/// finite and >= 0. Returns what is wrong and where (where "body 3", message
/// "radius and limits must be > 0"), or nothing. A scenario the loader
/// accepted always passes; a caller with other input checks it before
/// building a World.
std::optional<Error> CheckWorldSpec(const ArenaSpec& arena, std::span<const BodySpec> bodies);

/// A contact ends only when the gap exceeds this, so a body resting against
/// another (or a wall) and jittering by numerical noise counts once.
inline constexpr double kContactHysteresisM = 1e-3;

/// The drive kind the motion controller of a robot kind produces (the
/// motion layer's: omni and drone a velocity, rover wheels).
using motion::DriveKindFor;

class World {
 public:
  /// Requires CheckWorldSpec(arena, bodies) to pass: building a World from
  /// anything else is a caller's bug and stops the program (SYROF_CHECK,
  /// with the check's message). Bodies may start overlapping each other or a wall:
  /// the first Step separates them; contacts present at construction are not
  /// counted (placement, not motion, caused them).
  /// `seed` drives the drones' drift (nothing else draws from it).
  World(const ArenaSpec& arena, std::span<const BodySpec> bodies, uint64_t seed = 0);

  /// The body's latest setpoint, applied from the next Step on. A command of
  /// the other drive kind or with a non-finite field is replaced by zero
  /// speeds and counted in rejected_drives(). An unknown robot is a caller's bug
  /// (SYROF_CHECK), as in every call below that takes a robot.
  void SetDrive(uint16_t robot, const motion::DriveCommand& drive);

  /// Switches presence. Becoming absent or active starts the body from rest
  /// (wheels and velocity 0); becoming stopped keeps the velocity until the
  /// next Step, which stops it (so the IMU feels the crash). A body that
  /// becomes absent ends its contacts silently; a body that appears on top of
  /// another starts a contact at the next Step.
  void SetPresence(uint16_t robot, BodyPresence presence);

  /// Advances the world by dt_s > 0 (finite; else SYROF_CHECK) to the time now_ns (the state afterwards
  /// is the state at now_ns; new contacts are stamped now_ns):
  ///  1. integrates every active body toward its setpoint within its limits
  ///     (omni: velocity vector slews at most max_accel dt, speed capped,
  ///     yaw rate = setpoint capped; rover: each wheel slews at max_accel dt,
  ///     capped at max_speed, and the unicycle moves along the exact arc of
  ///     the mean wheel speeds; drone: as omni, but the velocity moves
  ///     toward the capped setpoint by the first-order lag's share of the
  ///     difference, 1 - exp(-dt / tilt_time_constant), still at most
  ///     max_accel dt, and a drift velocity, a Gauss-Markov process of
  ///     standard deviation drift_sigma per axis and correlation time
  ///     kDriftCorrelationS, is added on top);
  ///  2. records contacts: a pair (or body and wall) whose gap after
  ///     integration is <= 0 and was not touching starts one; touching ends
  ///     when that gap exceeds kContactHysteresisM;
  ///  3. separates overlaps: pairs in increasing (a, b) order pushed apart
  ///     along the centre line (a stopped body does not move, two movable
  ///     bodies move half each), then bodies put back inside the walls; a
  ///     few passes settle piles;
  ///  4. drops approaching velocity: each active body's velocity becomes the
  ///     nearest one with no component toward any body or wall it is in
  ///     contact with (its own component only: no momentum is passed on; a
  ///     robot's motors, not the bump, set its speed). A rover's wheels keep
  ///     turning (they slip);
  ///  5. sets ax, ay from the velocity change over the step;
  ///  6. updates min_separation_m() and max_overlap_m().
  void Step(int64_t now_ns, double dt_s);

  /// Number of bodies (ids 0 .. size() - 1).
  uint16_t size() const { return static_cast<uint16_t>(bodies_.size()); }
  /// The body's state (an unknown robot: SYROF_CHECK, as for the accessors below).
  const BodyState& state(uint16_t robot) const;
  /// The state in the simulated sensors' form.
  sensors::TrueState true_state(uint16_t robot) const;
  BodyPresence presence(uint16_t robot) const;
  double body_radius_m(uint16_t robot) const;
  /// Wheel speeds the rover's wheels actually turn at, m/s (0 for omni bodies).
  double left_wheel_mps(uint16_t robot) const;
  double right_wheel_mps(uint16_t robot) const;

  /// Contacts that started during the last Step, in increasing (a, b).
  std::span<const Contact> new_contacts() const { return new_contacts_; }
  /// Wall contacts that started during the last Step, in increasing robot.
  std::span<const WallContact> new_wall_contacts() const { return new_wall_contacts_; }
  /// Smallest surface-to-surface gap at the end of any step between two
  /// present (active or stopped) bodies, 0 when touching; +infinity before
  /// the first step or with fewer than two present bodies. Kept cheaply: the
  /// exact search over every body's neighbourhood runs only in steps where
  /// the movement since the last search (or a body appearing) could have
  /// brought some pair below the record.
  double min_separation_m() const { return min_separation_m_; }
  /// Largest overlap (penetration depth: sum of radii minus centre distance)
  /// between two present bodies at the end of any step, after separation:
  /// what the sensors, the replay and the goal see. 0 when bodies never
  /// overlapped. min_separation_m() clamps at 0 and cannot show this.
  double max_overlap_m() const { return max_overlap_m_; }
  /// Contacts and wall contacts started since construction.
  uint64_t contacts() const { return contacts_; }
  uint64_t wall_contacts() const { return wall_contacts_; }
  /// Drive commands replaced by zero speeds (wrong kind or non-finite).
  uint64_t rejected_drives() const { return rejected_drives_; }

  /// The bodies and the pairs in contact into `digest` (base/state_digest.h).
  void AddToDigest(base::StateDigest& digest) const;

 private:
  struct Body {
    BodyState state;
    BodyState previous;  // at the start of the current step (for the accelerations)
    RobotKind kind;
    KindSpec spec;
    BodyPresence presence;
    motion::DriveCommand drive;
    double left_mps = 0;   // rover wheel speeds
    double right_mps = 0;
    double drift_x_mps = 0;  // drone drift velocity, part of state.vx / vy
    double drift_y_mps = 0;
    bool touching_wall = false;
  };

  const Body& body(uint16_t robot) const;
  Body& body(uint16_t robot);
  void Integrate(Body& body, uint16_t robot, int64_t now_ns, double dt_s) const;
  void MoveHolonomic(Body& body, double vx, double vy, double dt_s) const;
  void IntegrateOmni(Body& body, double dt_s) const;
  void IntegrateDrone(Body& body, uint16_t robot, int64_t now_ns, double dt_s) const;
  // A standard normal number for (step time, robot, axis) from the seed.
  double DriftNormal(int64_t now_ns, uint16_t robot, int axis) const;
  void IntegrateRover(Body& body, double dt_s) const;
  // Counting sort of the present bodies into the grid by their current position.
  void BuildGrid();
  int CellOf(double x_m, double y_m) const;
  // Pairs of present bodies with a gap <= kCandidateGapM, sorted (a, b).
  void FindCandidates();
  void RecordContacts(int64_t now_ns);
  struct Normal {
    double x;
    double y;
  };
  // One pass of pushing overlapping pairs apart, then bodies inside the
  // walls (positions only); returns the largest displacement made.
  double SeparateOnce();
  // Removes from each active body's velocity its components toward the
  // bodies and walls it is in contact with (the nearest allowed velocity).
  void DropApproachingVelocities();
  void AddConstraint(uint16_t robot, double nx, double ny);
  static Normal NearestAllowed(Normal velocity, std::span<const Normal> normals);
  double ClampToWalls(Body& body) const;
  double WallGap(const Body& body) const;
  double Gap(uint16_t a, uint16_t b) const;
  void UpdateMinSeparation(double max_displacement_m);
  // min(best_m, exact smallest gap between present bodies), searching
  // outward from each body no further than `best_m` (the smallest known so
  // far). Rebuilds the grid.
  double SmallestGap(double best_m);

  double width_m_;
  double height_m_;
  uint64_t seed_;
  std::vector<Body> bodies_;
  double max_radius_m_ = 0;

  // The grid: cell size >= 2 max radius + candidate gap, about one cell per body.
  double cell_m_ = 1;
  int columns_ = 1;
  int rows_ = 1;
  std::vector<uint32_t> cell_start_;   // columns * rows + 1 prefix sums
  std::vector<uint16_t> cell_bodies_;  // present bodies, grouped by cell, increasing id in each
  std::vector<int> body_cell_;         // cell of each present body (-1: absent)
  std::vector<uint32_t> cell_cursor_;  // scratch for the counting sort

  std::vector<uint32_t> candidates_;   // (a << 16) | b, sorted
  std::vector<uint8_t> candidate_in_contact_;  // per candidate: touching this step
  std::vector<uint32_t> constraint_start_;     // per body, offsets into constraints_ (n + 1)
  std::vector<uint32_t> constraint_cursor_;
  std::vector<Normal> constraints_;            // unit normals toward each body's contacts
  std::vector<uint32_t> touching_;     // pairs in contact after the last step, sorted
  std::vector<uint32_t> touching_next_;
  std::vector<Contact> new_contacts_;
  std::vector<WallContact> new_wall_contacts_;

  double min_separation_m_;
  // No two present bodies are closer than this (-infinity: unknown). Set by
  // each SmallestGap search, lowered by every step's movement: while it is
  // >= min_separation_m_ no pair can lower the record and the search is skipped.
  double gap_floor_m_;
  double floor_slack_m_ = 0;  // taken off the floor by a step that moved anything
  double max_overlap_m_ = 0;
  uint64_t contacts_ = 0;
  uint64_t wall_contacts_ = 0;
  uint64_t rejected_drives_ = 0;
};

}  // namespace syrof::lab::world
