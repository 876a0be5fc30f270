// The synchronizer's state and an epoch's map into a base::StateDigest, for
// a search that prunes states it has seen (lab/search). Only the first
// `swarm_size` entries of the per-robot arrays go in: the rest are never
// written. The stats (SyncStats) stay out: they count what happened, for
// reports, and no step reads them.
#pragma once

#include <cstddef>
#include <span>

#include "syrof/base/state_digest.h"
#include "syrof/sync/ldmap.h"
#include "syrof/sync/synchronizer.h"

namespace syrof::sync {

using wire::AddToDigest;

inline void AddToDigest(base::StateDigest& digest, const LDMap& map, size_t swarm_size) {
  digest.AddValue(map.epoch);
  digest.AddValue(map.mode);
  AddToDigest(digest, map.members);
  digest.AddRange(std::span<const wire::Phase>(map.phases.data(), swarm_size));
  digest.AddRange(std::span<const wire::Snapshot>(map.snapshots.data(), swarm_size));
}

inline void AddToDigest(base::StateDigest& digest, const SyncState& state, size_t swarm_size) {
  digest.AddValue(state.status);
  digest.AddValue(state.epoch);
  digest.AddValue(state.phase);
  digest.AddValue(state.vote);
  digest.AddValue(state.epoch_mode);
  digest.AddValue(state.veto);
  for (const MemberSet* set : {&state.members, &state.waiting, &state.view, &state.votes_matched, &state.held,
                               &state.join_group, &state.flaky_current, &state.flaky_previous, &state.flaky,
                               &state.reported, &state.pruned, &state.pruned_members, &state.pruned_heard}) {
    AddToDigest(digest, *set);
  }
  digest.AddValue(state.join_target_known);
  digest.AddValue(state.join_rounds_left);
  digest.AddValue(state.join_epoch);
  digest.AddValue(state.rounds_alone);
  digest.AddValue(state.stay_rounds);
  digest.AddValue(state.rounds_joining);
  digest.AddValue(state.join_credit);
  digest.AddValue(state.report_count);
  for (size_t i = 0; i < state.report_count && i < state.reports.size(); ++i) {
    digest.AddValue(state.reports[i].reporter);
    AddToDigest(digest, state.reports[i].heard);
  }
  digest.AddValue(state.pruned_stale);
  digest.AddRange(std::span<const uint16_t>(state.silent_rounds.data(), swarm_size));
  digest.AddRange(std::span<const wire::Snapshot>(state.snapshots.data(), swarm_size));
  digest.AddRange(std::span<const wire::Phase>(state.last_phase.data(), swarm_size));
  digest.AddValue(state.live);
}

}  // namespace syrof::sync
