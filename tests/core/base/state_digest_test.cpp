// base::StateDigest: equal streams of bytes give equal values, in any
// chunking; a byte changed, moved or added gives another; the value is
// fixed by the definition (the same on every build, so a search's figures
// do not depend on the machine).
#include <gtest/gtest.h>

#include <array>
#include <cstdint>
#include <span>

#include "syrof/base/state_digest.h"

namespace syrof::base {
namespace {

StateDigest::Value Of(std::span<const uint8_t> bytes) {
  StateDigest digest;
  digest.AddBytes(std::as_bytes(bytes));
  return digest.value();
}

TEST(StateDigestTest, EqualBytesGiveEqualValues) {
  const std::array<uint8_t, 13> bytes{1, 2, 3, 4, 5, 6, 7, 8, 9, 10, 11, 12, 13};
  EXPECT_EQ(Of(bytes), Of(bytes));
  StateDigest values;
  for (uint8_t byte : bytes) values.AddValue(byte);
  // One byte at a time is another stream (each ends a word of its own).
  EXPECT_NE(values.value(), Of(bytes));
}

TEST(StateDigestTest, AChangedMovedOrAddedByteChangesTheValue) {
  std::array<uint8_t, 16> bytes{};
  const StateDigest::Value zero = Of(bytes);
  for (size_t i = 0; i < bytes.size(); ++i) {
    std::array<uint8_t, 16> changed = bytes;
    changed[i] = 1;
    EXPECT_NE(Of(changed), zero) << "byte " << i;
  }
  EXPECT_NE(Of(std::span(bytes).first(15)), zero);
  EXPECT_NE(Of(std::span(bytes).first(8)), Of(std::span(bytes).first(9)));
  StateDigest ab, ba;
  ab.AddValue(uint32_t{1});
  ab.AddValue(uint32_t{2});
  ba.AddValue(uint32_t{2});
  ba.AddValue(uint32_t{1});
  EXPECT_NE(ab.value(), ba.value());
}

TEST(StateDigestTest, TheValueIsFixedByTheDefinition) {
  StateDigest digest;
  digest.AddValue(uint64_t{0x0123456789ABCDEF});
  digest.AddValue(uint16_t{7});
  // Computed once from the definition; any change to the mixing shows here.
  EXPECT_EQ(digest.value().low, 0x011931bc7f8980d6ull);
  EXPECT_EQ(digest.value().high, 0xc2ec41d184f05378ull);
  EXPECT_NE(StateDigest().value(), digest.value());
}

}  // namespace
}  // namespace syrof::base
