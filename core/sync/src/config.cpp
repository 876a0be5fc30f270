#include "syrof/sync/config.h"

namespace syrof::sync {

const char* ToString(ConfigError error) {
  switch (error) {
    case ConfigError::kOk: return "Ok";
    case ConfigError::kSwarmSizeOutOfRange: return "SwarmSizeOutOfRange";
    case ConfigError::kSelfOutOfRange: return "SelfOutOfRange";
    case ConfigError::kVoteRoundsOutOfRange: return "VoteRoundsOutOfRange";
    case ConfigError::kSilenceNotAboveVote: return "SilenceNotAboveVote";
    case ConfigError::kSilenceTooLong: return "SilenceTooLong";
    case ConfigError::kQuorumNotMajority: return "QuorumNotMajority";
    case ConfigError::kInitialMemberOutOfRange: return "InitialMemberOutOfRange";
  }
  return "?";
}

SyncConfig SyncConfig::ForSwarm(uint16_t swarm_size, uint16_t self_id) {
  SyncConfig config;
  config.swarm_size = swarm_size;
  config.self_id = self_id;
  config.vote_rounds = 3;
  config.silence_rounds = 6;
  config.quorum = static_cast<uint16_t>(swarm_size / 2 + 1);
  for (uint16_t id = 0; id < swarm_size && id < wire::MemberSet::kCapacity; ++id) {
    config.initial_members.set(id);
  }
  return config;
}

ConfigError Validate(const SyncConfig& config) {
  if (config.swarm_size == 0 || config.swarm_size > wire::kMaxSwarmSize) {
    return ConfigError::kSwarmSizeOutOfRange;
  }
  if (config.self_id >= config.swarm_size) return ConfigError::kSelfOutOfRange;
  if (config.vote_rounds == 0 || config.vote_rounds > kMaxVoteRounds) {
    return ConfigError::kVoteRoundsOutOfRange;
  }
  if (config.silence_rounds <= config.vote_rounds) return ConfigError::kSilenceNotAboveVote;
  if (config.silence_rounds > kMaxSilenceRounds) return ConfigError::kSilenceTooLong;
  // Two disjoint sets of robots can never both reach a quorum above N / 2:
  // the heart of the safety argument (docs/protocol.md, "Safety").
  if (config.quorum <= config.swarm_size / 2 || config.quorum > config.swarm_size) {
    return ConfigError::kQuorumNotMajority;
  }
  if (config.initial_members.next_member(config.swarm_size) != wire::MemberSet::kCapacity) {
    return ConfigError::kInitialMemberOutOfRange;
  }
  return ConfigError::kOk;
}

}  // namespace syrof::sync
