#include "syrof/lab/sim/recording_app.h"

#include "syrof/base/split_mix64.h"
#include "syrof/app/state_digest.h"

namespace syrof::lab::sim {
namespace {

uint64_t Mix(uint64_t hash, uint64_t value) { return base::SplitMix64Hash(hash ^ value); }

}  // namespace

uint64_t MapFingerprint(const syrof_ldmap& ldmap) {
  uint64_t hash = Mix(0x4c444d4150ULL, ldmap.epoch);
  hash = Mix(hash, ldmap.mode);
  hash = Mix(hash, ldmap.member_count);
  for (uint16_t i = 0; i < ldmap.member_count; ++i) {
    const syrof_member_state& member = ldmap.members[i];
    hash = Mix(hash, member.id);
    hash = Mix(hash, static_cast<uint16_t>(member.x_mm) | (uint64_t{static_cast<uint16_t>(member.y_mm)} << 16) |
                         (uint64_t{static_cast<uint16_t>(member.heading_mrad)} << 32));
    hash = Mix(hash, static_cast<uint16_t>(member.vx_mm_s) | (uint64_t{static_cast<uint16_t>(member.vy_mm_s)} << 16) |
                         (uint64_t{member.payload_length} << 32));
    uint64_t payload = 0;
    for (size_t b = 0; b < 8; ++b) payload |= uint64_t{member.payload[b]} << (8 * b);
    hash = Mix(hash, payload);
    hash = Mix(hash, member.payload[8]);
  }
  return hash;
}

void RecordingApp::AddCall(uint8_t callback, const syrof_ldmap* ldmap, uint8_t global_state, uint32_t clock_ms) {
  history_.AddValue(callback);
  history_.AddValue(global_state);
  history_.AddValue(clock_ms);
  if (ldmap == nullptr) return;
  history_.AddValue(ldmap->epoch);
  history_.AddValue(ldmap->mode);
  history_.AddValue(ldmap->self_id);
  history_.AddValue(ldmap->member_count);
  for (uint16_t i = 0; i < ldmap->member_count; ++i) app::AddToDigest(history_, ldmap->members[i]);
}

}  // namespace syrof::lab::sim
