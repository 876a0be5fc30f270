#include "syrof/base/result.h"

#include <gtest/gtest.h>

namespace syrof::base {
namespace {

enum class ParseError : unsigned char { kOk = 0, kEmpty, kTooLong };

Result<int, ParseError> parse_length(int length) {
  if (length == 0) return ParseError::kEmpty;
  if (length > 9) return ParseError::kTooLong;
  return length * 2;
}

TEST(ResultTest, HoldsValueOnSuccess) {
  const auto result = parse_length(3);

  ASSERT_TRUE(result.ok());
  EXPECT_EQ(result.error(), ParseError::kOk);
  EXPECT_EQ(result.value(), 6);
}

TEST(ResultTest, HoldsTheDistinctErrorOnFailure) {
  EXPECT_EQ(parse_length(0).error(), ParseError::kEmpty);
  EXPECT_EQ(parse_length(10).error(), ParseError::kTooLong);
  EXPECT_FALSE(parse_length(10));
}

}  // namespace
}  // namespace syrof::base
