#include "syrof/app/app.h"

#include <cstddef>

// The ABI's layouts, as libraries built before `kind` was added read them:
// the member's kind took its padding byte, the info's came after its end.
static_assert(sizeof(syrof_member_state) == 24 && offsetof(syrof_member_state, payload) == 14 &&
                  offsetof(syrof_member_state, kind) == 23,
              "syrof_member_state's layout is the ABI's");
static_assert(offsetof(syrof_app_info, max_speed_mps) == 28 && offsetof(syrof_app_info, kind) == 32,
              "syrof_app_info's layout is the ABI's");

namespace syrof::app {

const syrof_member_state* FindMember(const syrof_ldmap& ldmap, uint16_t id) {
  size_t low = 0;
  size_t high = ldmap.member_count;
  while (low < high) {
    const size_t middle = low + (high - low) / 2;
    const uint16_t middle_id = ldmap.members[middle].id;
    if (middle_id == id) return &ldmap.members[middle];
    if (middle_id < id) {
      low = middle + 1;
    } else {
      high = middle;
    }
  }
  return nullptr;
}

syrof_app_status FindParameter(std::span<const Parameter> params, std::string_view name, double& value,
                               syrof_app_status missing) {
  for (const Parameter& param : params) {
    if (param.name == name) {
      value = param.value;
      return SYROF_APP_OK;
    }
  }
  return missing;
}

syrof_app_status Platform::AppParameter(std::string_view /*name*/, double& /*value*/) {
  return SYROF_APP_NO_SUCH_PARAMETER;
}

syrof_app_status Platform::AppInput(std::string_view /*name*/, double& /*value*/) { return SYROF_APP_NO_SUCH_INPUT; }

}  // namespace syrof::app

extern "C" size_t syrofMembersForQueries(const syrof_ldmap* ldmap, syrof_queries_member* out) {
  if (ldmap == nullptr || out == nullptr) return 0;
  for (size_t i = 0; i < ldmap->member_count; ++i) {
    out[i].id = ldmap->members[i].id;
    out[i].x_mm = ldmap->members[i].x_mm;
    out[i].y_mm = ldmap->members[i].y_mm;
  }
  return ldmap->member_count;
}
