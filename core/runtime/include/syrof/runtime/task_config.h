// Rates and priorities of the robot runtime's tasks, in one place. The
// estimation tasks' own values live in syrof/estimation/task_config.h; these
// sit below them, so at an instant where several are due the order is:
// sensor drivers (6), state task (5), Kalman task (4), radio delivery (3,
// the runtime's radio driver or the lab's channel), round task (2), motion
// task (1). The round task therefore sees every beacon of the round and the
// newest estimate, and the motion task the command the round just set.
#pragma once

#include <cstdint>

namespace syrof::runtime::config {

inline constexpr uint8_t kRadioDeliveryPriority = 3;  ///< delivers the previous round's beacons
inline constexpr uint8_t kRoundTaskPriority = 2;      ///< one synchronizer step per radio round
inline constexpr uint8_t kMotionTaskPriority = 1;     ///< controller -> drive command

inline constexpr int64_t kMotionPeriodNs = 10'000'000;       ///< 100 Hz, with the Kalman task
inline constexpr int64_t kDefaultRadioRoundNs = 50'000'000;  ///< alpha, the paper's 50 ms

}  // namespace syrof::runtime::config
