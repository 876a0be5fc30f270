// A value or an error, for core code that may not throw.
//
// Core code reports runtime failures (bad input, exhausted capacity, misuse)
// as values: an `enum class` error whose zero enumerator `kOk` means success,
// and Result<T, Error> where a value comes back as well. Reading the value of
// a failed Result is a bug and stops the program through SYROF_CHECK.
#pragma once

#include <type_traits>
#include <utility>

#include "syrof/base/check.h"

namespace syrof::base {

/// Holds either a T or an Error (an enum class whose `kOk` means success).
/// T must be default constructible; it is meant for small values such as
/// indices, handles and decoded messages.
template <typename T, typename Error>
class [[nodiscard]] Result {
  static_assert(std::is_enum_v<Error>, "Error must be an enum with a kOk enumerator");
  static_assert(std::is_default_constructible_v<T>, "T must be default constructible");

 public:
  Result(T value) : value_(std::move(value)), error_(Error::kOk) {}  // NOLINT: implicit by design
  Result(Error error) : error_(error) { SYROF_CHECK(error != Error::kOk); }  // NOLINT

  bool ok() const { return error_ == Error::kOk; }
  explicit operator bool() const { return ok(); }

  /// The error; Error::kOk when the Result holds a value.
  Error error() const { return error_; }

  /// The value. Calling this on an error is a bug and stops the program.
  const T& value() const& {
    SYROF_CHECK(ok());
    return value_;
  }
  T& value() & {
    SYROF_CHECK(ok());
    return value_;
  }
  T&& value() && {
    SYROF_CHECK(ok());
    return std::move(value_);
  }

 private:
  T value_{};
  Error error_;
};

}  // namespace syrof::base
