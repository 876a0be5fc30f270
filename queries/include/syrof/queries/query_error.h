// Why a query could not answer.
#pragma once

#include <cstdint>

namespace syrof::queries {

/// Errors of the queries. Every query validates its whole input first and
/// reports the first failing check in this order: sizes, coordinates, ids
/// out of range, duplicate ids, output space. So the error, like the answer,
/// does not depend on the order of the members. The values are the C API's
/// status codes (syrof/queries/queries.h).
enum class [[nodiscard]] QueryError : uint8_t{
    kOk = 0,
    kNoMembers = 1,             // the query needs at least one member (Leader, ShortestEnclosingCircle)
    kTooManyMembers = 2,        // more than kMaxMembers members
    kTooManyTargets = 3,        // more than kMaxTargets targets
    kIdOutOfRange = 4,          // a member id >= kMaxMembers
    kDuplicateId = 5,           // two members with the same id
    kNonFiniteCoordinate = 6,   // a coordinate in metres is NaN or infinite
    kCoordinateOutOfRange = 7,  // a coordinate in metres rounds outside -32768 .. 32767 mm
    kOutputTooSmall = 8,        // an output buffer is shorter than the query requires
    kNullArgument = 9,          // C API: a required pointer is NULL
    kWorkspaceTooSmall = 10,    // C API: workspace memory too small or misaligned
};

/// The enumerator's name without the k ("DuplicateId"); "?" for an unknown value.
const char* ToString(QueryError error);

}  // namespace syrof::queries
