#include "syrof/lab/metrics/agreement.h"

#include <algorithm>

#include "syrof/lab/metrics/collector.h"
#include "syrof/sync/synchronizer.h"

namespace syrof::lab::metrics {

AgreementTracker::EpochRecord* AgreementTracker::Find(uint16_t epoch) {
  for (EpochRecord& record : open_) {
    if (record.epoch == epoch) return &record;
  }
  return nullptr;
}

void AgreementTracker::Close(const EpochRecord& record) {
  if (!record.disagreed) ++agreed_closed_;
  if (record.groups.size() > 1) ++split_epochs_closed_;
}

void AgreementTracker::Disagree(EpochRecord& record, uint16_t robot, int64_t round, Call call, uint8_t state,
                                uint16_t reference_robot, uint8_t reference_state) {
  record.disagreed = true;
  ++disagreeing_calls_;
  if (first_) return;
  first_ = Disagreement{record.epoch, round, call == Call::kNewRound ? "new_round" : "end_of_round",
                        robot, state, reference_robot, reference_state};
}

void AgreementTracker::OnAppState(uint16_t robot, int64_t round, Call call, uint16_t epoch, bool cooperative,
                                  uint64_t map_fingerprint, uint8_t state) {
  if (!cooperative) return;
  (call == Call::kNewRound ? new_round_calls_ : end_of_round_calls_) += 1;
  EpochRecord* record = Find(epoch);
  if (record == nullptr) {
    // A new epoch opens only ahead of the newest (serial arithmetic, as the
    // collector's window); one that far behind is not compared.
    if (any_ && sync::EpochDifference(epoch, newest_) <= -kAgreementEpochWindow) {
      ++unchecked_calls_;
      return;
    }
    if (!any_ || sync::EpochDifference(epoch, newest_) > 0) newest_ = epoch;
    any_ = true;
    ++epochs_;
    open_.push_back(EpochRecord{epoch, false, {}});
    record = &open_.back();
    // Epochs too far behind the newest are final now.
    const auto stale = [this](const EpochRecord& open) {
      return sync::EpochDifference(open.epoch, newest_) <= -kAgreementEpochWindow;
    };
    for (const EpochRecord& open : open_) {
      if (stale(open)) Close(open);
    }
    std::erase_if(open_, stale);
    record = Find(epoch);
    if (record == nullptr) return;  // opened and closed at once: cannot happen, the new epoch is the newest or near it
  }
  Group* group = nullptr;
  for (Group& candidate : record->groups) {
    if (candidate.fingerprint == map_fingerprint) group = &candidate;
  }
  if (group == nullptr) {
    if (record->groups.size() >= kMaxMapGroups) {
      ++unchecked_calls_;
      return;
    }
    record->groups.push_back(Group{map_fingerprint});
    group = &record->groups.back();
  }
  if (call == Call::kNewRound) {
    if (!group->has_new_round) {
      group->has_new_round = true;
      group->new_round_robot = robot;
      group->new_round_state = state;
    } else if (state != group->new_round_state) {
      Disagree(*record, robot, round, call, state, group->new_round_robot, group->new_round_state);
    }
    return;
  }
  if (!group->has_end) {
    group->has_end = true;
    group->end_robot = robot;
    group->end_state = state;
    return;
  }
  if (state != group->end_state) Disagree(*record, robot, round, call, state, group->end_robot, group->end_state);
}

AgreementMetrics AgreementTracker::Finish() const {
  AgreementMetrics metrics;
  metrics.cooperative_epochs = epochs_;
  metrics.agreed_epochs = agreed_closed_;
  metrics.split_epochs = split_epochs_closed_;
  for (const EpochRecord& record : open_) {
    if (!record.disagreed) ++metrics.agreed_epochs;
    if (record.groups.size() > 1) ++metrics.split_epochs;
  }
  if (epochs_ > 0) {
    metrics.agreed_fraction = static_cast<double>(metrics.agreed_epochs) / static_cast<double>(epochs_);
  }
  metrics.new_round_calls = new_round_calls_;
  metrics.end_of_round_calls = end_of_round_calls_;
  metrics.disagreeing_calls = disagreeing_calls_;
  metrics.unchecked_calls = unchecked_calls_;
  metrics.first_disagreement = first_;
  return metrics;
}

void AgreementTracker::AddToDigest(base::StateDigest& digest) const {
  digest.AddValue(any_);
  digest.AddValue(newest_);
  for (const EpochRecord& record : open_) {
    digest.AddValue(record.epoch);
    digest.AddValue(record.disagreed);
    for (const Group& group : record.groups) {  // field by field: Group has padding
      digest.AddValue(group.fingerprint);
      digest.AddValue(group.has_new_round);
      digest.AddValue(group.new_round_robot);
      digest.AddValue(group.new_round_state);
      digest.AddValue(group.has_end);
      digest.AddValue(group.end_robot);
      digest.AddValue(group.end_state);
    }
  }
}

}  // namespace syrof::lab::metrics
