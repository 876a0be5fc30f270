// Checks every Port implementation must pass, shared by the port tests.
#pragma once

#include <gtest/gtest.h>

#include "syrof/os/port.h"

namespace syrof::os::testing {

/// A task that does nothing, for lifecycle checks.
class IdleTask final : public Task {
 public:
  void Step(int64_t) override {}
};

/// Drives a fresh port with room for exactly one task through every
/// lifecycle error: kInvalidTrigger, kNotStarted, kTooManyTasks,
/// kAlreadyStarted (twice: Start and AddTask after Start).
inline void ExpectEachLifecycleError(Port& port_with_one_task_slot) {
  Port& port = port_with_one_task_slot;
  IdleTask first, second;

  EXPECT_EQ(port.AddTask(first, {"bad", Trigger::periodic(0), 0}).error(), PortError::kInvalidTrigger);
  EXPECT_EQ(port.AddTask(first, {"bad", Trigger::periodic(10, -1), 0}).error(), PortError::kInvalidTrigger);
  EXPECT_EQ(port.Stop(), PortError::kNotStarted);
  ASSERT_TRUE(port.AddTask(first, {"first", Trigger::notified(), 0}));
  EXPECT_EQ(port.AddTask(second, {"second", Trigger::notified(), 0}).error(), PortError::kTooManyTasks);
  ASSERT_EQ(port.Start(), PortError::kOk);
  EXPECT_EQ(port.Start(), PortError::kAlreadyStarted);
  EXPECT_EQ(port.AddTask(second, {"second", Trigger::notified(), 0}).error(), PortError::kAlreadyStarted);
  EXPECT_EQ(port.Stop(), PortError::kOk);
}

}  // namespace syrof::os::testing
