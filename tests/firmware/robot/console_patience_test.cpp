// ConsolePatience (firmware/robot/console_patience.h): the console writer
// gives up after 200 ms of waiting while it runs, not because the guest was
// stopped from outside for a while.
#include "syrof/firmware/robot/console_patience.h"

#include <gtest/gtest.h>

namespace syrof::firmware::robot {
namespace {

constexpr int64_t kMs = 1'000'000;

TEST(ConsolePatienceTest, GivesUpAfter200MsOfWaitingWithoutProgress) {
  ConsolePatience patience(0);
  int64_t now = 0;
  bool exhausted = false;
  while (!exhausted && now < 1000 * kMs) {
    now += kMs;
    exhausted = patience.Exhausted(now, false);
  }
  EXPECT_TRUE(exhausted);
  EXPECT_EQ(now, 201 * kMs);
}

TEST(ConsolePatienceTest, AStopFromOutsideLongerThanThePatienceDoesNotUseItUp) {
  ConsolePatience patience(0);
  EXPECT_FALSE(patience.Exhausted(1 * kMs, false));
  // The qemu was stopped for 300 ms: its clock jumped between two checks.
  EXPECT_FALSE(patience.Exhausted(301 * kMs, false));
  EXPECT_FALSE(patience.Exhausted(302 * kMs, true));  // the ring drained
}

TEST(ConsolePatienceTest, ProgressStartsTheWaitOver) {
  ConsolePatience patience(0);
  int64_t now = 0;
  for (; now < 150 * kMs; now += kMs) EXPECT_FALSE(patience.Exhausted(now, false));
  EXPECT_FALSE(patience.Exhausted(now, true));
  for (int k = 0; k < 150; ++k) EXPECT_FALSE(patience.Exhausted(now += kMs, false));
}

}  // namespace
}  // namespace syrof::firmware::robot
