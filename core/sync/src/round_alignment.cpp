#include "syrof/sync/round_alignment.h"

#include <array>

#include "syrof/base/check.h"

namespace syrof::sync {

AlignmentConfig AlignmentConfig::ForRound(int64_t round_ns, uint16_t self_id) {
  AlignmentConfig config;
  config.round_ns = round_ns;
  config.max_slew_ns = round_ns / 4;
  config.lock_spread_ns = round_ns / 8;
  config.self_id = self_id;
  return config;
}

int64_t WrapPhase(int64_t x, int64_t round_ns) {
  SYROF_CHECK(round_ns > 0);
  int64_t r = x % round_ns;
  if (r < 0) r += round_ns;  // r in [0, round)
  return r >= round_ns - round_ns / 2 ? r - round_ns : r;
}

AlignmentStep Align(const AlignmentConfig& config, std::span<const AlignmentSample> samples, bool member,
                    AlignmentStats& stats, int64_t unseen_correction_ns) {
  AlignmentStep step;
  std::array<int64_t, kMaxAlignmentSamples> errors{};
  size_t count = 0;
  uint16_t lowest = 0xFFFF;
  int64_t lowest_error = 0;
  for (const AlignmentSample& sample : samples) {
    if (count == errors.size()) break;
    // Insertion sort as the samples come: at most 64, so at most ~2000 moves.
    const int64_t error =
        WrapPhase(sample.offset_ns - config.expected_delay_ns - unseen_correction_ns, config.round_ns);
    if (sample.sender < lowest) {
      lowest = sample.sender;
      lowest_error = error;
    }
    size_t at = count++;
    while (at > 0 && errors[at - 1] > error) {
      errors[at] = errors[at - 1];
      --at;
    }
    errors[at] = error;
  }
  if (count == 0) return step;
  // The lower median: with two samples, the earlier; deterministic, integer.
  const int64_t median = errors[(count - 1) / 2];
  step.median_error_ns = median;
  step.spread_ns = errors[(3 * (count - 1)) / 4] - errors[(count - 1) / 4];
  step.samples = static_cast<uint8_t>(count);
  ++stats.rounds_with_samples;
  stats.last_error_ns = median;
  if (!config.enabled) return step;
  if (!member) {
    step.correction_ns = median;
    step.jumped = median != 0;
  } else if (step.spread_ns > config.lock_spread_ns) {
    if (lowest < config.self_id) {
      step.correction_ns = lowest_error;
      step.jumped = lowest_error != 0;
    }
  } else {
    // A quarter of the error: two robots that hear each other meet in the
    // middle instead of swapping places, a group contracts onto its median,
    // and the peers' unseen corrections (header) do not make it ring.
    int64_t correction = median / 4;
    if (correction > config.max_slew_ns) correction = config.max_slew_ns;
    if (correction < -config.max_slew_ns) correction = -config.max_slew_ns;
    step.correction_ns = correction;
  }
  stats.jumps += step.jumped ? 1 : 0;
  const int64_t magnitude = step.correction_ns < 0 ? -step.correction_ns : step.correction_ns;
  if (magnitude > stats.largest_correction_ns) stats.largest_correction_ns = magnitude;
  return step;
}

}  // namespace syrof::sync
