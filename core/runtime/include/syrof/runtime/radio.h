// The robot's radio edge, outgoing side: where its beacons go.
//
// A robot hands its beacon to a Radio once per radio round; the Radio puts
// it on the air. Implementations: the lab's radio network (lab/sim), a DDS
// writer (sim_dds), the UART to the radio chip (firmware), a test's loopback.
//
// The incoming side is on Robot: Receive() (a decoded beacon, same thread as
// the round task) and ReceiveBytes() (a frame, from any thread or an
// interrupt); see robot.h.
#pragma once

#include "syrof/wire/beacon.h"

namespace syrof::runtime {

/// Where the robot's beacons go: the lab's channel, DDS, or the radio chip.
///
/// Contract:
///   - Who calls: the robot's round task (Robot::RunRound), in the port's
///     task context, at most once per radio round, at the end of the round's
///     step. Never from an interrupt, never concurrently with itself for the
///     same robot.
///   - Ownership: `beacon` belongs to the robot and is valid only during the
///     call; an implementation that sends later copies it (or encodes it to
///     bytes with wire::Encode) before returning.
///   - Bounds: Broadcast must return in bounded time and must not block (it
///     runs inside a run-to-completion task): queue the frame, do not wait
///     for the medium. It may drop the beacon (a full queue is a lost radio
///     frame, which the synchronizer tolerates).
///   - Lifetime: the Radio outlives the Robot that uses it.
class Radio {
 public:
  /// Sends this round's beacon. Called from the round task, once per round
  /// at most.
  virtual void Broadcast(const wire::Beacon& beacon) = 0;

 protected:
  ~Radio() = default;
};

}  // namespace syrof::runtime
