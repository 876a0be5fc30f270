// The formations the built-in apps build, as pure functions of their
// parameters, the arena, the body radius and the robot count: the gather
// app's hexagonal packing, the circle app's evenly spaced points and the
// leader_follow app's path and slots. The apps plan with them on every
// robot and the goal checks (builtin_goals.h) judge final poses with them, so a plan
// and its check can never disagree about where robots belong.
//
// Units: metres, radians, seconds; arena frame: the arena spans
// [0, width] x [0, height], x right, y up, angles counter-clockwise from +x.
// Every function is deterministic: the same inputs give the same bits.
#pragma once

#include <cstddef>
#include <map>
#include <string>
#include <vector>

namespace syrof::lab::apps {

/// A point in the arena frame, metres.
struct Position {
  double x_m = 0;
  double y_m = 0;
};

/// The arena [0, width_m] x [0, height_m].
struct ArenaSize {
  double width_m = 0;
  double height_m = 0;
};

/// Distance kept above every safety distance the formations are sized from
/// (millimetre rounding of maps, controller tolerance), metres.
inline constexpr double kPlanSlackM = 0.02;

/// What the platform's safety filter grows every disc by beyond what the
/// plans' margin absorbs, at the lab's usual position doubt, when it allows
/// for four of a robot's own position sigmas (SafetyConfig::own_sigmas = 4,
/// motion::kOwnSigmas, what covers the true error in 99.9% of
/// robot-rounds): 8.8 cm at a 2.2 cm sigma, less the half of its 6 cm margin that
/// covers it, 5.8 cm, of which the plans' margin absorbs the 1.4 cm of two
/// sigmas (docs/safety.md, "Margin coverage"). A follower whose next slot is
/// nearer its predecessor's start than the filter's disc is held off it, and
/// the line falls behind.
inline constexpr double kFilterGrowthM = 0.045;

/// Parameters of `gather` (catalog.h lists defaults and bounds).
struct GatherParams {
  double gap_m = 0.1;        ///< free space between neighbouring bodies in the packing
  double tolerance_m = 0.1;  ///< goal: allowed excess of the swarm's radius over the packing's
  double margin_m = 0.08;    ///< safety margin added to 2 body radii (estimation and control error)
};

/// Parameters of `circle`.
struct CircleParams {
  double radius_m = 1.2;      ///< circle radius (raised if the robots do not fit, lowered to fit the arena)
  double centre_x_m = -1;     ///< centre; negative means the arena's centre
  double centre_y_m = -1;
  double tolerance_m = 0.1;   ///< goal: largest distance of a robot from its point
  double margin_m = 0.08;     ///< safety margin
};

/// Parameters of `leader_follow`.
struct LeaderFollowParams {
  double speed_mps = 0.15;     ///< the leader's speed along its path (an upper bound, see LeaderStepM)
  double spacing_m = 0.4;      ///< distance between consecutive robots of the line
  double path_radius_m = 1.2;  ///< radius of the leader's circular path around the arena centre
  double tolerance_m = 0.1;    ///< goal: largest distance of a robot from its slot
  double margin_m = 0.08;      ///< safety margin
};

/// The parameters of each app from a scenario's map; missing keys take the
/// catalog's defaults, unknown keys are ignored.
GatherParams ReadGatherParams(const std::map<std::string, double>& params);
CircleParams ReadCircleParams(const std::map<std::string, double>& params);
LeaderFollowParams ReadLeaderFollowParams(const std::map<std::string, double>& params);

/// `position` moved into the part of the arena a body of `body_radius_m`
/// may occupy while keeping `margin_m` from every wall; the arena's centre
/// line on an axis too short for that.
Position ClampIntoArena(Position position, ArenaSize arena, double body_radius_m, double margin_m);

// ---- gather --------------------------------------------------------------

/// Centre-to-centre distance of neighbouring slots of the packing:
/// 2 R + max(gap, margin + kPlanSlackM). The gap is raised to exceed the
/// margin so a robot can always enter a slot next to an occupied one
/// without breaking the safety rule (docs/apps.md).
double GatherSpacingM(const GatherParams& params, double body_radius_m);

/// The `count` points of a hexagonal lattice of `spacing_m` around the
/// origin nearest to it, nearest first (equal distances by angle from +x in
/// [0, 2 pi)). The first is the origin.
std::vector<Position> HexSlots(size_t count, double spacing_m);

/// Distance from the origin of the farthest of HexSlots(count, spacing_m);
/// 0 for count <= 1.
double HexRingRadiusM(size_t count, double spacing_m);

/// The gather app's slots for `count` robots around `centre`: HexSlots,
/// with the centre moved (ClampIntoArena with the packing's radius added to
/// the body's) so that every slot keeps the margin from the walls.
std::vector<Position> GatherSlots(Position centre, size_t count, const GatherParams& params, ArenaSize arena,
                                  double body_radius_m);

// ---- circle ----------------------------------------------------------------

/// Where the circle app puts `count` robots.
struct CircleFormation {
  Position centre;
  double radius_m = 0;
};

/// The circle actually used: the radius is raised so neighbouring points
/// are at least 2 R + margin + kPlanSlackM apart, then lowered so the circle
/// keeps the margin from the walls; the centre (params, or the arena's
/// centre for a negative coordinate) is then moved inside the arena.
CircleFormation MakeCircleFormation(const CircleParams& params, size_t count, ArenaSize arena, double body_radius_m);

/// `count` points evenly spaced on MakeCircleFormation's circle, point k at
/// angle 2 pi k / count (point 0 at angle 0).
std::vector<Position> CircleTargets(const CircleParams& params, size_t count, ArenaSize arena, double body_radius_m);

// ---- leader_follow -------------------------------------------------------

/// The leader's path (a circle, driven counter-clockwise) and the angular
/// spacing of the line on it.
struct LeaderPath {
  Position centre;
  double radius_m = 0;
  double slot_angle_rad = 0;  ///< angle between consecutive robots of the line (chord = spacing)
};

/// The path for a swarm of `count` robots: around the arena centre, radius
/// path_radius_m lowered to keep the margin from the walls; the slot angle
/// is that of a chord of spacing_m, lowered to 2 pi / count if the line
/// would not fit on the circle.
LeaderPath MakeLeaderPath(const LeaderFollowParams& params, size_t count, ArenaSize arena, double body_radius_m);

/// How far the leader advances per maneuver, metres: speed x maneuver time,
/// but at most spacing - 2 R - margin - kPlanSlackM - kFilterGrowthM (and not
/// below 0), so a follower's next slot stays clear of where its predecessor
/// starts, for the apps' safety rule and the platform's safety filter alike,
/// and the whole line can move in one epoch.
double LeaderStepM(const LeaderFollowParams& params, double body_radius_m, double maneuver_s);

/// The angle of `position` seen from the path's centre, in (-pi, pi]; 0 at
/// the centre itself.
double PathAngleRad(const LeaderPath& path, Position position);

/// The point of the path at `angle_rad`.
Position PathPoint(const LeaderPath& path, double angle_rad);

/// The slots of `follower_count` followers behind a leader at
/// `leader_angle_rad`: slot k (k = 0, 1, ...) at leader_angle - (k + 1) x
/// slot_angle, i.e. the line trails the leader along its path.
std::vector<Position> FollowerSlots(const LeaderPath& path, double leader_angle_rad, size_t follower_count);

}  // namespace syrof::lab::apps
