#include "syrof/firmware/robot/report_lines.h"

#include <cstdio>

namespace syrof::firmware::robot {

size_t FormatRoundLine(uint16_t robot, int64_t now_ns, const sync::SyncState& state, bool estimate_valid, float x_m,
                       float y_m, uint32_t lost, std::span<char> out) {
  const int length = std::snprintf(
      out.data(), out.size(), "R t_ms=%lu robot=%u epoch=%u mode=%u phase=%u member=%u valid=%u x_mm=%ld y_mm=%ld lost=%lu\n",
      static_cast<unsigned long>(now_ns / 1'000'000), static_cast<unsigned>(robot), static_cast<unsigned>(state.epoch),
      static_cast<unsigned>(state.epoch_mode), static_cast<unsigned>(state.phase),
      state.status == sync::Status::kMember ? 1u : 0u, estimate_valid ? 1u : 0u, static_cast<long>(x_m * 1000.0f),
      static_cast<long>(y_m * 1000.0f), static_cast<unsigned long>(lost));
  return length > 0 && static_cast<size_t>(length) < out.size() ? static_cast<size_t>(length) : 0;
}

size_t FormatEpochLine(uint16_t robot, int64_t now_ns, const sync::LDMap& ldmap, bool active, std::span<char> out) {
  size_t used = 0;
  auto append = [&](int written) {
    if (written < 0 || used + static_cast<size_t>(written) >= out.size()) return false;
    used += static_cast<size_t>(written);
    return true;
  };
  if (!append(std::snprintf(out.data(), out.size(), "E t_ms=%lu robot=%u epoch=%u mode=%u active=%u members=",
                            static_cast<unsigned long>(now_ns / 1'000'000), static_cast<unsigned>(robot),
                            static_cast<unsigned>(ldmap.epoch), static_cast<unsigned>(ldmap.mode),
                            active ? 1u : 0u))) {
    return 0;
  }
  // Each member: id:x:y:heading:vx:vy:payload (hex, may be empty), ';' between.
  bool first = true;
  for (const uint16_t id : ldmap.members) {
    const wire::Snapshot& snapshot = ldmap.snapshots[id];
    if (!append(std::snprintf(out.data() + used, out.size() - used, "%s%u:%d:%d:%d:%d:%d:", first ? "" : ";",
                              static_cast<unsigned>(id), snapshot.x_mm, snapshot.y_mm, snapshot.heading_mrad,
                              snapshot.vx_mm_s, snapshot.vy_mm_s))) {
      return 0;
    }
    for (const uint8_t byte : snapshot.payload_bytes()) {
      if (!append(std::snprintf(out.data() + used, out.size() - used, "%02x", byte))) return 0;
    }
    first = false;
  }
  if (!append(std::snprintf(out.data() + used, out.size() - used, "\n"))) return 0;
  return used;
}

}  // namespace syrof::firmware::robot
