// The queries that need no geometry, the workspace, and metre conversions.
#include "syrof/queries/swarm_queries.h"

#include <cmath>
#include <cstdint>
#include <span>

#include "canonical.h"
#include "exact_rounding.h"
#include "int128.h"
#include "workspace_storage.h"

namespace syrof::queries {
namespace {

// Metres to millimetres with the beacon encoder's rounding, or an error.
base::Result<int16_t, QueryError> MillimetresFromMetres(float metres) {
  if (!std::isfinite(metres)) return QueryError::kNonFiniteCoordinate;
  const float scaled = metres * 1000.0f;  // may overflow to infinity: out of range below
  if (!(scaled > -40000.0f && scaled < 40000.0f)) return QueryError::kCoordinateOutOfRange;
  // Round half away from zero without libm: the fraction of a float below
  // 2^15 in magnitude is exact.
  auto whole = static_cast<int32_t>(scaled);  // toward zero
  const float fraction = scaled - static_cast<float>(whole);
  if (fraction >= 0.5f) ++whole;
  if (fraction <= -0.5f) --whole;
  if (whole < INT16_MIN || whole > INT16_MAX) return QueryError::kCoordinateOutOfRange;
  return static_cast<int16_t>(whole);
}

}  // namespace

Workspace::Workspace() { internal::WorkspaceAccess::Construct(*this); }

base::Result<uint16_t, QueryError> NumberOfMembers(std::span<const Member> members) {
  if (const QueryError error = internal::ValidateMembers(members); error != QueryError::kOk) return error;
  return static_cast<uint16_t>(members.size());
}

base::Result<uint16_t, QueryError> Leader(std::span<const Member> members) {
  if (const QueryError error = internal::ValidateMembers(members); error != QueryError::kOk) return error;
  if (members.empty()) return QueryError::kNoMembers;
  uint16_t leader = members[0].id;
  for (const Member& member : members) leader = member.id < leader ? member.id : leader;
  return leader;
}

base::Result<Point, QueryError> PointFromMetres(float x_m, float y_m) {
  const base::Result<int16_t, QueryError> x = MillimetresFromMetres(x_m);
  const base::Result<int16_t, QueryError> y = MillimetresFromMetres(y_m);
  // A non-finite coordinate outranks an out-of-range one, whichever axis.
  if (x.error() == QueryError::kNonFiniteCoordinate || y.error() == QueryError::kNonFiniteCoordinate) {
    return QueryError::kNonFiniteCoordinate;
  }
  if (!x.ok()) return x.error();
  if (!y.ok()) return y.error();
  return Point{x.value(), y.value()};
}

float ToMetres(int16_t millimetres) {
  return internal::NearestFloatOfQuotient(internal::Int128(millimetres), internal::Int128(1000));
}

}  // namespace syrof::queries
