// The app ABI's structs into a base::StateDigest field by field: they have
// padding (a byte after a syrof_member_state, three after a command's kind),
// which equal values need not share, since a struct copied off the stack
// carries whatever the stack held.
#pragma once

#include "syrof/app.h"
#include "syrof/base/state_digest.h"

namespace syrof::app {

inline void AddToDigest(base::StateDigest& digest, const syrof_car_command& command) {
  digest.AddValue(command.kind);
  digest.AddValue(command.x_m);
  digest.AddValue(command.y_m);
  digest.AddValue(command.speed_mps);
  digest.AddValue(command.vx_mps);
  digest.AddValue(command.vy_mps);
  digest.AddValue(command.heading_rad);
}

inline void AddToDigest(base::StateDigest& digest, const syrof_member_state& member) {
  digest.AddValue(member.id);
  digest.AddValue(member.x_mm);
  digest.AddValue(member.y_mm);
  digest.AddValue(member.heading_mrad);
  digest.AddValue(member.vx_mm_s);
  digest.AddValue(member.vy_mm_s);
  digest.AddValue(member.phase);
  digest.AddValue(member.payload_length);
  digest.AddValue(member.payload);
}

}  // namespace syrof::app
