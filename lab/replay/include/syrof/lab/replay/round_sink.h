// A reader of a run's replay as it is recorded, in the replay's own terms
// (replay.h): the header once, then every round, then the end. The live
// page (`--live`, docs/viewer.md) and the base station's bridge
// (`syrof-bridge`) watch a run through one; every runtime's RoundRecorder
// (lab/sim/round_recorder.h) feeds the sinks it was given with what it
// writes to the replay, whether or not a replay file is written.
//
// The calls come on the recording thread, in the run's time: a sink must
// not block (copy what it needs and hand it off). The spans are read during
// the call only.
#pragma once

#include <cstdint>
#include <span>

#include "syrof/lab/replay/replay.h"

namespace syrof::lab::replay {

class RoundSink {
 public:
  virtual ~RoundSink() = default;
  /// The run's header, before any round.
  virtual void OnHeader(const Header& header) = 0;
  /// One radio round, as Writer::WriteRound takes it (same contracts:
  /// frames in increasing id order, maps in increasing robot order).
  virtual void OnRound(uint32_t index, int64_t time_ns, std::span<const RobotFrame> robots,
                       std::span<const Event> events, std::span<const RobotMap> maps) = 0;
  /// The run ended (`complete`: it ran to its end, not stopped by an error).
  virtual void OnFinish(bool complete) = 0;
};

}  // namespace syrof::lab::replay
