#include "syrof/os/port.h"

#include <gtest/gtest.h>

namespace syrof::os {
namespace {

TEST(ValidateTriggerTest, AcceptsPositivePeriodAndNonNegativeOffset) {
  EXPECT_EQ(Validate(Trigger::periodic(1)), PortError::kOk);
  EXPECT_EQ(Validate(Trigger::periodic(1'000'000, 0)), PortError::kOk);
  EXPECT_EQ(Validate(Trigger::notified()), PortError::kOk);
}

TEST(ValidateTriggerTest, RejectsNonPositivePeriodAndNegativeOffset) {
  EXPECT_EQ(Validate(Trigger::periodic(0)), PortError::kInvalidTrigger);
  EXPECT_EQ(Validate(Trigger::periodic(-5)), PortError::kInvalidTrigger);
  EXPECT_EQ(Validate(Trigger::periodic(10, -1)), PortError::kInvalidTrigger);
}

TEST(PortErrorTest, EveryErrorHasADistinctName) {
  const PortError errors[] = {PortError::kOk,           PortError::kTooManyTasks, PortError::kInvalidTrigger,
                              PortError::kAlreadyStarted, PortError::kNotStarted,  PortError::kSystemError};
  for (const PortError a : errors) {
    for (const PortError b : errors) {
      if (a != b) {
        EXPECT_STRNE(ToString(a), ToString(b));
      }
    }
  }
}

}  // namespace
}  // namespace syrof::os
