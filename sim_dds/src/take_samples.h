// Takes every sample a Cyclone reader holds, with loans: one helper for the
// robot and the world processes. Internal to sim_dds.
#pragma once

#include <dds/dds.h>

#include <array>

namespace syrof::sim_dds {

/// Calls visit(sample, info) for each valid sample `reader` holds and
/// returns how many samples (valid or not) were taken, or a negative
/// dds_return_t.
template <typename T, typename Visit>
int TakeSamples(dds_entity_t reader, Visit&& visit) {
  constexpr int kBatch = 32;
  int total = 0;
  for (;;) {
    std::array<void*, kBatch> samples{};
    std::array<dds_sample_info_t, kBatch> infos{};
    const dds_return_t taken = dds_take(reader, samples.data(), infos.data(), kBatch, kBatch);
    if (taken < 0) return total > 0 ? total : taken;
    for (dds_return_t i = 0; i < taken; ++i) {
      if (infos[static_cast<size_t>(i)].valid_data) visit(*static_cast<const T*>(samples[static_cast<size_t>(i)]), infos[static_cast<size_t>(i)]);
    }
    if (taken > 0) (void)dds_return_loan(reader, samples.data(), taken);
    total += taken;
    if (taken < kBatch) return total;
  }
}

}  // namespace syrof::sim_dds
