// The lab's radio channel: whether one robot's beacon of one radio round
// reaches another robot, and the spec it is built from (a scenario holds
// one). Models (ChannelSpec): i.i.d. loss, bursty
// Gilbert-Elliott loss, per-link (asymmetric) loss overrides, and partitions
// in time windows.
//
// Determinism, independent of call order: every random decision is a
// counter-based hash, SplitMix64Hash of (seed, purpose, round, from, to),
// turned into a uniform number in [0, 1). Asking about links or rounds in
// any order, or skipping some, gives the same answers.
//
// Decision for a beacon from `from` to `to` in round r at time t:
//  1. an active partition (start_s <= t < end_s) that puts the two robots in
//     different groups drops it; robots named in none of its groups form one
//     more group together;
//  2. a link listed in `links` is lost with that entry's probability (an
//     i.i.d. draw), whatever the model: for Gilbert-Elliott the entry
//     replaces the chain and both state losses for that link;
//  3. otherwise the model: i.i.d. loss `loss`, or Gilbert-Elliott: the
//     link's two-state chain in its state at round r, lost with loss_good or
//     loss_bad; a scripted channel loses the beacons it lists, on top of
//     step 2 (so a link of loss 1 stays dead under a script).
// Every directed link has its own chain: it starts at round 0 in a state
// drawn from the stationary distribution (bad with probability
// good_to_bad / (good_to_bad + bad_to_good); good when both are 0) and at every round k >= 1 takes
// one transition with its own draw. The chain is advanced lazily, one
// transition per round since the link was last asked (going back in rounds
// replays from round 0), so the state at round r depends only on the seed,
// r and the link.
//
// Memory: with Gilbert-Elliott, 4 bytes per directed link (robots^2),
// allocated at construction; nothing otherwise.
#pragma once

#include <cstdint>
#include <optional>
#include <vector>

#include "syrof/base/split_mix64.h"
#include "syrof/lab/base/error.h"

namespace syrof::lab::world {

enum class ChannelModel : uint8_t {
  kIid = 0,             ///< each beacon on each link lost with probability `loss`
  kGilbertElliott = 1,  ///< per link, a two-state (good/bad) Markov chain stepped once per round
  kScripted = 2,        ///< exactly the beacons listed in `lost` are lost: a run replayed loss by loss
};

const char* ToString(ChannelModel model);

/// Loss on one directed link, replacing the model's loss for it.
struct LinkLossSpec {
  uint16_t from = 0;
  uint16_t to = 0;
  double loss = 0;  ///< probability in [0, 1]
};

/// During [start_s, end_s) beacons between robots of different groups are
/// lost. Robots named in no group form one more group together.
struct PartitionSpec {
  double start_s = 0;
  double end_s = 0;
  std::vector<std::vector<uint16_t>> groups;
};

/// During [start_s, end_s) no beacon from `from` reaches `to` (and none from
/// `to` reaches `from` when `both_ways`): a link cut for a time window.
struct CutSpec {
  uint16_t from = 0;
  uint16_t to = 0;
  double start_s = 0;
  double end_s = 0;
  bool both_ways = false;
};

/// One beacon a scripted channel loses: the one `from` sends in radio round
/// `round` (the round it is sent in, as Delivers counts them), to `to`.
struct LostBeacon {
  int64_t round = 0;
  uint16_t from = 0;
  uint16_t to = 0;
  friend auto operator<=>(const LostBeacon&, const LostBeacon&) = default;
};

/// Most beacons a scripted channel may list.
inline constexpr size_t kMaxLostBeacons = 1'000'000;

struct ChannelSpec {
  ChannelModel model = ChannelModel::kIid;
  double loss = 0;                  ///< iid: per beacon per link
  double good_to_bad = 0.05;        ///< Gilbert-Elliott: per round transition probabilities
  double bad_to_good = 0.5;
  double loss_good = 0;             ///< Gilbert-Elliott: loss in each state
  double loss_bad = 1;
  std::vector<LinkLossSpec> links;  ///< asymmetric per-link overrides
  std::vector<PartitionSpec> partitions;
  std::vector<CutSpec> cuts;        ///< links cut for a time window
  std::vector<LostBeacon> lost;     ///< scripted: the beacons lost (partitions and cuts drop theirs too)
};

/// What Channel's constructor requires: every probability in [0, 1] and
/// every per-link entry naming robots below `robots`. Returns what is wrong
/// and where ("link 0 -> 2: loss must be in [0, 1], not 1.500000"; the
/// spec's own fields have no `where`, their name says it), or nothing. A scenario the loader accepted always passes.
std::optional<Error> CheckChannelSpec(const ChannelSpec& spec, uint16_t robots);

class Channel {
 public:
  /// Requires CheckChannelSpec(spec, robots) to pass; anything else is a
  /// caller's bug and stops the program (SYROF_CHECK, with the check's
  /// message). Robots named in partitions beyond `robots` are ignored. A link
  /// listed twice takes its last entry.
  Channel(const ChannelSpec& spec, uint16_t robots, uint64_t seed);

  /// Whether the beacon robot `from` sends in radio round `round` (>= 0),
  /// starting at `time_s`, reaches robot `to`. A robot >= robots() or a
  /// negative round is a caller's bug (SYROF_CHECK).
  bool Delivers(uint16_t from, uint16_t to, int64_t round, double time_s) {
    // The common case inline (every link of a swarm asks each round): i.i.d.
    // loss on every link, a round whose hash prefix is known. The decision
    // is DeliversSlow's, on the integer bits.
    if (plain_iid_ && round == loss_round_ && round >= 0 && from < robots_ && to < robots_) {
      ++offered_;
      const uint64_t link = (static_cast<uint64_t>(from) << 16) | to;
      const bool delivered = (base::SplitMix64Hash(loss_round_hash_ ^ link) >> 11) >= loss_threshold_;
      delivered_ += delivered ? 1 : 0;
      return delivered;
    }
    return DeliversSlow(from, to, round, time_s);
  }

  uint16_t robots() const { return robots_; }
  /// Beacons asked about, and delivered, since construction.
  uint64_t offered() const { return offered_; }
  uint64_t delivered() const { return delivered_; }
  /// Beacons dropped by a partition or a cut (included in offered, not delivered).
  uint64_t partitioned() const { return partitioned_; }

  /// Long-run loss of a Gilbert-Elliott link:
  /// pi_bad * loss_bad + pi_good * loss_good.
  static double StationaryLoss(const ChannelSpec& spec);

 private:
  struct Partition {
    double start_s;
    double end_s;
    std::vector<uint16_t> group;  // group of each robot; unlisted robots share the last
  };
  struct LinkLoss {
    uint32_t key;  // (from << 16) | to
    double loss;
  };

  // Uniform in [0, 1) from the hash of (seed, purpose, round, from, to).
  double Draw(uint64_t purpose, int64_t round, uint16_t from, uint16_t to) const;
  // The same number as Draw(kLossDraw, round, from, to), reusing the
  // round's prefix.
  double LossDraw(int64_t round, uint16_t from, uint16_t to);
  uint64_t LossHash(int64_t round, uint16_t from, uint16_t to);
  bool DeliversSlow(uint16_t from, uint16_t to, int64_t round, double time_s);
  bool Partitioned(uint16_t from, uint16_t to, double time_s) const;
  bool Cut(uint16_t from, uint16_t to, double time_s) const;
  // Whether the Gilbert-Elliott chain of the link is bad at `round`.
  bool ChainBad(uint16_t from, uint16_t to, int64_t round);

  ChannelSpec spec_;
  uint16_t robots_;
  uint64_t seed_;
  std::vector<Partition> partitions_;
  std::vector<LinkLoss> link_losses_;  // sorted by key, one per link
  std::vector<LostBeacon> lost_;       // scripted: sorted, no repeats
  // Gilbert-Elliott, one per directed link (from * robots + to): bit 31 is
  // "bad", bits 0..30 the round the state is for (states of rounds past
  // 2^31 - 1 are not stored but recomputed each time: correct, only slower).
  std::vector<uint32_t> chains_;
  // The hash prefix of (seed, purpose, round) for the last round a loss was
  // drawn for: every link of a round shares it, so a draw costs one hash.
  bool plain_iid_ = false;   // i.i.d. loss, no partition, no per-link loss
  // ceil(loss * 2^53): a draw's top 53 bits x lose the beacon exactly when
  // x < loss_threshold_ (x < loss * 2^53, which is exact).
  uint64_t loss_threshold_ = 0;
  int64_t loss_round_ = -1;
  uint64_t loss_round_hash_ = 0;
  uint64_t offered_ = 0;
  uint64_t delivered_ = 0;
  uint64_t partitioned_ = 0;
};

}  // namespace syrof::lab::world
