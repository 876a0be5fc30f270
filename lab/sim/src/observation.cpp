#include "syrof/lab/sim/observation.h"

namespace syrof::lab::sim {

RobotObservation Observe(uint16_t id, replay::Presence presence, const sync::SyncState& state,
                         const world::BodyState& body, const estimation::StateEstimate& estimate,
                         bool estimate_warm) {
  RobotObservation observation;
  observation.id = id;
  observation.presence = presence;
  observation.status = state.status;
  observation.phase = state.phase;
  observation.epoch = state.epoch;
  observation.epoch_mode = state.epoch_mode;
  observation.estimate_warm = estimate_warm;
  observation.true_x_m = body.x_m;
  observation.true_y_m = body.y_m;
  observation.true_heading_rad = body.heading_rad;
  observation.est_x_m = estimate.x_m;
  observation.est_y_m = estimate.y_m;
  observation.est_heading_rad = estimate.heading_rad;
  return observation;
}

metrics::RobotRound ToRobotRound(const RobotObservation& observation) {
  metrics::RobotRound record;
  record.id = observation.id;
  record.running = observation.running();
  record.member = observation.running() && observation.status == sync::Status::kMember;
  record.paused = observation.presence == replay::Presence::kPaused;
  record.sync_member = observation.status == sync::Status::kMember;
  record.epoch = observation.epoch;
  record.epoch_mode = observation.epoch_mode;
  record.phase = observation.phase;
  record.estimate_valid = observation.running() && observation.estimate_warm;
  record.true_x_m = observation.true_x_m;
  record.true_y_m = observation.true_y_m;
  record.est_x_m = observation.est_x_m;
  record.est_y_m = observation.est_y_m;
  return record;
}

replay::RobotFrame ToRobotFrame(const RobotObservation& observation) {
  replay::RobotFrame frame;
  frame.id = observation.id;
  frame.presence = observation.presence;
  frame.status = static_cast<uint8_t>(observation.status);
  frame.phase = static_cast<uint8_t>(observation.phase);
  frame.mode = static_cast<uint8_t>(observation.epoch_mode);
  frame.epoch = observation.epoch;
  frame.true_x_m = static_cast<float>(observation.true_x_m);
  frame.true_y_m = static_cast<float>(observation.true_y_m);
  frame.true_heading_rad = static_cast<float>(observation.true_heading_rad);
  frame.est_x_m = observation.est_x_m;
  frame.est_y_m = observation.est_y_m;
  frame.est_heading_rad = observation.est_heading_rad;
  return frame;
}

}  // namespace syrof::lab::sim
