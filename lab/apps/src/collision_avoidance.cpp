#include "syrof/lab/apps/collision_avoidance.h"

#include <algorithm>
#include <cmath>

namespace syrof::lab::apps {
namespace {

struct Vector {
  double x = 0;
  double y = 0;
};

Vector Difference(Position a, Position b) { return {a.x_m - b.x_m, a.y_m - b.y_m}; }
double Dot(Vector a, Vector b) { return a.x * b.x + a.y * b.y; }
double Cross(Vector a, Vector b) { return a.x * b.y - a.y * b.x; }
double Norm(Vector a) { return std::sqrt(Dot(a, a)); }

double PointSegmentDistanceM(Position point, const Segment& segment) {
  const Vector along = Difference(segment.end, segment.start);
  const Vector from_start = Difference(point, segment.start);
  const double length_squared = Dot(along, along);
  if (length_squared == 0.0) return Norm(from_start);
  const double t = std::clamp(Dot(from_start, along) / length_squared, 0.0, 1.0);
  return Norm({from_start.x - t * along.x, from_start.y - t * along.y});
}

// True when the segments cross at a point inside both (strict sign changes;
// touching and collinear cases are covered by the endpoint distances).
bool SegmentsCross(const Segment& a, const Segment& b) {
  const Vector along_a = Difference(a.end, a.start);
  const Vector along_b = Difference(b.end, b.start);
  const double side_b_start = Cross(along_a, Difference(b.start, a.start));
  const double side_b_end = Cross(along_a, Difference(b.end, a.start));
  const double side_a_start = Cross(along_b, Difference(a.start, b.start));
  const double side_a_end = Cross(along_b, Difference(a.end, b.start));
  return ((side_b_start < 0 && side_b_end > 0) || (side_b_start > 0 && side_b_end < 0)) &&
         ((side_a_start < 0 && side_a_end > 0) || (side_a_start > 0 && side_a_end < 0));
}

// The longest prefix of `segment` none of whose points comes closer than
// `clearance_m` to `obstacle`, or the whole segment if it moves away from
// the obstacle (separating). Along the ray start + s u the squared distance
// is |w|^2 + 2 s (u.w) + s^2 with w = start - obstacle: it first falls to
// clearance^2 at s = -(u.w) - sqrt((u.w)^2 - |w|^2 + clearance^2).
// How far a sliding segment leans away from the robot it slides around,
// as a fraction of its length.
constexpr double kSlideOutward = 0.1;

Segment LongestClearPrefix(const Segment& segment, Position obstacle, double clearance_m) {
  const double length_m = SegmentLengthM(segment);
  if (length_m == 0.0) return segment;
  const Vector along = Difference(segment.end, segment.start);
  const Vector unit{along.x / length_m, along.y / length_m};
  const Vector away = Difference(segment.start, obstacle);
  const double approach = Dot(unit, away);
  if (approach >= 0.0) return segment;
  const double excess = Dot(away, away) - clearance_m * clearance_m;
  if (excess <= 0.0) return Truncate(segment, 0.0);
  const double discriminant = approach * approach - excess;
  if (discriminant <= 0.0) return segment;
  return Truncate(segment, -approach - std::sqrt(discriminant));
}

}  // namespace

double SegmentLengthM(const Segment& segment) { return Norm(Difference(segment.end, segment.start)); }

double SegmentDistanceM(const Segment& a, const Segment& b) {
  if (SegmentsCross(a, b)) return 0.0;
  return std::min({PointSegmentDistanceM(a.start, b), PointSegmentDistanceM(a.end, b), PointSegmentDistanceM(b.start, a),
                   PointSegmentDistanceM(b.end, a)});
}

bool SegmentsSeparate(const Segment& a, const Segment& b) {
  // With unit directions u, v, lengths travelled s, t >= 0 and w = a.start -
  // b.start: |w + s u - t v|^2 = |w|^2 + 2 s (u.w) - 2 t (v.w) + s^2 + t^2 -
  // 2 s t (u.v) >= |w|^2 when u.w >= 0 and v.w <= 0, since s^2 + t^2 -
  // 2 s t (u.v) >= (s - t)^2. Only signs matter, so the directions need not
  // be normalized.
  const Vector between = Difference(a.start, b.start);
  return Dot(Difference(a.end, a.start), between) >= 0.0 && Dot(Difference(b.end, b.start), between) <= 0.0;
}

bool PairIsSafe(const Segment& a, const Segment& b, double clearance_m) {
  return SegmentsSeparate(a, b) || SegmentDistanceM(a, b) >= clearance_m;
}

Segment Truncate(const Segment& segment, double length_m) {
  const double current_m = SegmentLengthM(segment);
  if (current_m <= length_m) return segment;
  if (length_m <= 0.0) return {segment.start, segment.start};
  const double scale = length_m / current_m;
  return {segment.start,
          {segment.start.x_m + (segment.end.x_m - segment.start.x_m) * scale,
           segment.start.y_m + (segment.end.y_m - segment.start.y_m) * scale}};
}

void SlideAroundNeighbours(std::span<Segment> segments, double clearance_m, double zone_m) {
  for (size_t i = 0; i < segments.size(); ++i) {
    Segment& own = segments[i];
    for (size_t j = 0; j < segments.size(); ++j) {
      if (j == i) continue;
      const Position other = segments[j].start;
      const Vector away = Difference(own.start, other);
      const double distance_m = Norm(away);
      if (distance_m == 0.0 || distance_m >= clearance_m + zone_m) continue;
      const double length_m = SegmentLengthM(own);
      if (length_m == 0.0 || SegmentLengthM(LongestClearPrefix(own, other, clearance_m)) >= length_m) continue;
      const Vector normal{away.x / distance_m, away.y / distance_m};
      Vector move = Difference(own.end, own.start);
      const double approach = Dot(move, normal);
      if (approach < 0.0) move = {move.x - approach * normal.x, move.y - approach * normal.y};
      if (Norm(move) < 0.25 * length_m) {
        // Nearly head-on: the tangent that is to the left when facing the
        // other robot. Two robots meeting head-on both turn left and pass.
        move = {normal.y * 0.5 * length_m, -normal.x * 0.5 * length_m};
      }
      // Tilt outwards a little: a pure tangent separates only up to
      // rounding, and LimitSegments would stop a pair on that edge.
      move = {move.x + kSlideOutward * length_m * normal.x, move.y + kSlideOutward * length_m * normal.y};
      own.end = {own.start.x_m + move.x, own.start.y_m + move.y};
    }
  }
}

void LimitSegments(std::span<Segment> segments, double clearance_m) {
  for (size_t i = 0; i < segments.size(); ++i) {
    for (size_t j = i + 1; j < segments.size(); ++j) {
      if (PairIsSafe(segments[i], segments[j], clearance_m)) continue;
      // Option 1, both share what is left of the distance: each moving at
      // most (d - clearance) / 2 keeps every pair of points d - 2 (d -
      // clearance) / 2 = clearance apart.
      const double distance_m = Norm(Difference(segments[i].start, segments[j].start));
      const double share_m = std::max(0.0, (distance_m - clearance_m) / 2.0);
      Segment best_i = Truncate(segments[i], share_m);
      Segment best_j = Truncate(segments[j], share_m);
      double best_total_m = SegmentLengthM(best_i) + SegmentLengthM(best_j);
      // Options 2 and 3, one waits: lets a robot take the place another
      // leaves (a chain), which option 1 would freeze.
      const Segment only_i = LongestClearPrefix(segments[i], segments[j].start, clearance_m);
      if (SegmentLengthM(only_i) > best_total_m) {
        best_i = only_i;
        best_j = Truncate(segments[j], 0.0);
        best_total_m = SegmentLengthM(only_i);
      }
      const Segment only_j = LongestClearPrefix(segments[j], segments[i].start, clearance_m);
      if (SegmentLengthM(only_j) > best_total_m) {
        best_i = Truncate(segments[i], 0.0);
        best_j = only_j;
      }
      segments[i] = best_i;
      segments[j] = best_j;
    }
  }
}

}  // namespace syrof::lab::apps
