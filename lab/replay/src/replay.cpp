#include "syrof/lab/replay/replay.h"

namespace syrof::lab::replay {

const char* ToString(EventKind kind) {
  switch (kind) {
    case EventKind::kEpochStart: return "EPOCH_START";
    case EventKind::kMemberRemoved: return "MEMBER_REMOVED";
    case EventKind::kMemberJoined: return "MEMBER_JOINED";
    case EventKind::kBecameJoiner: return "BECAME_JOINER";
    case EventKind::kCollision: return "COLLISION";
    case EventKind::kWallContact: return "WALL_CONTACT";
    case EventKind::kCrash: return "CRASH";
    case EventKind::kPause: return "PAUSE";
    case EventKind::kResume: return "RESUME";
    case EventKind::kJoin: return "JOIN";
    case EventKind::kPartitionStart: return "PARTITION_START";
    case EventKind::kPartitionEnd: return "PARTITION_END";
    case EventKind::kAppFault: return "APP_FAULT";
    case EventKind::kInvalidCommand: return "INVALID_COMMAND";
    case EventKind::kPayloadRefused: return "PAYLOAD_REFUSED";
    case EventKind::kSafetyIntervention: return "SAFETY_INTERVENTION";
    case EventKind::kJoinWait: return "JOIN_WAIT";
    case EventKind::kBeaconLost: return "BEACON_LOST";
  }
  return "?";
}

const char* ToString(Presence presence) {
  switch (presence) {
    case Presence::kAbsent: return "ABSENT";
    case Presence::kRunning: return "RUNNING";
    case Presence::kPaused: return "PAUSED";
    case Presence::kCrashed: return "CRASHED";
  }
  return "?";
}

}  // namespace syrof::lab::replay
