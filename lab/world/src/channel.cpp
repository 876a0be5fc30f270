#include "syrof/lab/world/channel.h"

#include <algorithm>
#include <cmath>
#include <string>

#include "syrof/base/check.h"
#include "syrof/base/split_mix64.h"

namespace syrof::lab::world {
namespace {

// What a draw decides; each purpose is an independent stream.
enum Purpose : uint64_t {
  kLossDraw = 1,        // whether a beacon is lost
  kTransitionDraw = 2,  // a Gilbert-Elliott chain's transition into a round
  kInitialDraw = 3,     // a Gilbert-Elliott chain's state at round 0
};

constexpr uint32_t kBadBit = 0x80000000u;
constexpr uint32_t kRoundMask = 0x7FFFFFFFu;

constexpr uint32_t LinkKey(uint16_t from, uint16_t to) { return (static_cast<uint32_t>(from) << 16) | to; }

bool IsProbability(double value) { return value >= 0 && value <= 1; }

// "NAME must be in [0, 1], not VALUE" at `where` ("" for the spec's own
// fields, whose name says where) when `value` is not a probability.
std::optional<Error> CheckProbability(double value, const std::string& where, const std::string& name) {
  if (IsProbability(value)) return std::nullopt;
  return Error{.where = where, .message = name + " must be in [0, 1], not " + std::to_string(value)};
}

double BadProbability(const ChannelSpec& spec) {
  const double rates = spec.good_to_bad + spec.bad_to_good;
  return rates > 0 ? spec.good_to_bad / rates : 0.0;
}

}  // namespace

const char* ToString(ChannelModel model) {
  switch (model) {
    case ChannelModel::kIid:
      return "iid";
    case ChannelModel::kGilbertElliott:
      return "gilbert_elliott";
    case ChannelModel::kScripted:
      return "scripted";
  }
  return "?";
}

std::optional<Error> CheckChannelSpec(const ChannelSpec& spec, uint16_t robots) {
  for (const auto& [value, name] : {std::pair{spec.loss, "loss"}, std::pair{spec.good_to_bad, "good_to_bad"},
                                    std::pair{spec.bad_to_good, "bad_to_good"}, std::pair{spec.loss_good, "loss_good"},
                                    std::pair{spec.loss_bad, "loss_bad"}}) {
    if (auto problem = CheckProbability(value, "", name)) return problem;
  }
  for (const LinkLossSpec& link : spec.links) {
    const std::string where = "link " + std::to_string(link.from) + " -> " + std::to_string(link.to);
    if (link.from >= robots || link.to >= robots) {
      return Error{.where = where, .message = "names a robot beyond the " + std::to_string(robots) + " robots"};
    }
    if (auto problem = CheckProbability(link.loss, where, "loss")) return problem;
  }
  for (const CutSpec& cut : spec.cuts) {
    const std::string where = "cut " + std::to_string(cut.from) + " -> " + std::to_string(cut.to);
    if (cut.from >= robots || cut.to >= robots) {
      return Error{.where = where, .message = "names a robot beyond the " + std::to_string(robots) + " robots"};
    }
  }
  if (spec.lost.size() > kMaxLostBeacons) {
    return Error{.where = "lost", .message = "lists " + std::to_string(spec.lost.size()) + " beacons; at most " +
                                              std::to_string(kMaxLostBeacons)};
  }
  for (const LostBeacon& beacon : spec.lost) {
    const std::string where = "lost beacon (round " + std::to_string(beacon.round) + ", " +
                              std::to_string(beacon.from) + " -> " + std::to_string(beacon.to) + ")";
    if (beacon.round < 0) return Error{.where = where, .message = "the round must be 0 or more"};
    if (beacon.from >= robots || beacon.to >= robots) {
      return Error{.where = where, .message = "names a robot beyond the " + std::to_string(robots) + " robots"};
    }
    if (beacon.from == beacon.to) return Error{.where = where, .message = "a robot never hears its own beacon"};
  }
  return std::nullopt;
}

double Channel::StationaryLoss(const ChannelSpec& spec) {
  const double bad = BadProbability(spec);
  return bad * spec.loss_bad + (1 - bad) * spec.loss_good;
}

Channel::Channel(const ChannelSpec& spec, uint16_t robots, uint64_t seed)
    : spec_(spec), robots_(robots), seed_(seed) {
  if (const std::optional<Error> problem = CheckChannelSpec(spec, robots)) {
    base::check_failed(("Channel: " + problem->ToString()).c_str(), __FILE__, __LINE__);
  }
  for (const LinkLossSpec& link : spec.links) {
    link_losses_.push_back(LinkLoss{LinkKey(link.from, link.to), link.loss});
  }
  // Stable, then keep the last entry of each key: a later entry overrides.
  std::stable_sort(link_losses_.begin(), link_losses_.end(),
                   [](const LinkLoss& a, const LinkLoss& b) { return a.key < b.key; });
  std::vector<LinkLoss> unique;
  for (const LinkLoss& entry : link_losses_) {
    if (!unique.empty() && unique.back().key == entry.key) {
      unique.back() = entry;
    } else {
      unique.push_back(entry);
    }
  }
  link_losses_.swap(unique);

  for (const PartitionSpec& partition : spec.partitions) {
    const auto unlisted = static_cast<uint16_t>(std::min<size_t>(partition.groups.size(), 0xFFFFu));
    Partition resolved{partition.start_s, partition.end_s, std::vector<uint16_t>(robots, unlisted)};
    for (size_t group = 0; group < partition.groups.size() && group < unlisted; ++group) {
      for (const uint16_t robot : partition.groups[group]) {
        // The first group naming a robot keeps it.
        if (robot < robots && resolved.group[robot] == unlisted) {
          resolved.group[robot] = static_cast<uint16_t>(group);
        }
      }
    }
    partitions_.push_back(std::move(resolved));
  }

  if (spec.model == ChannelModel::kGilbertElliott) {
    chains_.assign(static_cast<size_t>(robots) * robots, 0u);
    const double bad = BadProbability(spec);
    for (uint16_t from = 0; from < robots; ++from) {
      for (uint16_t to = 0; to < robots; ++to) {
        if (Draw(kInitialDraw, 0, from, to) < bad) {
          chains_[static_cast<size_t>(from) * robots + to] = kBadBit;  // round 0
        }
      }
    }
  }
  lost_ = spec_.lost;
  std::sort(lost_.begin(), lost_.end());
  lost_.erase(std::unique(lost_.begin(), lost_.end()), lost_.end());
  plain_iid_ = spec_.model == ChannelModel::kIid && partitions_.empty() && link_losses_.empty() && spec_.cuts.empty();
  // loss * 2^53 is exact; a draw's top 53 bits x (an integer) are below it
  // exactly when they are below its ceiling.
  loss_threshold_ = static_cast<uint64_t>(std::ceil(spec_.loss * 0x1.0p53));
}

double Channel::Draw(uint64_t purpose, int64_t round, uint16_t from, uint16_t to) const {
  uint64_t hash = base::SplitMix64Hash(seed_ ^ base::SplitMix64Hash(purpose));
  hash = base::SplitMix64Hash(hash ^ static_cast<uint64_t>(round));
  hash = base::SplitMix64Hash(hash ^ LinkKey(from, to));
  // The top 53 bits: every double in [0, 1) with that spacing equally likely.
  return static_cast<double>(hash >> 11) * 0x1.0p-53;
}

uint64_t Channel::LossHash(int64_t round, uint16_t from, uint16_t to) {
  if (round != loss_round_) {
    loss_round_ = round;
    loss_round_hash_ = base::SplitMix64Hash(base::SplitMix64Hash(seed_ ^ base::SplitMix64Hash(kLossDraw)) ^
                                            static_cast<uint64_t>(round));
  }
  return base::SplitMix64Hash(loss_round_hash_ ^ LinkKey(from, to));
}

double Channel::LossDraw(int64_t round, uint16_t from, uint16_t to) {
  return static_cast<double>(LossHash(round, from, to) >> 11) * 0x1.0p-53;
}

bool Channel::Partitioned(uint16_t from, uint16_t to, double time_s) const {
  for (const Partition& partition : partitions_) {
    if (partition.start_s <= time_s && time_s < partition.end_s && partition.group[from] != partition.group[to]) {
      return true;
    }
  }
  return false;
}

bool Channel::Cut(uint16_t from, uint16_t to, double time_s) const {
  for (const CutSpec& cut : spec_.cuts) {
    if (cut.start_s <= time_s && time_s < cut.end_s &&
        ((cut.from == from && cut.to == to) || (cut.both_ways && cut.from == to && cut.to == from))) {
      return true;
    }
  }
  return false;
}

bool Channel::ChainBad(uint16_t from, uint16_t to, int64_t round) {
  uint32_t& chain = chains_[static_cast<size_t>(from) * robots_ + to];
  int64_t at = chain & kRoundMask;
  bool bad = (chain & kBadBit) != 0;
  if (round < at) {
    at = 0;
    bad = Draw(kInitialDraw, 0, from, to) < BadProbability(spec_);
  }
  for (int64_t next = at + 1; next <= round; ++next) {
    const double draw = Draw(kTransitionDraw, next, from, to);
    bad = bad ? !(draw < spec_.bad_to_good) : draw < spec_.good_to_bad;
  }
  if (round <= static_cast<int64_t>(kRoundMask)) {
    chain = static_cast<uint32_t>(round) | (bad ? kBadBit : 0u);
  }
  return bad;
}

bool Channel::DeliversSlow(uint16_t from, uint16_t to, int64_t round, double time_s) {
  SYROF_CHECK(from < robots_ && to < robots_);
  SYROF_CHECK(round >= 0);
  ++offered_;
  if (plain_iid_) {
    // The common case, i.i.d. loss on every link, in a round the inline path
    // has no prefix for yet: the same decision as below (LossDraw() < loss,
    // with LossDraw the top 53 bits over 2^53), taken on the integer bits.
    const bool delivered = (LossHash(round, from, to) >> 11) >= loss_threshold_;
    delivered_ += delivered ? 1 : 0;
    return delivered;
  }
  if (Partitioned(from, to, time_s) || Cut(from, to, time_s)) {
    ++partitioned_;
    return false;
  }
  const uint32_t key = LinkKey(from, to);
  const auto link = link_losses_.empty() ? link_losses_.end() : std::lower_bound(link_losses_.begin(), link_losses_.end(), key,
                                     [](const LinkLoss& entry, uint32_t wanted) { return entry.key < wanted; });
  const bool listed = link != link_losses_.end() && link->key == key;
  if (spec_.model == ChannelModel::kScripted) {
    // A listed link keeps its own loss (a dead link stays dead); the script
    // loses its beacons on top.
    const bool delivered = !(listed && LossDraw(round, from, to) < link->loss) &&
                           !std::binary_search(lost_.begin(), lost_.end(), LostBeacon{round, from, to});
    delivered_ += delivered ? 1 : 0;
    return delivered;
  }
  double loss = spec_.loss;
  if (listed) {
    loss = link->loss;
  } else if (spec_.model == ChannelModel::kGilbertElliott) {
    loss = ChainBad(from, to, round) ? spec_.loss_bad : spec_.loss_good;
  }
  const bool delivered = !(LossDraw(round, from, to) < loss);
  delivered_ += delivered ? 1 : 0;
  return delivered;
}

}  // namespace syrof::lab::world
