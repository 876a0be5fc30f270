#include "syrof/sync/activation.h"

#include "syrof/base/split_mix64.h"

namespace syrof::sync {
namespace {

// Each use of the seed has its own stream, so the draws do not correlate.
constexpr uint64_t kDrawPurpose = 0x61637469766174ull;     // "activat"
constexpr uint64_t kOffsetPurpose = 0x6f6666736574ull;     // "offset"
constexpr uint64_t kFallbackPurpose = 0x66616c6c6261ull;   // "fallba"
constexpr uint64_t kStartPurpose = 0x7374617274ull;        // "start"
constexpr uint64_t kLengthPurpose = 0x6c656e677468ull;     // "length"
constexpr uint64_t kCutPurpose = 0x637574ull;              // "cut"

uint64_t Mix(uint64_t seed, uint64_t purpose, uint64_t a, uint64_t b) {
  return base::SplitMix64Hash(base::SplitMix64Hash(seed ^ purpose) ^ base::SplitMix64Hash((a << 16) ^ b));
}

// The member at `position` (0-based) of the ascending member list.
uint16_t MemberAt(const wire::MemberSet& members, uint32_t position) {
  uint32_t index = 0;
  for (const uint16_t member : members) {
    if (index++ == position) return member;
  }
  return wire::MemberSet::kCapacity;  // unreachable for position < count
}

bool ScriptListsEpoch(std::span<const ScriptedActivation> script, uint16_t epoch, size_t& first) {
  // Binary search for the first entry of `epoch`.
  size_t low = 0;
  size_t high = script.size();
  while (low < high) {
    const size_t middle = low + (high - low) / 2;
    if (script[middle].epoch < epoch) {
      low = middle + 1;
    } else {
      high = middle;
    }
  }
  first = low;
  return low < script.size() && script[low].epoch == epoch;
}

bool ScriptNames(std::span<const ScriptedActivation> script, size_t first, uint16_t epoch, uint16_t robot) {
  for (size_t i = first; i < script.size() && script[i].epoch == epoch; ++i) {
    if (script[i].robot == robot) return true;
  }
  return false;
}

// The schedule's own choice for `robot`, before the non-empty rule.
bool Chosen(const ActivationConfig& config, uint16_t epoch, const wire::MemberSet& members, uint16_t robot) {
  switch (config.schedule) {
    case ActivationSchedule::kRandom: {
      const uint32_t bound = config.fair_within;
      const uint32_t offset = static_cast<uint32_t>(Mix(config.seed, kOffsetPurpose, robot, 0) % bound);
      if ((epoch + offset) % bound == 0) return true;
      return (Mix(config.seed, kDrawPurpose, epoch, robot) & 1U) != 0;
    }
    case ActivationSchedule::kRoundRobin:
      return MemberAt(members, epoch % members.count()) == robot;
    case ActivationSchedule::kScripted: {
      size_t first = 0;
      if (!ScriptListsEpoch(config.script, epoch, first)) return true;
      return ScriptNames(config.script, first, epoch, robot);
    }
  }
  return true;
}

// Whether the schedule's own choice holds at least one of `members` (not
// empty). Linear in the members at most, so a swarm's decisions for one
// epoch stay quadratic, not cubic.
bool ChoiceHoldsAMember(const ActivationConfig& config, uint16_t epoch, const wire::MemberSet& members) {
  switch (config.schedule) {
    case ActivationSchedule::kRandom:
      for (const uint16_t member : members) {
        if (Chosen(config, epoch, members, member)) return true;
      }
      return false;
    case ActivationSchedule::kRoundRobin:
      return true;  // always one of the members
    case ActivationSchedule::kScripted: {
      size_t first = 0;
      if (!ScriptListsEpoch(config.script, epoch, first)) return true;  // every member
      for (size_t i = first; i < config.script.size() && config.script[i].epoch == epoch; ++i) {
        if (config.script[i].robot < wire::MemberSet::kCapacity && members.test(config.script[i].robot)) return true;
      }
      return false;
    }
  }
  return true;
}

}  // namespace

const char* ToString(ActivationModel model) {
  switch (model) {
    case ActivationModel::kFsync: return "fsync";
    case ActivationModel::kSsync: return "ssync";
    case ActivationModel::kAsync: return "async";
  }
  return "?";
}

const char* ToString(ActivationSchedule schedule) {
  switch (schedule) {
    case ActivationSchedule::kRandom: return "random";
    case ActivationSchedule::kRoundRobin: return "round_robin";
    case ActivationSchedule::kScripted: return "scripted";
  }
  return "?";
}

bool IsValid(const ActivationConfig& config) {
  if (config.fair_within < 1) return false;
  for (size_t i = 1; i < config.script.size(); ++i) {
    const ScriptedActivation& before = config.script[i - 1];
    const ScriptedActivation& entry = config.script[i];
    if (entry.epoch < before.epoch || (entry.epoch == before.epoch && entry.robot <= before.robot)) return false;
  }
  if (config.max_delay_epochs > kMaxAsyncDelayEpochs) return false;
  for (size_t i = 0; i < config.cycles.size(); ++i) {
    const ScriptedCycle& entry = config.cycles[i];
    if (entry.start_delay > config.max_delay_epochs || entry.move_epochs < 1 ||
        entry.move_epochs > config.max_delay_epochs + 1) {
      return false;
    }
    if (i == 0) continue;
    const ScriptedCycle& before = config.cycles[i - 1];
    if (entry.epoch < before.epoch || (entry.epoch == before.epoch && entry.robot <= before.robot)) return false;
  }
  return true;
}

bool IsActive(const ActivationConfig& config, uint16_t epoch, const wire::MemberSet& members, uint16_t robot) {
  if (robot >= wire::MemberSet::kCapacity || !members.test(robot)) return false;
  if (config.model != ActivationModel::kSsync) return true;
  if (Chosen(config, epoch, members, robot)) return true;
  // Only when the schedule chose no member at all does the fallback apply.
  if (ChoiceHoldsAMember(config, epoch, members)) return false;
  const uint32_t position = static_cast<uint32_t>(Mix(config.seed, kFallbackPurpose, epoch, 0) % members.count());
  return MemberAt(members, position) == robot;
}

uint16_t ActiveCount(const ActivationConfig& config, uint16_t epoch, const wire::MemberSet& members) {
  uint16_t count = 0;
  for (const uint16_t member : members) count += IsActive(config, epoch, members, member) ? 1 : 0;
  return count;
}

AsyncCycle CycleFor(const ActivationConfig& config, uint16_t epoch, uint16_t robot) {
  AsyncCycle cycle;
  if (config.model != ActivationModel::kAsync) return cycle;
  if (config.schedule == ActivationSchedule::kScripted) {
    // Binary search for (epoch, robot); a look the script does not list is
    // a one-epoch cycle.
    size_t low = 0;
    size_t high = config.cycles.size();
    while (low < high) {
      const size_t middle = low + (high - low) / 2;
      const ScriptedCycle& entry = config.cycles[middle];
      if (entry.epoch < epoch || (entry.epoch == epoch && entry.robot < robot)) {
        low = middle + 1;
      } else {
        high = middle;
      }
    }
    if (low < config.cycles.size() && config.cycles[low].epoch == epoch && config.cycles[low].robot == robot) {
      const ScriptedCycle& entry = config.cycles[low];
      cycle.start_delay = entry.start_delay;
      cycle.move_epochs = entry.move_epochs;
      cycle.cut = entry.cut && config.min_move_mm > 0;
    }
    return cycle;
  }
  const uint64_t choices = static_cast<uint64_t>(config.max_delay_epochs) + 1;
  cycle.start_delay = static_cast<uint8_t>(Mix(config.seed, kStartPurpose, epoch, robot) % choices);
  cycle.move_epochs = static_cast<uint8_t>(1 + Mix(config.seed, kLengthPurpose, epoch, robot) % choices);
  cycle.cut = config.min_move_mm > 0 && (Mix(config.seed, kCutPurpose, epoch, robot) & 1U) != 0;
  return cycle;
}

AsyncTracker::Step AsyncTracker::OnEpochStart(const ActivationConfig& config, uint16_t epoch, uint16_t robot) {
  Step step;
  if (!busy_) {
    busy_ = true;
    look_epoch_ = epoch;
    since_look_ = 0;
    cycle_ = CycleFor(config, epoch, robot);
    step.looks = true;
  } else {
    ++since_look_;
  }
  const uint32_t first_move = cycle_.start_delay;
  const uint32_t last_move = first_move + cycle_.move_epochs - 1;
  step.moves = since_look_ >= first_move && since_look_ <= last_move;
  step.first_move_epoch = since_look_ == first_move;
  step.last_move_epoch = since_look_ == last_move;
  step.look_epoch = look_epoch_;
  step.cycle = cycle_;
  if (step.last_move_epoch) busy_ = false;  // the next epoch start looks again
  return step;
}

uint64_t AsyncTracker::Packed() const {
  return (busy_ ? 1ULL : 0ULL) | (uint64_t{look_epoch_} << 1) | (uint64_t{since_look_} << 17) |
         (uint64_t{cycle_.start_delay} << 33) | (uint64_t{cycle_.move_epochs} << 41) | (cycle_.cut ? 1ULL << 49 : 0ULL);
}

}  // namespace syrof::sync
