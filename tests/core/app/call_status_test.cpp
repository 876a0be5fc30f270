#include "syrof/app/call_status.h"

#include <gtest/gtest.h>

#include <cstring>
#include <string>

namespace syrof::app {
namespace {

TEST(CallStatusTest, OkHasNoVerdictAndNoDetail) {
  const CallStatus status = CallStatus::Ok();

  EXPECT_TRUE(status.ok());
  EXPECT_EQ(status.verdict(), Verdict::kOk);
  EXPECT_STREQ(status.detail(), "");
}

TEST(CallStatusTest, FaultKeepsItsVerdictAndDetail) {
  const CallStatus status = CallStatus::Fault(Verdict::kForbiddenSyscall, "openat");

  EXPECT_FALSE(status.ok());
  EXPECT_EQ(status.verdict(), Verdict::kForbiddenSyscall);
  EXPECT_STREQ(status.detail(), "openat");
}

TEST(CallStatusTest, ALongDetailIsTruncatedAndTerminated) {
  const std::string long_detail(200, 'x');

  const CallStatus status = CallStatus::Fault(Verdict::kAppError, long_detail.c_str());

  EXPECT_EQ(std::strlen(status.detail()), CallStatus::kDetailBytes - 1);
  EXPECT_EQ(std::string(status.detail()), long_detail.substr(0, CallStatus::kDetailBytes - 1));
}

TEST(CallStatusTest, ANullDetailIsEmpty) {
  EXPECT_STREQ(CallStatus::Fault(Verdict::kTimeout, nullptr).detail(), "");
}

TEST(CallStatusTest, EveryVerdictAndCallbackHasItsName) {
  EXPECT_STREQ(ToString(Verdict::kOk), "ok");
  EXPECT_STREQ(ToString(Verdict::kAppError), "app_error");
  EXPECT_STREQ(ToString(Verdict::kCrashed), "crashed");
  EXPECT_STREQ(ToString(Verdict::kTimeout), "timeout");
  EXPECT_STREQ(ToString(Verdict::kExited), "exited");
  EXPECT_STREQ(ToString(Verdict::kMemory), "memory");
  EXPECT_STREQ(ToString(Verdict::kForbiddenSyscall), "forbidden_syscall");
  EXPECT_STREQ(ToString(Verdict::kOutputLimit), "output_limit");
  EXPECT_STREQ(ToString(Verdict::kBadAbi), "bad_abi");
  EXPECT_STREQ(ToString(Verdict::kLoadFailed), "load_failed");
  EXPECT_STREQ(ToString(static_cast<Verdict>(static_cast<uint8_t>(kLastVerdict) + 1)), "?");
  EXPECT_STREQ(ToString(Callback::kInit), "init");
  EXPECT_STREQ(ToString(Callback::kNewRound), "new_round");
  EXPECT_STREQ(ToString(Callback::kEndOfRound), "end_of_round");
}

}  // namespace
}  // namespace syrof::app
