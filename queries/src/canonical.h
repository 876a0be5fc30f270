// Input checks and the canonical order every query starts from.
#pragma once

#include <cstdint>
#include <span>

#include "syrof/base/result.h"
#include "syrof/queries/query_error.h"
#include "syrof/queries/types.h"
#include "workspace_storage.h"

namespace syrof::queries::internal {

/// Checks a member list without scratch memory. Reports, in this order:
/// kTooManyMembers, kIdOutOfRange (any id), kDuplicateId (any repeat), so
/// the error does not depend on the members' order.
QueryError ValidateMembers(std::span<const Member> members);

/// Validates like ValidateMembers and writes the members to
/// storage.members in increasing id order; returns their number.
base::Result<uint16_t, QueryError> CanonicalMembers(std::span<const Member> members, WorkspaceStorage& storage);

}  // namespace syrof::queries::internal
