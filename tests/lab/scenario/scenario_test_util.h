// Helpers shared by the scenario tests.
#pragma once

#include <gtest/gtest.h>

#include <string>

#include "syrof/lab/scenario/scenario.h"

namespace syrof::lab::scenario::testing {

/// The smallest valid scenario body; tests append sections to it.
inline const char* const kMinimal = "robots: { count: 4 }\napp: builtin:idle\n";

inline LoadResult Load(const std::string& text, const Overrides& overrides = {}) {
  return LoadScenarioText(text, "test.yaml", overrides);
}

/// Asserts that loading failed at `line`:`column` with a message holding
/// every fragment.
inline ::testing::AssertionResult FailsAt(const LoadResult& result, int line, int column,
                                          std::initializer_list<const char*> fragments) {
  if (result.ok()) return ::testing::AssertionFailure() << "loaded without error";
  const ScenarioError& error = *result.error;
  if (error.line != line || error.column != column) {
    return ::testing::AssertionFailure() << "error at " << error.line << ":" << error.column << ", expected " << line
                                         << ":" << column << ": " << error.ToString();
  }
  for (const char* fragment : fragments) {
    if (error.message.find(fragment) == std::string::npos) {
      return ::testing::AssertionFailure() << "message lacks '" << fragment << "': " << error.ToString();
    }
  }
  return ::testing::AssertionSuccess();
}

}  // namespace syrof::lab::scenario::testing
