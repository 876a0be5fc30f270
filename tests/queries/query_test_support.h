// Helpers shared by the queries' tests: a seeded generator that gives the
// same numbers on every platform, random member sets, exact reference
// predicates written independently of the library's.
#pragma once

#include <algorithm>
#include <cstdint>
#include <numeric>
#include <vector>

#include "syrof/base/split_mix64.h"
#include "syrof/queries/types.h"

namespace syrof::queries::testing {

/// Seeded, and the same sequence on the host and the Cortex-M4.
using Rng = base::SplitMix64;

template <typename T>
void Shuffle(std::vector<T>& values, Rng& rng) {
  for (size_t index = values.size(); index > 1; --index) {
    std::swap(values[index - 1], values[rng.Below(static_cast<uint32_t>(index))]);
  }
}

/// `count` members with distinct random ids below `id_limit` (at most
/// kMaxMembers) and coordinates in [-extent_mm, extent_mm], in random order.
inline std::vector<Member> RandomMembers(Rng& rng, size_t count, int32_t extent_mm, uint16_t id_limit = kMaxMembers) {
  std::vector<uint16_t> ids(id_limit);
  std::iota(ids.begin(), ids.end(), uint16_t{0});
  Shuffle(ids, rng);
  std::vector<Member> members;
  for (size_t index = 0; index < count; ++index) {
    members.push_back(Member{ids[index], Point{static_cast<int16_t>(rng.Between(-extent_mm, extent_mm)),
                                               static_cast<int16_t>(rng.Between(-extent_mm, extent_mm))}});
  }
  return members;
}

inline std::vector<Point> RandomPoints(Rng& rng, size_t count, int32_t extent_mm) {
  std::vector<Point> points;
  for (size_t index = 0; index < count; ++index) {
    points.push_back(Point{static_cast<int16_t>(rng.Between(-extent_mm, extent_mm)),
                           static_cast<int16_t>(rng.Between(-extent_mm, extent_mm))});
  }
  return points;
}

/// Sign of the cross product (b - a) x (c - a): exact in int64 for int16 input.
inline int Orientation(Point a, Point b, Point c) {
  const int64_t value =
      (int64_t{b.x_mm} - a.x_mm) * (int64_t{c.y_mm} - a.y_mm) - (int64_t{b.y_mm} - a.y_mm) * (int64_t{c.x_mm} - a.x_mm);
  return value > 0 ? 1 : (value < 0 ? -1 : 0);
}

inline uint64_t SquaredDistance(Point a, Point b) {
  const int64_t dx = int64_t{a.x_mm} - b.x_mm;
  const int64_t dy = int64_t{a.y_mm} - b.y_mm;
  return static_cast<uint64_t>(dx * dx + dy * dy);
}

/// floor(sqrt(value)) by bisection: deliberately unlike the library's.
inline uint64_t ReferenceSqrt(uint64_t value) {
  uint64_t low = 0;
  uint64_t high = uint64_t{1} << 32;  // sqrt(2^64) bound, exclusive
  while (high - low > 1) {
    const uint64_t middle = low + (high - low) / 2;
    if (middle * middle <= value) {
      low = middle;
    } else {
      high = middle;
    }
  }
  return low;
}

/// The matching's distance unit: floor(distance * 2^15) for a squared distance.
inline uint64_t ReferenceFixedDistance(uint64_t squared_mm2) { return ReferenceSqrt(squared_mm2 << 30); }

inline std::vector<Point> Positions(const std::vector<Member>& members) {
  std::vector<Point> points;
  for (const Member& member : members) points.push_back(member.position);
  return points;
}

}  // namespace syrof::queries::testing
