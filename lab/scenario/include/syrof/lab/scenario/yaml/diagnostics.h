// The first error of a load, and the helpers every reader uses to report it.
//
// Loading stops at the first problem: readers call Fail() and return false,
// and callers return as soon as a step fails, so one error comes back.
#pragma once

#include <optional>
#include <string>

#include "syrof/lab/scenario/scenario.h"

namespace syrof::lab::scenario {

class Diagnostics {
 public:
  explicit Diagnostics(std::string file) : file_(std::move(file)) {}

  // Records an error at a 1-based line and column (0, 0: no place) unless
  // one is recorded already. Always returns false, so `return Fail(...)`
  // reads as "this step failed".
  bool Fail(int line, int column, std::string message) {
    if (!error_) error_ = ScenarioError{file_, line, column, std::move(message)};
    return false;
  }

  bool failed() const { return error_.has_value(); }
  const std::optional<ScenarioError>& error() const { return error_; }
  const std::string& file() const { return file_; }

 private:
  std::string file_;
  std::optional<ScenarioError> error_;
};

}  // namespace syrof::lab::scenario
