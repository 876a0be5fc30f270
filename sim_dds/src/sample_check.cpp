#include "syrof/sim_dds/sample_check.h"

#include "syrof/base/check.h"
#include "syrof/wire/beacon_codec.h"

namespace syrof::sim_dds {

const char* ToString(SampleVerdict verdict) {
  switch (verdict) {
    case SampleVerdict::kAccepted:
      return "accepted";
    case SampleVerdict::kOversized:
      return "oversized";
    case SampleVerdict::kSenderOutOfSwarm:
      return "sender_out_of_swarm";
    case SampleVerdict::kFromSelf:
      return "from_self";
    case SampleVerdict::kMalformed:
      return "malformed";
    case SampleVerdict::kSenderMismatch:
      return "sender_mismatch";
    case SampleVerdict::kRoundOutOfWindow:
      return "round_out_of_window";
    case SampleVerdict::kDuplicate:
      return "duplicate";
    case SampleVerdict::kOtherRun:
      return "other_run";
  }
  return "?";
}

SampleVerdict CheckSample(uint16_t sample_sender, uint32_t sample_round, std::span<const uint8_t> wire,
                          const ReceiverView& receiver, wire::Beacon& beacon) {
  if (wire.size() > wire::EncodedSize(receiver.swarm_size)) return SampleVerdict::kOversized;
  if (sample_sender >= receiver.swarm_size) return SampleVerdict::kSenderOutOfSwarm;
  if (sample_sender == receiver.self) return SampleVerdict::kFromSelf;
  auto decoded = wire::Decode(wire, receiver.swarm_size);
  if (!decoded.ok()) return SampleVerdict::kMalformed;
  if (decoded.value().robot_id != sample_sender) return SampleVerdict::kSenderMismatch;
  const auto round = static_cast<int64_t>(sample_round);
  if (receiver.current_round >= 0 &&
      (round < receiver.current_round - kRoundWindow || round > receiver.current_round + kRoundWindow)) {
    return SampleVerdict::kRoundOutOfWindow;
  }
  if (round <= receiver.last_round_from_sender) return SampleVerdict::kDuplicate;
  beacon = decoded.value();
  return SampleVerdict::kAccepted;
}

SampleVerdict CheckRun(uint64_t sample_run, uint64_t receiver_run) {
  return sample_run == receiver_run ? SampleVerdict::kAccepted : SampleVerdict::kOtherRun;
}

int64_t AgreedRoundOffset(std::span<const SenderRoundOffset> offsets, int64_t since_round) {
  auto heard = [since_round](const SenderRoundOffset& o) { return o.heard_in >= 0 && o.heard_in >= since_round; };
  size_t senders = 0;
  size_t best_count = 0;
  int64_t best = 0;
  for (const SenderRoundOffset& a : offsets) {
    if (!heard(a)) continue;
    ++senders;
    size_t count = 0;
    for (const SenderRoundOffset& b : offsets) count += heard(b) && b.offset == a.offset ? 1 : 0;
    if (count > best_count || (count == best_count && a.offset > best)) {
      best_count = count;
      best = a.offset;
    }
  }
  if (best > 0 && 2 * best_count > senders) return best;
  if (best < 0 && senders >= 2 && best_count == senders) return best;
  return 0;
}

uint64_t SampleCounters::rejected() const {
  uint64_t total = 0;
  for (int verdict = 1; verdict < kSampleVerdicts; ++verdict) total += counts_[verdict].load(std::memory_order_relaxed);
  return total;
}

SampleFilter::SampleFilter(uint16_t self, uint16_t swarm_size, uint64_t run_id)
    : self_(self), swarm_size_(swarm_size), run_id_(run_id), last_round_(swarm_size, -1) {
  SYROF_CHECK(swarm_size >= 1 && swarm_size <= kMaxDdsSwarm && self < swarm_size);
}

SampleVerdict SampleFilter::CheckRun(uint64_t sample_run) {
  const SampleVerdict verdict = sim_dds::CheckRun(sample_run, run_id_);
  if (verdict != SampleVerdict::kAccepted) counters_.Add(verdict);
  return verdict;
}

SampleVerdict SampleFilter::Check(uint16_t sample_sender, uint32_t sample_round, std::span<const uint8_t> wire,
                                  int64_t current_round, wire::Beacon& beacon) {
  ReceiverView view{.self = self_, .swarm_size = swarm_size_, .current_round = current_round};
  if (sample_sender < swarm_size_) view.last_round_from_sender = last_round_[sample_sender];
  const SampleVerdict verdict = CheckSample(sample_sender, sample_round, wire, view, beacon);
  if (verdict == SampleVerdict::kAccepted) last_round_[sample_sender] = sample_round;
  counters_.Add(verdict);
  return verdict;
}

}  // namespace syrof::sim_dds
