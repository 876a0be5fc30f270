// What the lab sees of one robot at the end of a radio round, once, feeding
// both the metrics (metrics::RobotRound) and the replay (replay::RobotFrame):
// the two are derived from the same observation, so they cannot disagree.
#pragma once

#include <cstdint>

#include "syrof/estimation/messages.h"
#include "syrof/lab/metrics/collector.h"
#include "syrof/lab/replay/replay.h"
#include "syrof/lab/world/world.h"
#include "syrof/sync/synchronizer.h"

namespace syrof::lab::sim {

/// One robot at the end of one radio round.
struct RobotObservation {
  uint16_t id = 0;
  replay::Presence presence = replay::Presence::kAbsent;  ///< RUNNING, PAUSED, CRASHED or ABSENT
  sync::Status status = sync::Status::kJoining;           ///< its synchronizer's, whether it runs or not
  wire::Phase phase = wire::Phase::kWait;
  uint16_t epoch = 0;
  wire::Mode epoch_mode = wire::Mode::kAutonomous;  ///< the mode its current epoch started in
  /// The estimator is initialized and past its warm-up since the robot
  /// (re)started, whether or not the robot runs now.
  bool estimate_warm = false;
  double true_x_m = 0;  ///< ground truth (the world's body), arena frame
  double true_y_m = 0;
  double true_heading_rad = 0;
  float est_x_m = 0;  ///< the robot's own estimate, arena frame
  float est_y_m = 0;
  float est_heading_rad = 0;

  bool running() const { return presence == replay::Presence::kRunning; }
};

/// Observes a robot from its synchronizer state, its body and its estimate.
RobotObservation Observe(uint16_t id, replay::Presence presence, const sync::SyncState& state,
                         const world::BodyState& body, const estimation::StateEstimate& estimate,
                         bool estimate_warm);

/// The metrics' view: a robot that does not run is neither a member nor
/// scored, whatever its frozen state says.
metrics::RobotRound ToRobotRound(const RobotObservation& observation);

/// The replay's view: everything as observed, poses in float.
replay::RobotFrame ToRobotFrame(const RobotObservation& observation);

}  // namespace syrof::lab::sim
