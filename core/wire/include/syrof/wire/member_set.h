// A set of robot ids, as beacons carry it and the synchronizer keeps it.
//
// Robot ids in a swarm of N robots are 0 .. N-1, and N is at most
// kMaxSwarmSize, a build-time constant (SYROF_MAX_SWARM_SIZE: 1024 on the
// host, 32 on the Teensy). A MemberSet is a bitset of that capacity: no
// allocation, constant size, cheap to copy and compare; operations cost in
// proportion to the highest id held, not to the capacity.
#pragma once

#include <array>
#include <span>
#include <bit>
#include <cstddef>
#include <cstdint>
#include <iterator>

#include "syrof/base/check.h"
#include "syrof/base/state_digest.h"

// The build sets this (core/wire/CMakeLists.txt); the default only serves
// compiling a file on its own.
#ifndef SYROF_MAX_SWARM_SIZE
#define SYROF_MAX_SWARM_SIZE 1024
#endif

static_assert(SYROF_MAX_SWARM_SIZE >= 1 && SYROF_MAX_SWARM_SIZE <= 65535,
              "SYROF_MAX_SWARM_SIZE must be 1..65535: swarm sizes travel as uint16_t");

namespace syrof::wire {

/// The largest swarm this build supports; robot ids are below it.
inline constexpr uint16_t kMaxSwarmSize = SYROF_MAX_SWARM_SIZE;

/// A set of robot ids below kMaxSwarmSize. Iterating visits members in
/// increasing order.
class MemberSet {
 public:
  /// Members are 0 .. kCapacity - 1.
  static constexpr uint16_t kCapacity = kMaxSwarmSize;
  /// Number of bytes byte_at() and set_byte() address.
  static constexpr size_t kBytes = (kCapacity + 7) / 8;

  /// Walks the members in increasing order.
  class Iterator {
   public:
    // Dereferencing yields a value, not a reference, so to pre-C++20 code
    // this is an input iterator; to C++20 ranges it is a forward iterator.
    using iterator_category = std::input_iterator_tag;
    using iterator_concept = std::forward_iterator_tag;
    using value_type = uint16_t;
    using difference_type = std::ptrdiff_t;
    using pointer = const uint16_t*;
    using reference = uint16_t;

    constexpr Iterator() = default;
    constexpr uint16_t operator*() const { return member_; }
    constexpr Iterator& operator++() {
      member_ = set_->next_member(static_cast<uint16_t>(member_ + 1));
      return *this;
    }
    constexpr Iterator operator++(int) {
      Iterator before = *this;
      ++*this;
      return before;
    }
    constexpr bool operator==(const Iterator& other) const { return member_ == other.member_; }

   private:
    friend class MemberSet;
    constexpr Iterator(const MemberSet* set, uint16_t member) : set_(set), member_(member) {}

    const MemberSet* set_ = nullptr;
    uint16_t member_ = kCapacity;  // kCapacity is the end
  };

  /// The empty set.
  constexpr MemberSet() = default;

  /// Adds `member`. A member at or beyond kCapacity is a bug and stops the program.
  constexpr void set(uint16_t member) {
    SYROF_CHECK(member < kCapacity);
    const size_t word = member / kWordBits;
    words_[word] |= bit(member);
    Cover(word + 1);
  }

  /// Removes `member`. A member at or beyond kCapacity is a bug and stops the program.
  constexpr void reset(uint16_t member) {
    SYROF_CHECK(member < kCapacity);
    words_[member / kWordBits] &= ~bit(member);
  }

  /// Removes every member.
  constexpr void clear() {
    for (size_t i = 0; i < used_; ++i) words_[i] = 0;
    used_ = 0;
  }

  /// Whether `member` is in the set; false for any id at or beyond kCapacity.
  constexpr bool test(uint16_t member) const {
    return member < kCapacity && (words_[member / kWordBits] & bit(member)) != 0;
  }

  /// Number of members.
  constexpr uint16_t count() const {
    unsigned total = 0;
    for (size_t i = 0; i < used_; ++i) total += static_cast<unsigned>(std::popcount(words_[i]));
    return static_cast<uint16_t>(total);
  }

  constexpr bool empty() const { return next_member(0) == kCapacity; }

  /// The smallest member at or after `from`, or kCapacity when there is none.
  constexpr uint16_t next_member(uint16_t from) const {
    size_t word = from / kWordBits;
    if (word >= used_) return kCapacity;
    uint32_t bits = words_[word] & (~uint32_t{0} << (from % kWordBits));
    while (bits == 0) {
      if (++word >= used_) return kCapacity;
      bits = words_[word];
    }
    return static_cast<uint16_t>(word * kWordBits + static_cast<size_t>(std::countr_zero(bits)));
  }

  /// Whether every member of `other` is also a member of this set.
  constexpr bool includes(const MemberSet& other) const {
    // Without an early exit the loop vectorizes: in a large swarm the sets
    // compared are mostly equal, so every word is read anyway.
    uint32_t missing = 0;
    for (size_t i = 0; i < other.used_; ++i) missing |= other.words_[i] & ~words_[i];
    return missing == 0;
  }

  /// Bits per word of word().
  static constexpr size_t kWordBits = 32;

  /// Number of words that may hold members: the rest are zero.
  constexpr size_t word_count() const { return used_; }

  /// Members kWordBits*index .. kWordBits*index+31, the first in bit 0; 0
  /// past word_count().
  constexpr uint32_t word(size_t index) const { return index < used_ ? words_[index] : 0; }

  /// Whether any member is at or beyond `bound`.
  constexpr bool any_at_or_above(uint16_t bound) const { return next_member(bound) != kCapacity; }

  /// Union.
  constexpr MemberSet& operator|=(const MemberSet& other) {
    for (size_t i = 0; i < other.used_; ++i) words_[i] |= other.words_[i];
    Cover(other.used_);
    return *this;
  }

  /// Intersection.
  constexpr MemberSet& operator&=(const MemberSet& other) {
    for (size_t i = 0; i < used_; ++i) words_[i] &= other.words_[i];
    return *this;
  }

  /// Difference: removes every member of `other`.
  constexpr MemberSet& operator-=(const MemberSet& other) {
    const size_t used = used_ < other.used_ ? used_ : other.used_;
    for (size_t i = 0; i < used; ++i) words_[i] &= ~other.words_[i];
    return *this;
  }

  /// Same members (however each set came to hold them).
  constexpr bool operator==(const MemberSet& other) const {
    const size_t used = used_ > other.used_ ? used_ : other.used_;
    uint32_t differ = 0;  // no early exit, as in includes()
    for (size_t i = 0; i < used; ++i) differ |= words_[i] ^ other.words_[i];
    return differ == 0;
  }

  /// Members 8*index .. 8*index+7 as one byte, member 8*index in bit 0 (the
  /// beacon's wire order). `index` must be below kBytes (checked).
  constexpr uint8_t byte_at(size_t index) const {
    SYROF_CHECK(index < kBytes);
    return static_cast<uint8_t>(words_[index / kBytesPerWord] >> (8 * (index % kBytesPerWord)));
  }

  /// Replaces members 8*index .. 8*index+7 with the bits of `bits`, member
  /// 8*index in bit 0. `index` must be below kBytes, and bits naming ids at or
  /// beyond kCapacity must be zero (both checked).
  constexpr void set_byte(size_t index, uint8_t bits) {
    SYROF_CHECK(index < kBytes);
    SYROF_CHECK(index * 8 + static_cast<size_t>(std::bit_width(bits)) <= kCapacity);
    const unsigned shift = 8 * (index % kBytesPerWord);
    uint32_t& word = words_[index / kBytesPerWord];
    word = (word & ~(uint32_t{0xFF} << shift)) | (uint32_t{bits} << shift);
    if (bits != 0) Cover(index / kBytesPerWord + 1);
  }

  constexpr Iterator begin() const { return Iterator(this, next_member(0)); }
  constexpr Iterator end() const { return Iterator(this, kCapacity); }

 private:
  static constexpr size_t kBytesPerWord = kWordBits / 8;
  static constexpr size_t kWords = (kCapacity + kWordBits - 1) / kWordBits;

  static constexpr uint32_t bit(uint16_t member) { return uint32_t{1} << (member % kWordBits); }

  constexpr void Cover(size_t words) {
    if (words > used_) used_ = static_cast<uint16_t>(words);
  }

  // Bits at or beyond kCapacity stay zero, so == and count() need no mask.
  std::array<uint32_t, kWords> words_{};
  // Words from used_ on are zero (every operation keeps this), so operations
  // touch only the words a swarm of N robots can use, N / 32 of them, not
  // the build's capacity: a 100-robot swarm on a 1024-robot build reads 4
  // words, not 32. It may overstate (after reset), never understate.
  uint16_t used_ = 0;
};

/// A set's members into `digest` (base/state_digest.h): its words alone,
/// since the count of words in use may overstate.
inline void AddToDigest(base::StateDigest& digest, const MemberSet& set) {
  for (size_t index = 0; index < (MemberSet::kCapacity + MemberSet::kWordBits - 1) / MemberSet::kWordBits; ++index) {
    digest.AddValue(set.word(index));
  }
}

}  // namespace syrof::wire
