#include "syrof/app/app.h"

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
