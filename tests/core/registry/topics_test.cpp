#include "syrof/registry/topics.h"

#include <gtest/gtest.h>

namespace syrof::registry {
namespace {

// The checks that guard topics::kAll, shown to reject the mistakes they are
// there for (the list itself is checked by static_asserts in the header).
TEST(RegistryTopicsTest, TheChecksRejectASharedId) {
  constexpr TopicEntry kClash[] = {{16, "imu"}, {17, "flow"}, {16, "drive"}};
  static_assert(!TopicIdsUnique(kClash));
  constexpr TopicEntry kDistinct[] = {{16, "imu"}, {17, "flow"}, {20, "drive"}};
  static_assert(TopicIdsUnique(kDistinct));
  EXPECT_FALSE(TopicIdsUnique(kClash));
}

TEST(RegistryTopicsTest, TheChecksRejectAnIdOutsideTheBrokersRange) {
  constexpr TopicEntry kTooHigh[] = {{1, "imu"}, {256, "flow"}};
  constexpr TopicEntry kNegative[] = {{-1, "imu"}};
  constexpr TopicEntry kEdges[] = {{0, "first"}, {255, "last"}};
  static_assert(!TopicIdsInRange(kTooHigh));
  static_assert(!TopicIdsInRange(kNegative));
  static_assert(TopicIdsInRange(kEdges));
  EXPECT_FALSE(TopicIdsInRange(kTooHigh));
}

TEST(RegistryTopicsTest, TheChecksRejectASharedName) {
  constexpr TopicEntry kClash[] = {{1, "imu"}, {2, "imu"}};
  constexpr TopicEntry kPrefix[] = {{1, "imu"}, {2, "imu2"}};
  static_assert(!TopicNamesUnique(kClash));
  static_assert(TopicNamesUnique(kPrefix));
  EXPECT_FALSE(TopicNamesUnique(kClash));
}

TEST(RegistryTopicsTest, TheRobotsTopicsAreAllListed) {
  EXPECT_EQ(kTopicCount, 5u);
  EXPECT_TRUE(TopicIdsUnique(topics::kAll));
  EXPECT_TRUE(TopicIdsInRange(topics::kAll));
}

}  // namespace
}  // namespace syrof::registry
