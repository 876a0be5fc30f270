#include "syrof/wire/member_set.h"

#include <gtest/gtest.h>

#include <algorithm>
#include <bit>
#include <iterator>
#include <ranges>
#include <vector>

namespace syrof::wire {
namespace {

// The Teensy build has the smallest capacity the project uses.
static_assert(MemberSet::kCapacity >= 32, "these tests name members up to 31");

constexpr uint16_t kLast = MemberSet::kCapacity - 1;

static_assert(std::forward_iterator<MemberSet::Iterator>);
static_assert(std::ranges::forward_range<MemberSet>);

TEST(MemberSetTest, StartsEmpty) {
  const MemberSet set;

  EXPECT_TRUE(set.empty());
  EXPECT_EQ(set.count(), 0);
  EXPECT_EQ(set.begin(), set.end());
}

TEST(MemberSetTest, SetAndResetChangeOnlyTheirMember) {
  MemberSet set;

  set.set(0);
  set.set(kLast);
  set.set(kLast);
  set.reset(0);

  EXPECT_FALSE(set.test(0));
  EXPECT_TRUE(set.test(kLast));
  EXPECT_EQ(set.count(), 1);
}

TEST(MemberSetTest, TestIsFalseBeyondCapacity) {
  const MemberSet set;

  EXPECT_FALSE(set.test(MemberSet::kCapacity));
  EXPECT_FALSE(set.test(65535));
}

TEST(MemberSetTest, AnyAtOrAboveSeesOnlyMembersFromTheBound) {
  MemberSet set;
  set.set(5);
  set.set(MemberSet::kCapacity - 1);

  EXPECT_TRUE(set.any_at_or_above(0));
  EXPECT_TRUE(set.any_at_or_above(5));
  EXPECT_TRUE(set.any_at_or_above(6));  // the last member
  set.reset(MemberSet::kCapacity - 1);
  EXPECT_TRUE(set.any_at_or_above(5));
  EXPECT_FALSE(set.any_at_or_above(6));
  EXPECT_FALSE(set.any_at_or_above(MemberSet::kCapacity));
  EXPECT_FALSE(MemberSet{}.any_at_or_above(0));
}

TEST(MemberSetTest, SetsWithTheSameMembersAreEqualWhateverTheirHistory) {
  MemberSet emptied;
  emptied.set(MemberSet::kCapacity - 1);
  emptied.set(3);
  emptied.reset(MemberSet::kCapacity - 1);
  MemberSet direct;
  direct.set(3);

  EXPECT_EQ(emptied, direct);
  EXPECT_EQ(direct, emptied);
  EXPECT_EQ(emptied.count(), 1);
  EXPECT_FALSE(emptied.any_at_or_above(4));
  emptied.reset(3);
  EXPECT_TRUE(emptied.empty());
  EXPECT_EQ(emptied, MemberSet{});
}

TEST(MemberSetTest, UnionIntersectionAndIncludesSeeHighMembers) {
  MemberSet low;
  low.set(1);
  MemberSet high;
  high.set(1);
  high.set(MemberSet::kCapacity - 1);

  EXPECT_FALSE(low.includes(high));
  EXPECT_TRUE(high.includes(low));
  low |= high;
  EXPECT_TRUE(low.test(MemberSet::kCapacity - 1));
  EXPECT_EQ(low, high);
  MemberSet only_low;
  only_low.set(1);
  high &= only_low;
  EXPECT_EQ(high, only_low);
  EXPECT_EQ(high.next_member(2), MemberSet::kCapacity);
}

TEST(MemberSetTest, DifferenceRemovesOnlyTheOthersMembersInEveryWord) {
  // The middle member is in the second word when the capacity allows one.
  constexpr uint16_t kMiddle = MemberSet::kCapacity / 2 + 1;
  MemberSet a;
  a.set(1);
  a.set(kMiddle);
  a.set(MemberSet::kCapacity - 1);
  MemberSet b;
  b.set(kMiddle);
  b.set(2);
  a -= b;
  EXPECT_TRUE(a.test(1));
  EXPECT_FALSE(a.test(kMiddle));
  EXPECT_TRUE(a.test(MemberSet::kCapacity - 1));
  EXPECT_FALSE(a.test(2));
  EXPECT_EQ(a.count(), 2);
  MemberSet all = a;
  all -= a;
  EXPECT_TRUE(all.empty());
  EXPECT_EQ(all, MemberSet{});
}

TEST(MemberSetTest, WordsHoldThirtyTwoMembersLowBitFirst) {
  MemberSet set;
  EXPECT_EQ(set.word_count(), 0u);
  EXPECT_EQ(set.word(0), 0u);
  set.set(0);
  set.set(5);
  set.set(kLast);
  const size_t last_word = kLast / MemberSet::kWordBits;
  EXPECT_EQ(set.word_count(), last_word + 1);
  EXPECT_EQ(set.word(0) & 0x21u, 0x21u);
  EXPECT_EQ(set.word(last_word) >> (kLast % MemberSet::kWordBits), 1u);
  EXPECT_EQ(set.word(last_word + 1), 0u);  // past the used words
  size_t members = 0;
  for (size_t w = 0; w < set.word_count(); ++w) members += static_cast<size_t>(std::popcount(set.word(w)));
  EXPECT_EQ(members, set.count());
}

// == and includes() read every word, with no early exit: a difference in
// any word, the last one too, still counts.
TEST(MemberSetTest, EqualityAndInclusionSeeADifferenceInAnyWord) {
  MemberSet full;
  for (uint16_t id = 0; id <= kLast; ++id) full.set(id);
  for (const uint16_t missing : {uint16_t{0}, uint16_t{31}, uint16_t(kLast / 2), kLast}) {
    MemberSet holed = full;
    holed.reset(missing);
    EXPECT_NE(holed, full) << missing;
    EXPECT_NE(full, holed) << missing;
    EXPECT_TRUE(full.includes(holed)) << missing;
    EXPECT_FALSE(holed.includes(full)) << missing;
  }
}

TEST(MemberSetTest, BytesSetAnywhereAreSeen) {
  MemberSet set;
  set.set_byte(MemberSet::kBytes - 1, 0x01);

  EXPECT_TRUE(set.test(static_cast<uint16_t>(8 * (MemberSet::kBytes - 1))));
  EXPECT_EQ(set.count(), 1);
  EXPECT_FALSE(set.empty());
}

TEST(MemberSetTest, ClearRemovesEveryMember) {
  MemberSet set;
  for (uint16_t member = 0; member < MemberSet::kCapacity; member += 3) set.set(member);

  set.clear();

  EXPECT_TRUE(set.empty());
  EXPECT_EQ(set, MemberSet());
}

TEST(MemberSetTest, IteratesMembersInIncreasingOrder) {
  MemberSet set;
  const std::vector<uint16_t> members = {0, 5, 31, kLast};
  for (auto it = members.rbegin(); it != members.rend(); ++it) set.set(*it);

  std::vector<uint16_t> visited;
  for (const uint16_t member : set) visited.push_back(member);

  std::vector<uint16_t> expected = members;
  std::sort(expected.begin(), expected.end());
  expected.erase(std::unique(expected.begin(), expected.end()), expected.end());
  EXPECT_EQ(visited, expected);
  EXPECT_EQ(set.count(), expected.size());
}

TEST(MemberSetTest, NextMemberFindsTheFirstAtOrAfter) {
  MemberSet set;
  set.set(kLast);

  EXPECT_EQ(set.next_member(0), kLast);
  EXPECT_EQ(set.next_member(kLast), kLast);
  EXPECT_EQ(set.next_member(MemberSet::kCapacity), MemberSet::kCapacity);
  set.reset(kLast);
  EXPECT_EQ(set.next_member(0), MemberSet::kCapacity);
}

TEST(MemberSetTest, EqualityComparesMembers) {
  MemberSet first;
  MemberSet second;
  first.set(kLast);

  EXPECT_NE(first, second);
  second.set(kLast);
  EXPECT_EQ(first, second);
}

TEST(MemberSetTest, UnionIntersectionAndInclusion) {
  MemberSet small;
  small.set(0);
  MemberSet large = small;
  large.set(kLast);

  EXPECT_TRUE(large.includes(small));
  EXPECT_FALSE(small.includes(large));
  EXPECT_TRUE(small.includes(MemberSet()));

  MemberSet joined = small;
  joined |= large;
  EXPECT_EQ(joined, large);
  MemberSet common = large;
  common &= small;
  EXPECT_EQ(common, small);
}

TEST(MemberSetTest, BytesHoldEightMembersLowBitFirst) {
  MemberSet set;
  set.set(0);
  set.set(3);
  set.set(15);

  EXPECT_EQ(set.byte_at(0), 0x09);
  EXPECT_EQ(set.byte_at(1), 0x80);
}

TEST(MemberSetTest, SetByteReplacesEightMembers) {
  MemberSet set;
  set.set(1);

  set.set_byte(0, 0xA0);

  EXPECT_FALSE(set.test(1));
  EXPECT_TRUE(set.test(5));
  EXPECT_TRUE(set.test(7));
  EXPECT_EQ(set.count(), 2);
  EXPECT_EQ(set.byte_at(0), 0xA0);
}

TEST(MemberSetTest, SetByteRoundTripsEveryByte) {
  // A pattern per byte, cut to the ids the last byte can name.
  auto pattern = [](size_t index) {
    const size_t ids_in_byte = std::min<size_t>(8, MemberSet::kCapacity - 8 * index);
    return static_cast<uint8_t>((0x5Au ^ index) & ((1u << ids_in_byte) - 1));
  };
  MemberSet set;

  for (size_t index = 0; index < MemberSet::kBytes; ++index) set.set_byte(index, pattern(index));

  for (size_t index = 0; index < MemberSet::kBytes; ++index) {
    EXPECT_EQ(set.byte_at(index), pattern(index));
  }
}

TEST(MemberSetDeathTest, SetBeyondCapacityStops) {
  MemberSet set;

  EXPECT_DEATH_IF_SUPPORTED(set.set(MemberSet::kCapacity), "SYROF_CHECK");
}

}  // namespace
}  // namespace syrof::wire
