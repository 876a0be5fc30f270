#include "syrof/registry/tasks.h"

#include <gtest/gtest.h>

namespace syrof::registry {
namespace {

TEST(RegistryTasksTest, TheOrderCheckRejectsASwapAndATie) {
  constexpr uint8_t kSwapped[] = {9, 8, 5, 6, 4};  // state task above the drivers
  constexpr uint8_t kTied[] = {9, 8, 6, 6, 4};     // same level: order falls back to registration
  constexpr uint8_t kGood[] = {9, 8, 6, 5, 4};
  static_assert(!StrictlyDecreasing(kSwapped));
  static_assert(!StrictlyDecreasing(kTied));
  static_assert(StrictlyDecreasing(kGood));
  EXPECT_FALSE(StrictlyDecreasing(kSwapped));
  EXPECT_FALSE(StrictlyDecreasing(kTied));
}

TEST(RegistryTasksTest, TheRobotsTasksRunInDataFlowOrder) {
  EXPECT_GT(kSensorTaskPriority, kStateTaskPriority);
  EXPECT_GT(kStateTaskPriority, kKalmanTaskPriority);
  EXPECT_GT(kKalmanTaskPriority, kRadioDeliveryPriority);
  EXPECT_GT(kRadioDeliveryPriority, kRoundTaskPriority);
  EXPECT_GT(kRoundTaskPriority, kMotionTaskPriority);
  EXPECT_EQ(kMotionPeriodNs, kKalmanPeriodNs);
}

}  // namespace
}  // namespace syrof::registry
