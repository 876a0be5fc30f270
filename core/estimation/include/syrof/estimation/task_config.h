// Rates and priorities of the estimation tasks and of the sensor drivers that
// feed them, in one place (the firmware, the lab and the tests read them
// here).
//
// Priorities order the tasks the way the paper's FreeRTOS design needs:
// drivers publish, the state task collects what they published, and the
// Kalman task, lowest, runs after both when they are due at the same instant
// (on SimPort, higher priority runs first; on an RTOS it preempts).
#pragma once

#include <cstdint>

namespace syrof::estimation::config {

inline constexpr int64_t kKalmanPeriodNs = 10'000'000;  ///< Kalman task: 100 Hz
inline constexpr int64_t kImuPeriodNs = 10'000'000;     ///< MPU-9250 driver: 100 Hz
inline constexpr int64_t kFlowPeriodNs = 20'000'000;    ///< flow driver: 50 Hz
inline constexpr int64_t kUwbPeriodNs = 100'000'000;    ///< DWM1000 driver: one sweep of every anchor at 10 Hz

inline constexpr uint8_t kSensorTaskPriority = 6;  ///< drivers (and the lab's simulated sensors)
inline constexpr uint8_t kStateTaskPriority = 5;   ///< the state task, notified by every sensor topic
inline constexpr uint8_t kKalmanTaskPriority = 4;  ///< the periodic Kalman task

}  // namespace syrof::estimation::config
