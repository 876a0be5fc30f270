// ConvexHull and ShortestEnclosingCircle: the queries that need geometric
// predicates, which come from the CGAL kernel (cgal_kernel.h). This is the
// only translation unit that includes CGAL.
//
// CGAL's own algorithms (convex_hull_2 and its variants, Min_circle_2)
// allocate on every call (a std::vector stack, a std::list of points), which
// core code must not do after start-up. So the algorithms here are short
// allocation-free versions working in the caller's Workspace, and every
// decision in them is a CGAL kernel predicate evaluated exactly.

// clang-format off
#include "cgal_kernel.h"  // first: it configures CGAL before any other header
// clang-format on

#include <algorithm>
#include <array>
#include <cstdint>
#include <span>
#include <utility>

#include "canonical.h"
#include "exact_rounding.h"
#include "int128.h"
#include "syrof/base/check.h"
#include "syrof/queries/swarm_queries.h"
#include "workspace_storage.h"

#if defined(SYROF_QUERIES_CGAL_OWN_FAILURE_HANDLERS)
// CGAL's failure handlers (declared in CGAL/assertions.h), for builds without
// exceptions (cgal_config.h, item 3). With CGAL's checks compiled out only
// CGAL_error() could reach them, which the predicates used here never call.
namespace CGAL {
void assertion_fail(const char* expression, const char* file, int line, const char* /*message*/) {
  syrof::base::check_failed(expression, file, line);
}
void precondition_fail(const char* expression, const char* file, int line, const char* /*message*/) {
  syrof::base::check_failed(expression, file, line);
}
void postcondition_fail(const char* expression, const char* file, int line, const char* /*message*/) {
  syrof::base::check_failed(expression, file, line);
}
void warning_fail(const char* /*expression*/, const char* /*file*/, int /*line*/, const char* /*message*/) {}
}  // namespace CGAL
#endif

namespace syrof::queries {
namespace {

using internal::CanonicalMember;
using internal::Int128;
using internal::Kernel;
using internal::WorkspaceStorage;
using Point2 = Kernel::Point_2;

Point2 ToPoint2(const CanonicalMember& member) { return Point2(Int128(member.x_mm), Int128(member.y_mm)); }

bool SamePosition(const CanonicalMember& a, const CanonicalMember& b) { return a.x_mm == b.x_mm && a.y_mm == b.y_mm; }

// --- ConvexHull ---------------------------------------------------------

// A member as one integer whose order is (x, y, id): offset-binary
// coordinates (x + 32768 keeps int16 order as unsigned) above the id.
uint64_t HullKey(const CanonicalMember& member) {
  const auto x = static_cast<uint16_t>(static_cast<uint16_t>(member.x_mm) ^ 0x8000u);
  const auto y = static_cast<uint16_t>(static_cast<uint16_t>(member.y_mm) ^ 0x8000u);
  return (uint64_t{x} << 32) | (uint64_t{y} << 16) | member.id;
}

CanonicalMember FromHullKey(uint64_t key) {
  return CanonicalMember{static_cast<int16_t>(static_cast<uint16_t>((key >> 32) ^ 0x8000u)),
                         static_cast<int16_t>(static_cast<uint16_t>((key >> 16) ^ 0x8000u)),
                         static_cast<uint16_t>(key & 0xFFFFu)};
}

// Andrew's monotone chain over the distinct positions (sorted by x, then y),
// keeping only strict left turns, so collinear points on an edge drop out.
// Writes chain indices into storage.hull_chain and returns their count:
// the corners counter-clockwise from the first (smallest x, then y).
uint16_t MonotoneChain(WorkspaceStorage& storage, uint16_t positions) {
  const auto position = [&storage](uint16_t index) {
    return ToPoint2(FromHullKey(storage.hull_keys[storage.hull_position_start[index]]));
  };
  if (positions == 1) {
    storage.hull_chain[0] = 0;
    return 1;
  }
  const Kernel::Left_turn_2 left_turn = Kernel().left_turn_2_object();
  auto& chain = storage.hull_chain;
  size_t size = 0;
  const auto keep_left_turns = [&](uint16_t index, size_t floor) {
    const Point2 next = position(index);
    while (size >= floor + 2 && !left_turn(position(chain[size - 2]), position(chain[size - 1]), next)) {
      --size;
    }
    chain[size++] = index;
  };
  for (uint16_t index = 0; index < positions; ++index) keep_left_turns(index, 0);  // lower hull
  const size_t lower_size = size;
  for (int index = positions - 2; index >= 0; --index) {  // upper hull, back to the start
    keep_left_turns(static_cast<uint16_t>(index), lower_size - 1);
  }
  // The last entry is the first corner again.
  return static_cast<uint16_t>(size - 1);
}

// --- ShortestEnclosingCircle ------------------------------------------------

// The circle under construction, as the 1 to 3 members on its boundary.
struct Support {
  uint8_t count = 0;
  std::array<CanonicalMember, 3> members{};
};

// Whether `point` lies on or inside the support's circle (exact).
bool Holds(const Support& support, const CanonicalMember& point) {
  switch (support.count) {
    case 1:
      return SamePosition(support.members[0], point);
    case 2:
      return Kernel().side_of_bounded_circle_2_object()(ToPoint2(support.members[0]), ToPoint2(support.members[1]),
                                                        ToPoint2(point)) != CGAL::ON_UNBOUNDED_SIDE;
    default:
      return Kernel().side_of_bounded_circle_2_object()(ToPoint2(support.members[0]), ToPoint2(support.members[1]),
                                                        ToPoint2(support.members[2]),
                                                        ToPoint2(point)) != CGAL::ON_UNBOUNDED_SIDE;
  }
}

// A fixed pseudo-random order for the randomized incremental construction
// (expected linear time whatever order the ids have, e.g. ids assigned
// around a formation). Same constants on every robot: 64-bit LCG (Knuth's
// MMIX), high half, bounded by multiply-shift.
class FixedShuffle {
 public:
  uint32_t Below(uint32_t bound) {
    state_ = state_ * 6364136223846793005ull + 1442695040888963407ull;
    return static_cast<uint32_t>((uint64_t{static_cast<uint32_t>(state_ >> 32)} * bound) >> 32);
  }

 private:
  uint64_t state_ = 0x5359524F46515259ull;  // "SYROFQRY"
};

// Welzl's construction, iterative (no recursion, so bounded stack): each
// point found outside the current circle must lie on the boundary of the
// smallest circle of the points seen so far. Coincident points need no
// special case: the tests are on the closed disc.
Support SmallestCircleSupport(std::span<const CanonicalMember> points) {
  Support circle{1, {points[0]}};
  for (size_t i = 1; i < points.size(); ++i) {
    if (Holds(circle, points[i])) continue;
    circle = Support{1, {points[i]}};
    for (size_t j = 0; j < i; ++j) {
      if (Holds(circle, points[j])) continue;
      circle = Support{2, {points[i], points[j]}};
      for (size_t k = 0; k < j; ++k) {
        if (Holds(circle, points[k])) continue;
        circle = Support{3, {points[i], points[j], points[k]}};
        // Points i and j are on the boundary of the smallest circle holding
        // points 0..j and i, so k cannot be collinear with them.
        SYROF_CHECK(Kernel().orientation_2_object()(ToPoint2(points[i]), ToPoint2(points[j]), ToPoint2(points[k])) !=
                    CGAL::COLLINEAR);
      }
    }
  }
  return circle;
}

// The exact circle through the support, rounded once to floats in metres.
Circle ToCircle(const Support& support) {
  Circle circle;
  const CanonicalMember& a = support.members[0];
  if (support.count == 1) {
    circle.centre_x_m = internal::NearestFloatOfQuotient(Int128(a.x_mm), Int128(1000));
    circle.centre_y_m = internal::NearestFloatOfQuotient(Int128(a.y_mm), Int128(1000));
    circle.radius_m = 0.0f;
    return circle;
  }
  const CanonicalMember& b = support.members[1];
  const int64_t bx = int64_t{b.x_mm} - a.x_mm;
  const int64_t by = int64_t{b.y_mm} - a.y_mm;
  if (support.count == 2) {
    // Centre (a + b) / 2; radius |b - a| / 2.
    circle.centre_x_m = internal::NearestFloatOfQuotient(Int128(int64_t{a.x_mm} + b.x_mm), Int128(2000));
    circle.centre_y_m = internal::NearestFloatOfQuotient(Int128(int64_t{a.y_mm} + b.y_mm), Int128(2000));
    circle.radius_m = internal::NearestFloatOfSqrtQuotient(Int128(bx * bx + by * by), Int128(4'000'000));
    return circle;
  }
  // Circumcentre relative to a: (ux, uy) / d with
  //   d  = 2 (bx cy - by cx)            |d|  < 2^35
  //   ux = cy |b|^2 - by |c|^2          |ux| < 2^50
  //   uy = bx |c|^2 - cx |b|^2          |uy| < 2^50
  // (coordinates differ by less than 2^16, squared lengths are below 2^33).
  const CanonicalMember& c = support.members[2];
  const int64_t cx = int64_t{c.x_mm} - a.x_mm;
  const int64_t cy = int64_t{c.y_mm} - a.y_mm;
  int64_t d = 2 * (bx * cy - by * cx);
  SYROF_CHECK(d != 0);
  const int64_t b2 = bx * bx + by * by;
  const int64_t c2 = cx * cx + cy * cy;
  int64_t ux = cy * b2 - by * c2;
  int64_t uy = bx * c2 - cx * b2;
  // Centre in metres: (a d + u) / (1000 d); radius: sqrt(ux^2 + uy^2) / |1000 d|.
  const Int128 radius_squared_numerator = Int128::Product(ux, ux) + Int128::Product(uy, uy);
  const Int128 radius_squared_denominator = Int128::Product(1000 * d, 1000 * d);
  if (d < 0) {
    d = -d;
    ux = -ux;
    uy = -uy;
  }
  circle.centre_x_m = internal::NearestFloatOfQuotient(Int128(a.x_mm * d + ux), Int128(1000 * d));
  circle.centre_y_m = internal::NearestFloatOfQuotient(Int128(a.y_mm * d + uy), Int128(1000 * d));
  circle.radius_m = internal::NearestFloatOfSqrtQuotient(radius_squared_numerator, radius_squared_denominator);
  return circle;
}

}  // namespace

base::Result<uint16_t, QueryError> ConvexHull(std::span<const Member> members, Workspace& workspace,
                                              std::span<uint16_t> hull_ids) {
  WorkspaceStorage& storage = internal::WorkspaceAccess::Storage(workspace);
  const base::Result<uint16_t, QueryError> count = internal::CanonicalMembers(members, storage);
  if (!count.ok()) return count.error();
  if (hull_ids.size() < members.size()) return QueryError::kOutputTooSmall;
  const uint16_t n = count.value();
  if (n == 0) return uint16_t{0};

  for (uint16_t index = 0; index < n; ++index) storage.hull_keys[index] = HullKey(storage.members[index]);
  std::sort(storage.hull_keys.begin(), storage.hull_keys.begin() + n);
  // Runs of equal positions: hull_position_start[p] is the first key of
  // position p, and one past the last position holds n.
  uint16_t positions = 0;
  for (uint16_t index = 0; index < n; ++index) {
    if (index == 0 || (storage.hull_keys[index] >> 16) != (storage.hull_keys[index - 1] >> 16)) {
      storage.hull_position_start[positions++] = index;
    }
  }
  storage.hull_position_start[positions] = n;

  const uint16_t corners = MonotoneChain(storage, positions);
  uint16_t written = 0;
  for (uint16_t corner = 0; corner < corners; ++corner) {
    const uint16_t position = storage.hull_chain[corner];
    for (uint16_t key = storage.hull_position_start[position]; key < storage.hull_position_start[position + 1]; ++key) {
      hull_ids[written++] = static_cast<uint16_t>(storage.hull_keys[key] & 0xFFFFu);
    }
  }
  return written;
}

base::Result<Circle, QueryError> ShortestEnclosingCircle(std::span<const Member> members, Workspace& workspace) {
  WorkspaceStorage& storage = internal::WorkspaceAccess::Storage(workspace);
  const base::Result<uint16_t, QueryError> count = internal::CanonicalMembers(members, storage);
  if (!count.ok()) return count.error();
  const uint16_t n = count.value();
  if (n == 0) return QueryError::kNoMembers;

  // Inside-out Fisher-Yates from id order into the construction's order.
  FixedShuffle shuffle;
  for (uint16_t index = 0; index < n; ++index) {
    const uint32_t other = shuffle.Below(uint32_t{index} + 1);
    if (other != index) storage.circle_order[index] = storage.circle_order[other];
    storage.circle_order[other] = storage.members[index];
  }
  const Support support = SmallestCircleSupport(std::span<const CanonicalMember>(storage.circle_order.data(), n));

  Circle circle = ToCircle(support);
  circle.support_count = support.count;
  // Each support position stands for the smallest id there: the first
  // member at that position in id order.
  for (uint8_t index = 0; index < support.count; ++index) {
    for (uint16_t member = 0; member < n; ++member) {
      if (SamePosition(storage.members[member], support.members[index])) {
        circle.support_ids[index] = storage.members[member].id;
        break;
      }
    }
  }
  // Increasing order (unused entries are kNoRobot, the largest value).
  auto& ids = circle.support_ids;
  if (ids[0] > ids[1]) std::swap(ids[0], ids[1]);
  if (ids[1] > ids[2]) std::swap(ids[1], ids[2]);
  if (ids[0] > ids[1]) std::swap(ids[0], ids[1]);
  return circle;
}

}  // namespace syrof::queries
