#include "syrof/queries/query_error.h"

namespace syrof::queries {

const char* ToString(QueryError error) {
  switch (error) {
    case QueryError::kOk:
      return "Ok";
    case QueryError::kNoMembers:
      return "NoMembers";
    case QueryError::kTooManyMembers:
      return "TooManyMembers";
    case QueryError::kTooManyTargets:
      return "TooManyTargets";
    case QueryError::kIdOutOfRange:
      return "IdOutOfRange";
    case QueryError::kDuplicateId:
      return "DuplicateId";
    case QueryError::kNonFiniteCoordinate:
      return "NonFiniteCoordinate";
    case QueryError::kCoordinateOutOfRange:
      return "CoordinateOutOfRange";
    case QueryError::kOutputTooSmall:
      return "OutputTooSmall";
    case QueryError::kNullArgument:
      return "NullArgument";
    case QueryError::kWorkspaceTooSmall:
      return "WorkspaceTooSmall";
  }
  return "?";
}

}  // namespace syrof::queries
