// The synchronizer's step function. Section names in comments refer to
// docs/protocol.md, which this code follows.
#include "syrof/sync/synchronizer.h"

#include <algorithm>
#include <array>
#include <bit>
#include <cstddef>

#include "syrof/base/check.h"

namespace syrof::sync {
namespace {

// Members of `set` other than `self`.
MemberSet Without(MemberSet set, uint16_t self) {
  set.reset(self);
  return set;
}

// "Connectivity": this robot's heard set, the members it hears well, and
// itself. A member the failure detector removed in this epoch still counts
// until it has been silent for 2F rounds (a run of lost beacons is no broken
// link, and a report without it would reach the others stale, in WAIT, after
// it is back); a deaf robot's or a dead link's report lacks it F rounds after
// the removal. A member is not heard well (flaky) from the second epoch in a
// row in which the failure detector removed it, until an epoch passes without
// a removal: a link at 90 % loss stays out, while at 25 % loss (a removal in
// about 1 % of a link's epochs) a link is almost never out.
MemberSet HeardSet(const SyncConfig& config, const SyncState& state) {
  MemberSet flaky = state.flaky_current;
  flaky &= state.flaky_previous;
  flaky |= state.flaky;
  MemberSet heard = state.members;
  for (const uint16_t id : state.flaky_current) {
    if (!heard.test(id) && state.silent_rounds[id] < 2 * config.silence_rounds) heard.set(id);
  }
  heard -= flaky;
  heard.set(config.self_id);
  return heard;
}

// The kept report of `id`, or nullptr.
const Report* FindReport(const SyncState& state, uint16_t id) {
  if (!state.reported.test(id)) return nullptr;
  for (size_t i = 0; i < state.report_count; ++i) {
    if (state.reports[i].reporter == id) return &state.reports[i];
  }
  return nullptr;
}

void DropReport(SyncState& state, uint16_t id) {
  if (!state.reported.test(id)) return;
  size_t at = 0;
  while (state.reports[at].reporter != id) ++at;
  for (size_t i = at + 1; i < state.report_count; ++i) state.reports[i - 1] = state.reports[i];
  state.reports[--state.report_count] = Report{};
  state.reported.reset(id);
  state.pruned_stale = true;
}

// Keeps `heard`, the heard set `id` sent, if it lacks one of this robot's
// members; a report that names them all says nothing the rule needs (the
// rule reads reports only about members). The pool is sorted by id; when it
// is full the highest id gives way.
void TakeReport(SyncState& state, uint16_t id, const MemberSet& heard) {
  if (heard.includes(state.members)) {
    // Nearly every PROGRESS beacon, and nearly always nothing kept to drop:
    // the test here spares a call per beacon.
    if (state.reported.test(id)) DropReport(state, id);
    return;
  }
  size_t at = 0;
  while (at < state.report_count && state.reports[at].reporter < id) ++at;
  if (at < state.report_count && state.reports[at].reporter == id) {
    if (!(state.reports[at].heard == heard)) {
      state.reports[at].heard = heard;
      state.pruned_stale = true;
    }
    return;
  }
  if (at == kMaxReports) return;  // full of lower ids
  if (state.report_count == kMaxReports) {
    state.reported.reset(state.reports[kMaxReports - 1].reporter);
    --state.report_count;
  }
  for (size_t i = state.report_count; i > at; --i) state.reports[i] = state.reports[i - 1];
  state.reports[at] = Report{id, heard};
  ++state.report_count;
  state.reported.set(id);
  state.pruned_stale = true;
}

// "Connectivity", the rule: among the members, while some pair does not
// hear each other both ways, leave out the member with the most such
// partners, the higher id on a tie. What a member hears: this robot, its
// heard set; a member with a kept report, that report; any other member,
// every member (its report equalled this robot's members). A robot this
// one does not hear is not a member, so it is not a candidate: whoever
// hears it decides about it.
MemberSet ComputePruned(const SyncConfig& config, const SyncState& state, const MemberSet& heard_self) {
  const uint16_t self = config.self_id;
  MemberSet candidates = state.members;
  MemberSet reporters;
  for (size_t i = 0; i < state.report_count; ++i) {
    const uint16_t reporter = state.reports[i].reporter;
    if (state.members.test(reporter) && reporter != self) reporters.set(reporter);
  }
  MemberSet pruned;
  if (reporters.empty() && heard_self.includes(state.members)) return pruned;  // everyone hears everyone

  const auto hears = [&](uint16_t c, uint16_t p) {
    if (c == self) return heard_self.test(p);
    if (reporters.test(c)) return FindReport(state, c)->heard.test(p);
    return true;  // a plain member: its report named every member
  };
  while (true) {
    uint16_t worst = MemberSet::kCapacity;
    uint16_t worst_count = 0;
    for (const uint16_t c : candidates) {
      uint16_t count = 0;
      if (c == self || reporters.test(c)) {
        // Its row is known: every candidate it does not hear, or that does
        // not hear it, once.
        for (const uint16_t p : candidates) {
          if (p != c && (!hears(c, p) || !hears(p, c))) ++count;
        }
      } else {
        // A plain member hears every candidate: count who does not hear it.
        if (candidates.test(self) && !hears(self, c)) ++count;
        for (const uint16_t r : reporters) {
          if (!hears(r, c)) ++count;
        }
      }
      if (count > 0 && count >= worst_count) {
        worst = c;
        worst_count = count;
      }
    }
    if (worst == MemberSet::kCapacity) return pruned;
    pruned.set(worst);
    candidates.reset(worst);
    reporters.reset(worst);
  }
}

// Brings `pruned` up to date with the members, the heard set and the reports.
void UpdatePruned(const SyncConfig& config, SyncState& state) {
  const MemberSet heard = HeardSet(config, state);
  if (!state.pruned_stale && state.pruned_members == state.members && state.pruned_heard == heard) return;
  const MemberSet pruned = ComputePruned(config, state, heard);
  if (!(pruned == state.pruned)) ++state.stats.prunings;
  state.pruned = pruned;
  state.pruned_members = state.members;
  state.pruned_heard = heard;
  state.pruned_stale = false;
}

// "Beacon validation": why `beacon` cannot be used, or kNone.
BeaconIssue Inspect(const SyncConfig& config, const wire::Beacon& beacon, const MemberSet& seen) {
  if (beacon.robot_id >= config.swarm_size) return BeaconIssue::kIdOutOfRange;
  if (beacon.robot_id == config.self_id) return BeaconIssue::kFromSelf;
  if (seen.test(beacon.robot_id)) return BeaconIssue::kDuplicate;
  const bool voting = beacon.phase == Phase::kVote;
  if (voting && (beacon.vote_counter < 1 || beacon.vote_counter > config.vote_rounds)) {
    return BeaconIssue::kBadVoteCounter;
  }
  if (!voting && beacon.vote_counter != 0) return BeaconIssue::kBadVoteCounter;
  if (beacon.waiting.any_at_or_above(config.swarm_size)) {
    return BeaconIssue::kMemberOutOfRange;
  }
  return BeaconIssue::kNone;
}

const wire::Beacon& Deref(const wire::Beacon& beacon) { return beacon; }
const wire::Beacon& Deref(const wire::Beacon* beacon) { return *beacon; }

// The beacons of one round that passed validation, at most one per robot, so
// never more than the swarm size. The later passes of a step read only these.
class UsableBeacons {
 public:
  // `received` holds beacons or pointers to them (Deref reads either).
  template <typename Received>
  UsableBeacons(const SyncConfig& config, std::span<Received> received, SyncStats& stats) {
    MemberSet seen;
    size_t count = 0;  // a local, so that the loop keeps it in a register
    for (const auto& entry : received) {
      const wire::Beacon& beacon = Deref(entry);
      const BeaconIssue issue = Inspect(config, beacon, seen);
      if (issue != BeaconIssue::kNone) {
        ++stats.beacons_rejected;
        stats.last_issue = issue;
        continue;
      }
      seen.set(beacon.robot_id);
      beacons_[count++] = &beacon;
    }
    count_ = count;
    stats.beacons_used += static_cast<uint32_t>(count);
  }
  const wire::Beacon* const* begin() const { return beacons_.data(); }
  const wire::Beacon* const* end() const { return beacons_.data() + count_; }
  bool empty() const { return count_ == 0; }

  // Keeps only the beacons for which `keep` holds, in their order.
  template <typename Keep>
  void RetainIf(Keep keep) {
    size_t kept = 0;
    for (size_t i = 0; i < count_; ++i) {
      if (keep(*beacons_[i])) beacons_[kept++] = beacons_[i];
    }
    count_ = kept;
  }

 private:
  // Only the first count_ entries are ever read; left uninitialized, since
  // zeroing the whole array (8 KB on the host) would cost more than the step.
  std::array<const wire::Beacon*, wire::kMaxSwarmSize> beacons_;
  size_t count_ = 0;
};

// "Epoch start": fills `ldmap`, moves `state` into PROGRESS of epoch + 1.
void StartEpoch(const SyncConfig& config, SyncState& state, Mode mode, StepOutput& out, LDMap& ldmap) {
  const uint16_t next_epoch = static_cast<uint16_t>(state.epoch + 1);
  ldmap.epoch = next_epoch;
  ldmap.mode = mode;
  if (mode == Mode::kCooperative) {
    ldmap.members = state.view;
  } else {
    ldmap.members = state.held;
    ldmap.members &= state.members;
  }
  if (!state.held.test(config.self_id)) {
    // A robot always knows itself: a catch-up from PROGRESS cannot happen,
    // but a founder or joiner has no frozen snapshot, so it uses its live one.
    state.snapshots[config.self_id] = state.live;
  }
  ldmap.members.set(config.self_id);
  for (const uint16_t id : ldmap.members) {
    ldmap.snapshots[id] = state.snapshots[id];
    ldmap.phases[id] = id == config.self_id ? state.phase : state.last_phase[id];
  }

  state.epoch = next_epoch;
  state.phase = Phase::kProgress;
  state.vote = 0;
  state.veto = false;
  state.epoch_mode = mode;
  state.stay_rounds = 0;
  state.waiting.clear();
  state.view.clear();
  state.votes_matched.clear();
  state.held.clear();
  MemberSet twice = state.flaky_current;
  twice &= state.flaky_previous;
  state.flaky &= state.flaky_current;  // stays flaky while removed again
  state.flaky |= twice;
  state.flaky_previous = state.flaky_current;
  state.flaky_current.clear();

  out.epoch_started = true;
  ++state.stats.epochs_started;
  if (mode == Mode::kCooperative) ++state.stats.epochs_cooperative;
}

// "Connectivity": nothing known about anyone's links.
void ForgetConnectivity(SyncState& state) {
  state.flaky_current.clear();
  state.flaky_previous.clear();
  state.flaky.clear();
  state.reported.clear();
  state.reports = {};
  state.report_count = 0;
  state.pruned.clear();
  state.pruned_stale = true;
}

// "Joining": the robot leaves its group and listens for another's boundary.
void BecomeJoiner(SyncState& state, StepOutput& out) {
  state.status = Status::kJoining;
  state.members.clear();
  state.waiting.clear();
  state.view.clear();
  state.votes_matched.clear();
  state.held.clear();
  state.join_group.clear();
  state.join_target_known = false;
  state.join_rounds_left = 0;
  state.rounds_alone = 0;
  state.veto = false;
  state.vote = 0;
  state.stay_rounds = 0;
  state.rounds_joining = 0;
  ForgetConnectivity(state);
  out.became_joiner = true;
}

// Whether `beacon` speaks for a group: a WAIT or VOTE beacon whose set (a
// subset of its sender's members) names a robot besides its sender. A
// PROGRESS beacon's set is a heard set, which says nothing of groups. A
// robot alone (a deaf one, or one cut off) never drags others along
// ("Falling behind", "Alone ahead").
bool FromGroup(const wire::Beacon& beacon) {
  if (beacon.phase == Phase::kProgress) return false;
  // Its smallest member other than the sender, without copying the set.
  const uint16_t first = beacon.waiting.next_member(0);
  const uint16_t other = first == beacon.robot_id ? beacon.waiting.next_member(first + 1) : first;
  return other != MemberSet::kCapacity;
}

// "Epoch numbers": whether a joiner may move from its epoch to `target`,
// and what that costs. A joiner that has not been a member for
// kJoinFreeRounds may take any epoch, at no cost.
bool JoinAllowed(const SyncState& state, uint16_t target) {
  if (state.rounds_joining >= kJoinFreeRounds) return true;
  const int16_t jump = EpochDifference(target, state.epoch);
  return jump > 0 && jump <= static_cast<int16_t>(state.join_credit);
}

void PayForJoin(SyncState& state, uint16_t target) {
  if (state.rounds_joining >= kJoinFreeRounds) return;
  state.join_credit = static_cast<uint16_t>(state.join_credit - EpochDifference(target, state.epoch));
}

// "Joining" and "Founding".
void StepJoining(const SyncConfig& config, SyncState& state, const UsableBeacons& received,
                 StepOutput& out, LDMap& ldmap) {
  for (const wire::Beacon* usable : received) {
    const wire::Beacon& beacon = *usable;
    if (beacon.phase != Phase::kVote) continue;
    const uint16_t target = static_cast<uint16_t>(beacon.epoch + 1);
    // Only an epoch after every one this robot has been in, within its join
    // credit: a robot never takes part in the same epoch twice within
    // 21,846 rounds (docs/protocol.md, "Epoch numbers").
    if (!JoinAllowed(state, target)) continue;
    const auto rounds_left = static_cast<uint8_t>(config.vote_rounds - beacon.vote_counter);
    const int16_t ahead = state.join_target_known ? EpochDifference(target, state.join_epoch) : 1;
    if (ahead > 0) {
      state.join_target_known = true;
      state.join_epoch = target;
      state.join_rounds_left = rounds_left;
      state.join_group.clear();
      state.held.clear();
    } else if (ahead == 0 && rounds_left < state.join_rounds_left) {
      state.join_rounds_left = rounds_left;
    }
    if (ahead >= 0) {
      state.join_group.set(beacon.robot_id);
      if (!state.held.test(beacon.robot_id)) {
        state.held.set(beacon.robot_id);
        state.snapshots[beacon.robot_id] = beacon.snapshot;
        state.last_phase[beacon.robot_id] = beacon.phase;
      }
    }
  }
  state.rounds_alone = !received.empty() ? 0 : static_cast<uint16_t>(state.rounds_alone + 1);

  if (state.join_target_known) {
    if (state.join_rounds_left > 0) {
      --state.join_rounds_left;
      return;
    }
    // The group starts join_epoch at the end of this round; so does the joiner.
    PayForJoin(state, state.join_epoch);
    state.status = Status::kMember;
    state.epoch = static_cast<uint16_t>(state.join_epoch - 1);
    state.members = state.join_group;
    state.members.set(config.self_id);
    for (const uint16_t id : state.members) state.silent_rounds[id] = 0;
    out.joined = Without(state.members, config.self_id);
    state.join_target_known = false;
    ++state.stats.joins_started;
    StartEpoch(config, state, Mode::kAutonomous, out, ldmap);
    return;
  }
  const auto founded = static_cast<uint16_t>(state.epoch + 1);
  if (state.rounds_alone >= config.silence_rounds && JoinAllowed(state, founded)) {
    // Nobody to join: found a group of one in a fresh epoch.
    PayForJoin(state, founded);
    state.status = Status::kMember;
    state.members.clear();
    state.members.set(config.self_id);
    state.held.clear();
    state.rounds_alone = 0;
    StartEpoch(config, state, Mode::kAutonomous, out, ldmap);
  }
}

// Step 1, "PROGRESS": the maneuver ends, the snapshot freezes.
void FinishProgress(const SyncConfig& config, SyncState& state, const StepInput& input) {
  if (state.phase != Phase::kProgress || !input.maneuver_finished) return;
  state.phase = Phase::kWait;
  state.snapshots[config.self_id] = input.own_snapshot;
  state.held.set(config.self_id);
  state.waiting.set(config.self_id);
}

// What the first pass over this round's beacons found (SurveyBeacons).
struct Survey {
  bool lost_group = false;    // "Falling behind" or "Alone ahead": rejoin
  bool catch_up_any = false;  // some robot, ignored ones included, one epoch ahead
};

// Steps 2 and 3, first pass: where the groups this robot hears are relative
// to its epoch, and whether any robot, ignored ones included, is one epoch
// ahead ("Catching up", used by the caller only when this robot is left
// alone, which follows whoever it hears). In the same pass, "Connectivity":
// the heard sets of PROGRESS beacons are the reports the rule reads. If the
// robot turns out to have lost its group, it rejoins and forgets every
// report, so taking them before that is known changes nothing.
Survey SurveyBeacons(SyncState& state, const UsableBeacons& received, bool past_progress) {
  const bool alone = state.members.count() == 1;
  Survey survey;
  for (const wire::Beacon* beacon : received) {
    const int16_t ahead = EpochDifference(beacon->epoch, state.epoch);
    if (ahead == 1 && past_progress) survey.catch_up_any = true;
    if ((ahead >= 2 || (alone && ahead <= -2)) && FromGroup(*beacon)) survey.lost_group = true;
    if (beacon->phase == Phase::kProgress && ahead >= -1 && ahead <= 1) {
      TakeReport(state, beacon->robot_id, beacon->waiting);
    }
  }
  return survey;
}

// Step 3, "Connectivity": drops the beacons of the robots the rule leaves
// out, which every later step ignores except the failure detector (they are
// still evidence of life: put in `evidence`). Returns whether a kept beacon
// is one epoch ahead; with none left out (nearly always) every beacon is
// kept, and that is exactly what the first pass saw (`catch_up_any`).
bool IgnorePruned(const SyncConfig& config, SyncState& state, UsableBeacons& received, bool past_progress,
                  bool catch_up_any, StepOutput& out, MemberSet& evidence) {
  UpdatePruned(config, state);
  MemberSet ignored = state.pruned;
  ignored.reset(config.self_id);
  if (ignored.empty()) return catch_up_any;
  bool catch_up_kept = false;
  received.RetainIf([&](const wire::Beacon& beacon) {
    const uint16_t id = beacon.robot_id;
    const int16_t ahead = EpochDifference(beacon.epoch, state.epoch);
    if (ignored.test(id)) {
      // Membership stays physical: an ignored robot heard in this epoch is
      // a member (the rule may keep it once it is one).
      if (ahead >= -1 && ahead <= 1) evidence.set(id);
      if (ahead == 0 && !state.members.test(id)) {
        state.members.set(id);
        state.silent_rounds[id] = 0;
        out.joined.set(id);
      }
      return false;
    }
    if (past_progress && ahead == 1) catch_up_kept = true;
    return true;
  });
  return catch_up_kept;
}

// Step 5, "Receiving": evidence of life into `alive`; from this epoch's
// beacons, joins, waiting sets and snapshots. Returns the highest VOTE
// counter heard in this epoch (0: none).
uint8_t ReceiveBeacons(SyncState& state, const UsableBeacons& received, StepOutput& out, MemberSet& alive) {
  uint8_t highest_vote = 0;
  for (const wire::Beacon* usable : received) {
    const wire::Beacon& beacon = *usable;
    const uint16_t id = beacon.robot_id;
    const int16_t ahead = EpochDifference(beacon.epoch, state.epoch);
    if (ahead < -1 || ahead > 1) continue;  // another group: not evidence of life
    alive.set(id);
    if (ahead != 0) continue;
    if (!state.members.test(id)) {
      state.members.set(id);
      state.silent_rounds[id] = 0;
      out.joined.set(id);
    }
    state.last_phase[id] = beacon.phase;
    if (beacon.phase == Phase::kProgress) continue;  // its set is a heard set
    state.waiting.set(id);
    if (!state.held.test(id)) {
      state.held.set(id);
      state.snapshots[id] = beacon.snapshot;
    }
    if (beacon.phase == Phase::kWait) {
      state.waiting |= beacon.waiting;
    } else if (beacon.vote_counter > highest_vote) {
      highest_vote = beacon.vote_counter;
    }
  }
  return highest_vote;
}

// Step 6, "Failure detector", a word of members at a time: the heard ones
// reset their count without a branch per member (in a large swarm nearly all
// are heard, and the few lost beacons are unpredictable). Then
// "Connectivity": how long each member removed in this epoch has been silent.
void DetectFailures(const SyncConfig& config, SyncState& state, const MemberSet& alive, StepOutput& out) {
  const uint16_t self = config.self_id;
  const size_t member_words = state.members.word_count();
  for (size_t w = 0; w < member_words; ++w) {
    uint32_t others = state.members.word(w);
    if (w == self / MemberSet::kWordBits) others &= ~(uint32_t{1} << (self % MemberSet::kWordBits));
    const uint32_t heard_word = alive.word(w);
    const auto first_id = static_cast<uint16_t>(w * MemberSet::kWordBits);
    for (uint32_t heard = others & heard_word; heard != 0; heard &= heard - 1) {
      state.silent_rounds[first_id + std::countr_zero(heard)] = 0;
    }
    for (uint32_t unheard = others & ~heard_word; unheard != 0; unheard &= unheard - 1) {
      const auto id = static_cast<uint16_t>(first_id + std::countr_zero(unheard));
      if (++state.silent_rounds[id] >= config.silence_rounds) {
        state.members.reset(id);
        state.flaky_current.set(id);
        DropReport(state, id);
        out.removed.set(id);
      }
    }
  }

  for (const uint16_t id : state.flaky_current) {
    if (state.members.test(id)) continue;
    state.silent_rounds[id] = alive.test(id) ? 0 : static_cast<uint16_t>(std::min<uint32_t>(0xFFFFu, state.silent_rounds[id] + 1u));
  }
}

// Step 7, "WAIT": every member waiting (those left out aside), or a member
// already voting. The view is the members the rule keeps, and this robot.
void MaybeStartVote(const SyncConfig& config, SyncState& state, uint8_t highest_vote) {
  UpdatePruned(config, state);
  MemberSet kept = state.members;
  kept -= state.pruned;
  kept.set(config.self_id);
  if (state.phase == Phase::kWait && (state.waiting.includes(kept) || highest_vote > 0)) {
    if (highest_vote > 0) ++state.stats.late_votes;
    state.phase = Phase::kVote;
    state.view = kept;
    state.vote = 0;
    state.veto = false;
    state.votes_matched.clear();
  }
}

// Step 8, "VOTE": evidence for the mode, then the counter; at K, the epoch starts.
void StepVote(const SyncConfig& config, SyncState& state, const UsableBeacons& received, uint8_t highest_vote,
              StepOutput& out, LDMap& ldmap) {
  const uint16_t self = config.self_id;
  for (const wire::Beacon* usable : received) {
    const wire::Beacon& beacon = *usable;
    if (beacon.phase != Phase::kVote || beacon.epoch != state.epoch) continue;
    if (!state.view.test(beacon.robot_id)) continue;
    if (beacon.mode == Mode::kAutonomous || beacon.waiting != state.view) {
      state.veto = true;
    } else {
      state.votes_matched.set(beacon.robot_id);
    }
  }
  if (!state.members.includes(state.view) || state.view.count() < config.quorum) state.veto = true;
  // A robot the rule leaves out cannot cooperate: some member does not hear
  // it, or it does not hear some member.
  if (state.pruned.test(self)) state.veto = true;

  if (highest_vote > state.vote) state.vote = highest_vote;
  if (state.vote < config.vote_rounds) {
    ++state.vote;
    return;
  }
  const bool cooperative = !state.veto && state.votes_matched.includes(Without(state.view, self)) &&
                           state.held.includes(state.view);
  StartEpoch(config, state, cooperative ? Mode::kCooperative : Mode::kAutonomous, out, ldmap);
}

// "Step, for a member" (docs/protocol.md), its steps 1 to 8 in order.
void StepMember(const SyncConfig& config, SyncState& state, UsableBeacons& received,
                const StepInput& input, StepOutput& out, LDMap& ldmap) {
  FinishProgress(config, state, input);
  const bool past_progress = state.phase != Phase::kProgress;
  const Survey survey = SurveyBeacons(state, received, past_progress);

  // Step 2, "Falling behind": a group two or more epochs ahead means this
  // robot's group is gone. "Alone ahead": a robot with no other member that
  // hears a group two or more epochs behind waits for it. Either way it
  // rejoins, and this round's beacons already count.
  if (survey.lost_group) {
    BecomeJoiner(state, out);
    StepJoining(config, state, received, out, ldmap);
    return;
  }

  MemberSet evidence;  // ignored robots heard this round
  const bool catch_up_kept =
      IgnorePruned(config, state, received, past_progress, survey.catch_up_any, out, evidence);

  // Step 4, "Catching up": a member one epoch ahead started it without this
  // one. A robot alone also follows a robot it ignores, so that robot, if it
  // only lost it for a while, hears it in its own epoch again.
  if (catch_up_kept || (survey.catch_up_any && state.members.count() == 1)) {
    ++state.stats.catch_ups;
    StartEpoch(config, state, Mode::kAutonomous, out, ldmap);
  }

  MemberSet alive = evidence;
  const uint8_t highest_vote = ReceiveBeacons(state, received, out, alive);
  DetectFailures(config, state, alive, out);
  MaybeStartVote(config, state, highest_vote);
  if (state.phase != Phase::kVote) return;
  StepVote(config, state, received, highest_vote, out, ldmap);
}

}  // namespace

const char* ToString(Status status) {
  switch (status) {
    case Status::kMember: return "MEMBER";
    case Status::kJoining: return "JOINING";
  }
  return "?";
}

const char* ToString(BeaconIssue issue) {
  switch (issue) {
    case BeaconIssue::kNone: return "None";
    case BeaconIssue::kFromSelf: return "FromSelf";
    case BeaconIssue::kIdOutOfRange: return "IdOutOfRange";
    case BeaconIssue::kDuplicate: return "Duplicate";
    case BeaconIssue::kBadVoteCounter: return "BadVoteCounter";
    case BeaconIssue::kMemberOutOfRange: return "MemberOutOfRange";
  }
  return "?";
}

int16_t EpochDifference(uint16_t a, uint16_t b) {
  return static_cast<int16_t>(static_cast<uint16_t>(a - b));
}

SyncState InitialState(const SyncConfig& config, const wire::Snapshot& initial_snapshot) {
  SYROF_CHECK(Validate(config) == ConfigError::kOk);
  SyncState state;
  state.live = initial_snapshot;
  if (!config.initial_members.test(config.self_id)) {
    state.status = Status::kJoining;
    state.rounds_joining = kJoinFreeRounds;  // never in an epoch: any epoch will do
    return state;
  }
  state.status = Status::kMember;
  state.epoch = 0;
  state.phase = Phase::kWait;
  state.members = config.initial_members;
  state.waiting.set(config.self_id);
  state.held.set(config.self_id);
  state.snapshots[config.self_id] = initial_snapshot;
  return state;
}

wire::Beacon MakeBeacon(const SyncConfig& config, const SyncState& state) {
  wire::Beacon beacon;
  beacon.robot_id = config.self_id;
  beacon.epoch = state.epoch;
  beacon.phase = state.phase;
  switch (state.phase) {
    case Phase::kProgress:
      beacon.mode = state.epoch_mode;
      beacon.waiting = HeardSet(config, state);
      beacon.snapshot = state.live;
      break;
    case Phase::kWait:
      beacon.mode = state.epoch_mode;
      beacon.waiting = state.waiting;
      beacon.snapshot = state.snapshots[config.self_id];
      break;
    case Phase::kVote:
      beacon.mode = state.veto ? Mode::kAutonomous : Mode::kCooperative;
      beacon.vote_counter = state.vote;
      beacon.waiting = state.view;
      beacon.snapshot = state.snapshots[config.self_id];
      break;
  }
  return beacon;
}

namespace {

// The body of both Step() overloads.
void StepWith(const SyncConfig& config, SyncState& state, UsableBeacons& usable, const StepInput& input,
              StepOutput& out, LDMap& ldmap) {
  // "Epoch numbers": time passes, missed rounds included.
  const uint32_t elapsed = input.rounds_elapsed == 0 ? 1 : input.rounds_elapsed;
  const auto saturate = [](uint32_t value) { return static_cast<uint16_t>(value > 0xFFFFu ? 0xFFFFu : value); };
  state.join_credit = saturate(std::min<uint32_t>(kMaxJoinCredit, state.join_credit + elapsed));
  if (state.status == Status::kMember) {
    state.stay_rounds = saturate(state.stay_rounds + elapsed);
    const uint32_t missed = elapsed - 1;
    const bool gap = missed >= config.silence_rounds;
    if (gap || state.stay_rounds >= kMaxStayRounds) {
      // The others have removed it (gap), or its knowledge is too old to
      // be trusted under 16-bit epoch numbers: start over as a joiner.
      if (gap) {
        ++state.stats.restarts_after_gap;
      } else {
        ++state.stats.restarts_long_stay;
      }
      BecomeJoiner(state, out);
      state.rounds_joining = saturate(missed);
    }
  } else {
    state.rounds_joining = saturate(state.rounds_joining + elapsed);
    if (elapsed > 1) {
      // A countdown heard before a pause is stale.
      state.join_target_known = false;
      state.join_group.clear();
      state.held.clear();
    }
  }
  if (state.status == Status::kJoining) {
    StepJoining(config, state, usable, out, ldmap);
  } else {
    StepMember(config, state, usable, input, out, ldmap);
  }
  out.send = state.status == Status::kMember;
  out.beacon = MakeBeacon(config, state);
}

void BeginStep(SyncState& state, const StepInput& input, StepOutput& out) {
  out.epoch_started = false;
  out.became_joiner = false;
  out.removed.clear();
  out.joined.clear();
  state.live = input.own_snapshot;
}

}  // namespace

void Step(const SyncConfig& config, SyncState& state, std::span<const wire::Beacon> received,
          const StepInput& input, StepOutput& out, LDMap& ldmap) {
  BeginStep(state, input, out);
  UsableBeacons usable(config, received, state.stats);
  StepWith(config, state, usable, input, out, ldmap);
}

void Step(const SyncConfig& config, SyncState& state, std::span<const wire::Beacon* const> received,
          const StepInput& input, StepOutput& out, LDMap& ldmap) {
  BeginStep(state, input, out);
  UsableBeacons usable(config, received, state.stats);
  StepWith(config, state, usable, input, out, ldmap);
}

}  // namespace syrof::sync
