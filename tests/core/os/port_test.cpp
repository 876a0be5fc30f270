#include "syrof/os/port.h"

#include <gtest/gtest.h>

namespace syrof::os {
namespace {

TEST(ValidateTriggerTest, AcceptsPositivePeriodAndNonNegativeOffset) {
  EXPECT_EQ(validate(Trigger::periodic(1)), PortError::kOk);
  EXPECT_EQ(validate(Trigger::periodic(1'000'000, 0)), PortError::kOk);
  EXPECT_EQ(validate(Trigger::notified()), PortError::kOk);
}

TEST(ValidateTriggerTest, RejectsNonPositivePeriodAndNegativeOffset) {
  EXPECT_EQ(validate(Trigger::periodic(0)), PortError::kInvalidTrigger);
  EXPECT_EQ(validate(Trigger::periodic(-5)), PortError::kInvalidTrigger);
  EXPECT_EQ(validate(Trigger::periodic(10, -1)), PortError::kInvalidTrigger);
}

TEST(PortErrorTest, EveryErrorHasADistinctName) {
  const PortError errors[] = {PortError::kOk,           PortError::kTooManyTasks, PortError::kInvalidTrigger,
                              PortError::kAlreadyStarted, PortError::kNotStarted,  PortError::kSystemError};
  for (const PortError a : errors) {
    for (const PortError b : errors) {
      if (a != b) {
        EXPECT_STRNE(to_string(a), to_string(b));
      }
    }
  }
}

}  // namespace
}  // namespace syrof::os
