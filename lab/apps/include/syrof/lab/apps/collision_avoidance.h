// The built-in apps' collision-avoidance rule for one epoch (docs/apps.md,
// "Safety"). Every robot computes every member's straight segment from the
// same map, shortens them all with LimitSegments, and drives its own. After
// LimitSegments every pair of segments satisfies one of:
//   - clear: no point of one is closer than `clearance_m` to any point of
//     the other, so the pair keeps that distance whatever the timing along
//     the two segments;
//   - separating: neither robot moves towards the other's start (a . w >= 0
//     and b . w <= 0 with w from the second start to the first), so their
//     distance never drops below the current one, whatever the timing.
// Both hold for every prefix of the segments, so a robot that stops early
// (slow, AUTONOMOUS, crashed) keeps the pair safe too.
#pragma once

#include <span>

#include "syrof/lab/apps/formation.h"

namespace syrof::lab::apps {

/// A straight move from `start` to `end`, metres.
struct Segment {
  Position start;
  Position end;
};

/// Length of `segment`, metres.
double SegmentLengthM(const Segment& segment);

/// The smallest distance between a point of `a` and a point of `b` (0 if
/// they cross), metres.
double SegmentDistanceM(const Segment& a, const Segment& b);

/// True when neither segment moves towards the other's start (see above).
bool SegmentsSeparate(const Segment& a, const Segment& b);

/// True when the pair is clear at `clearance_m` or separating.
bool PairIsSafe(const Segment& a, const Segment& b, double clearance_m);

/// `segment` with its end moved towards its start so it is at most
/// `length_m` long (length_m >= 0); unchanged if already shorter.
Segment Truncate(const Segment& segment, double length_m);

/// Liveness, not safety: a segment whose straight path would come closer
/// than `clearance_m` to the start of a robot that is already within
/// `clearance_m + zone_m` is turned onto the tangent of that robot (its
/// approaching component removed; a nearly head-on one instead goes to its
/// own left at half its length) and tilted slightly away from it, so robots
/// slide around each other rather than stop nose to nose. Each segment is
/// turned against the nearby robots in index order; starts never change.
/// LimitSegments must follow: a turned segment is not yet safe.
void SlideAroundNeighbours(std::span<Segment> segments, double clearance_m, double zone_m);

/// Shortens segments (keeping every start and direction) until every pair
/// is safe at `clearance_m`. Pairs are visited once, in index order (0,1),
/// (0,2), ..., and an unsafe pair (i, j) is fixed by the choice that leaves
/// the most total length, ties in this order:
///   1. both shortened to (d - clearance) / 2, d the distance of the starts;
///   2. j stops, i goes as far as it stays clear of j's start;
///   3. i stops, j goes as far as it stays clear of i's start.
/// Shortening never makes a safe pair unsafe, so one pass suffices. The
/// result depends only on the input (same bits on the same build). O(n^2).
void LimitSegments(std::span<Segment> segments, double clearance_m);

}  // namespace syrof::lab::apps
