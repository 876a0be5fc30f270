#include "nearest_name.h"

#include <gtest/gtest.h>

#include <string_view>

namespace syrof::lab::scenario {
namespace {

TEST(EditDistance, CountsInsertionsDeletionsAndSubstitutions) {
  EXPECT_EQ(EditDistance("", ""), 0u);
  EXPECT_EQ(EditDistance("abc", ""), 3u);
  EXPECT_EQ(EditDistance("", "ab"), 2u);
  EXPECT_EQ(EditDistance("kitten", "sitting"), 3u);
  EXPECT_EQ(EditDistance("robtos", "robots"), 2u);
  EXPECT_EQ(EditDistance("count", "count"), 0u);
}

TEST(NearestName, SuggestsTheClosestCandidateWhenClose) {
  constexpr std::string_view kCandidates[] = {"count", "kind", "placement"};
  EXPECT_EQ(NearestName("cuont", kCandidates), "count");
  EXPECT_EQ(NearestName("placment", kCandidates), "placement");
}

TEST(NearestName, SuggestsNothingWhenFar) {
  constexpr std::string_view kCandidates[] = {"count", "kind", "placement"};
  EXPECT_EQ(NearestName("velocity", kCandidates), "");
}

TEST(JoinNames, SeparatesWithCommas) {
  constexpr std::string_view kCandidates[] = {"a", "b", "c"};
  EXPECT_EQ(JoinNames(kCandidates), "a, b, c");
}

}  // namespace
}  // namespace syrof::lab::scenario
