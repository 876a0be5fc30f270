// The queries an app asks about the swarm (paper, section "Virtual Machine"):
// NumberOfMembers, Leader, ShortestEnclosingCircle, ConvexHull and
// MinWeightedMatching. This is the C++ API; student apps call the same
// queries through the plain C API in syrof/queries/queries.h.
//
// Every robot must get the same answer from the same map, so each query:
//   - depends only on the set of (id, position) pairs, never on their order
//     in the span (members are put in id order first);
//   - decides with exact integer arithmetic on millimetre coordinates (no
//     floating point in any comparison), so no two robots can disagree
//     through rounding, and the Cortex-M4's soft float gives the host's bits;
//   - breaks ties by robot id, as each query states;
//   - never allocates and runs in time bounded by the input size.
// Bad input gives an error (QueryError), never a crash. docs/queries.md has
// the definitions, the exactness argument and the complexity of each query.
#pragma once

#include <cstdint>
#include <span>

#include "syrof/base/result.h"
#include "syrof/queries/query_error.h"
#include "syrof/queries/types.h"
#include "syrof/queries/workspace.h"

namespace syrof::queries {

/// The number of members. Errors: kTooManyMembers, kIdOutOfRange,
/// kDuplicateId (a map with a repeated id has no defined member count).
base::Result<uint16_t, QueryError> NumberOfMembers(std::span<const Member> members);

/// The leader: the member with the smallest id. Errors: kNoMembers, and
/// those of NumberOfMembers.
base::Result<uint16_t, QueryError> Leader(std::span<const Member> members);

/// The smallest circle that holds every member (on or inside it). One
/// member, or all at one position, gives radius 0. Errors: kNoMembers, and
/// those of NumberOfMembers. Expected O(n) time (randomized incremental
/// construction over a fixed pseudo-random order), O(n^3) worst case.
base::Result<Circle, QueryError> ShortestEnclosingCircle(std::span<const Member> members, Workspace& workspace);

/// The members at the corners of the convex hull, written to `hull_ids`;
/// returns how many. Order: counter-clockwise, starting at the corner with
/// the smallest x (then smallest y). Only corners count: members inside the
/// hull or in the interior of an edge are left out. Members sharing a
/// corner's position are all listed there, in increasing id order. Empty
/// input gives 0; all members at one position give all of them; collinear
/// members give the two ends. `hull_ids` must hold members.size() ids
/// (kOutputTooSmall otherwise, whatever the hull's size). O(n log n).
base::Result<uint16_t, QueryError> ConvexHull(std::span<const Member> members, Workspace& workspace,
                                              std::span<uint16_t> hull_ids);

/// Assigns robots to target points, one robot per target at most:
///   1. as many pairs as possible, min(robots, targets): with at least as
///      many targets as robots every robot gets a target and the rest of the
///      targets stay free; with fewer targets every target gets a robot and
///      the robots left over get kNoTarget;
///   2. among those, the longest distance any robot travels is as small as
///      possible (bottleneck), compared exactly as squared integer mm;
///   3. among those, the total travelled distance is smallest, each distance
///      measured in units of 2^-15 mm rounded down (an exact integer sum);
///   4. remaining ties: a fixed deterministic rule (docs/queries.md).
/// `by_robot` receives one Assignment per member in increasing id order
/// (size >= members.size()); `robot_of_target[j]` the robot id sent to
/// target j or kNoRobot (size >= targets.size()). Errors: kTooManyTargets,
/// kOutputTooSmall, and those of NumberOfMembers. O(n^2 m) time for
/// n = min and m = max of the two counts.
base::Result<MatchingSummary, QueryError> MinWeightedMatching(std::span<const Member> members,
                                                              std::span<const Point> targets, Workspace& workspace,
                                                              std::span<Assignment> by_robot,
                                                              std::span<uint16_t> robot_of_target);

/// A position in metres to millimetres, each coordinate rounded to nearest
/// (ties away from zero) after multiplying by 1000 in float, the beacon
/// encoder's rule (syrof::wire::ToMillimetres). Errors: kNonFiniteCoordinate
/// (NaN, infinity), kCoordinateOutOfRange (outside -32768 .. 32767 mm; the
/// encoder would saturate, which would move the point).
base::Result<Point, QueryError> PointFromMetres(float x_m, float y_m);

/// Millimetres to metres (the float nearest to millimetres / 1000).
float ToMetres(int16_t millimetres);

}  // namespace syrof::queries
