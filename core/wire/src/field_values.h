// Internal: how the codecs see a field's value, as a plain integer.
//
// Every beacon field is an integer or an enum of at most 16 bits, so an
// int32_t holds any of them and any raw bit pattern read for them.
#pragma once

#include <cstdint>
#include <type_traits>

namespace syrof::wire::detail {

template <typename T>
using Underlying = typename std::conditional_t<std::is_enum_v<T>, std::underlying_type<T>,
                                               std::type_identity<T>>::type;

template <typename T>
constexpr int32_t to_integer(T value) {
  static_assert(std::is_integral_v<Underlying<T>> && sizeof(Underlying<T>) <= 2,
                "beacon fields are integers or enums of at most 16 bits");
  return static_cast<int32_t>(static_cast<Underlying<T>>(value));
}

template <typename T>
constexpr T from_integer(int32_t value) {
  return static_cast<T>(static_cast<Underlying<T>>(value));
}

// The smallest and largest values `bits` bits hold, read as T reads them
// (two's complement when T is signed). `bits` is 1 .. 16.
template <typename T>
constexpr int32_t lowest_in_bits(unsigned bits) {
  return std::is_signed_v<Underlying<T>> ? -(int32_t{1} << (bits - 1)) : 0;
}
template <typename T>
constexpr int32_t highest_in_bits(unsigned bits) {
  return std::is_signed_v<Underlying<T>> ? (int32_t{1} << (bits - 1)) - 1
                                         : (int32_t{1} << bits) - 1;
}

// The value of `bits` raw bits as T reads them.
template <typename T>
constexpr int32_t from_raw_bits(uint32_t raw, unsigned bits) {
  const auto value = static_cast<int32_t>(raw);
  if (std::is_signed_v<Underlying<T>> && value > highest_in_bits<T>(bits)) {
    return value - (int32_t{1} << bits);
  }
  return value;
}

// The low `bits` bits of `value` in two's complement.
constexpr uint32_t to_raw_bits(int32_t value, unsigned bits) {
  return static_cast<uint32_t>(value) & ((uint32_t{1} << bits) - 1);
}

}  // namespace syrof::wire::detail
