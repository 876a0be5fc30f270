// Every task priority and rate of a robot, and of the lab's world tasks that
// run beside it, in one table with compile-time checks of the order they must
// keep.
//
// Priorities decide who runs first when several tasks are due at one instant:
// on SimPort the higher priority runs first (docs/os.md), on an RTOS it
// preempts. So the order below is the data flow of one instant, and each step
// depends on the one before it:
//
//   faults (9)          lab: a crash, pause or join takes effect before
//                       anything moves or is measured at that instant.
//   physics (8)         lab: bodies move to the instant's true state, which
//                       the sensors then measure.
//   sensor drivers (6)  publish the IMU, flow and UWB readings of the instant
//                       (the MPU-9250, flow and DWM1000 drivers, or the lab's
//                       simulated sensors).
//   state task (5)      collects what the drivers just published, so the
//                       Kalman step due at the same instant fuses it.
//   Kalman task (4)     predicts, fuses, publishes the estimate of the instant.
//   radio delivery (3)  delivers the previous round's beacons (the radio
//                       driver, or the lab's channel) before the round ends.
//   round task (2)      one synchronizer step: it sees every beacon of the
//                       round and the newest estimate.
//   motion task (1)     the controller acts on the command the round just set
//                       and the newest estimate.
//   recorder (0)        lab: metrics and replay see the instant after every
//                       robot task ran.
//
// Priority 7 is free: nothing sits between physics and the drivers.
#pragma once

#include <cstddef>
#include <cstdint>

namespace syrof::registry {

// --- Priorities, highest first ---------------------------------------------
inline constexpr uint8_t kFaultPriority = 9;          ///< lab: faults (crash, pause, join)
inline constexpr uint8_t kPhysicsPriority = 8;        ///< lab: bodies, contacts
inline constexpr uint8_t kSensorTaskPriority = 6;     ///< sensor drivers (and the lab's simulated sensors)
inline constexpr uint8_t kStateTaskPriority = 5;      ///< estimator's state task, notified by every sensor topic
inline constexpr uint8_t kKalmanTaskPriority = 4;     ///< estimator's periodic Kalman task
inline constexpr uint8_t kRadioDeliveryPriority = 3;  ///< delivers the previous round's beacons
inline constexpr uint8_t kRoundTaskPriority = 2;      ///< one synchronizer step per radio round
inline constexpr uint8_t kMotionTaskPriority = 1;     ///< controller -> drive command
inline constexpr uint8_t kRecorderPriority = 0;       ///< lab: metrics and replay

/// The priorities in the order the header comment gives, highest first.
inline constexpr uint8_t kPriorityOrder[] = {
    kFaultPriority,     kPhysicsPriority,       kSensorTaskPriority, kStateTaskPriority, kKalmanTaskPriority,
    kRadioDeliveryPriority, kRoundTaskPriority, kMotionTaskPriority, kRecorderPriority,
};

// --- Rates -------------------------------------------------------------------
inline constexpr int64_t kKalmanPeriodNs = 10'000'000;  ///< Kalman task: 100 Hz
inline constexpr int64_t kImuPeriodNs = 10'000'000;     ///< MPU-9250 driver: 100 Hz
inline constexpr int64_t kFlowPeriodNs = 20'000'000;    ///< flow driver: 50 Hz
inline constexpr int64_t kUwbPeriodNs = 100'000'000;    ///< DWM1000 driver: one sweep of every anchor at 10 Hz
inline constexpr int64_t kMotionPeriodNs = 10'000'000;  ///< motion task: 100 Hz, with the Kalman task
inline constexpr int64_t kDefaultRadioRoundNs = 50'000'000;  ///< alpha, the paper's 50 ms

/// Whether `order` is strictly decreasing: no two tasks share a level, so
/// the same-instant order never falls back to registration order.
template <size_t N>
constexpr bool StrictlyDecreasing(const uint8_t (&order)[N]) {
  for (size_t i = 1; i < N; ++i) {
    if (order[i] >= order[i - 1]) return false;
  }
  return true;
}

static_assert(StrictlyDecreasing(kPriorityOrder),
              "priorities must run faults > physics > sensor drivers > state > Kalman > radio delivery > round > "
              "motion > recorder (see the comment above)");

// The motion task acts on every estimate: one step per Kalman step.
static_assert(kMotionPeriodNs == kKalmanPeriodNs, "the motion task runs with the Kalman task");
// The Kalman task averages the IMU samples since its last step: at least one
// per step, and a whole number of them.
static_assert(kKalmanPeriodNs % kImuPeriodNs == 0, "the Kalman period is a whole number of IMU periods");
// The lab's simulated sensors run as one task at the IMU rate and emit flow
// and UWB when due: their periods must be multiples of it.
static_assert(kFlowPeriodNs % kImuPeriodNs == 0 && kUwbPeriodNs % kImuPeriodNs == 0,
              "every sensor period is a whole number of IMU periods");
// A radio round ends on a Kalman step, so the round task sees the estimate of
// its instant.
static_assert(kDefaultRadioRoundNs % kKalmanPeriodNs == 0, "a radio round is a whole number of Kalman periods");

}  // namespace syrof::registry
