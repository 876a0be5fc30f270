// What a submission folder of an assignment must get when graded: its
// `expected.yaml` (starter/, reference/, broken/<variant>/; docs/grading.md,
// "An assignment's folder"), and the one comparison of a graded submission
// with it, shared by `syrof assignment check` and the assignments' tests.
//
// expected.yaml:
//   points: 62.5          # the submission's total, to the hundredth
//   loses: [agreement]    # the criteria below full points on some run ([] for none)
//
// Read with the assignment file's reader and held to its standard: errors
// as file:line:column with the key path and the nearest valid key.
#pragma once

#include <optional>
#include <string>
#include <vector>

#include "syrof/assignment/assignment.h"
#include "syrof/assignment/result.h"
#include "syrof/lab/base/error.h"

namespace syrof::grader::assignment {

struct Expected {
  double points = 0;               ///< the submission's total, to the hundredth, in [0, the assignment's points]
  std::vector<std::string> loses;  ///< criteria of the rubric, in the rubric's order (docs/grading.md, "The rubric")
  int points_line = 0;             ///< where `points` is in the file (1-based), for errors about its value
  int points_column = 0;
};

struct ExpectedLoad {
  std::optional<Expected> expected;
  std::optional<lab::Error> error;
  bool ok() const { return expected.has_value(); }
};

/// Reads `path` (an expected.yaml) for `assignment`: `points` required, at
/// most the assignment's points, with at most two decimals; `loses`
/// required, each a criterion of the assignment's rubric (or `search` when it
/// has search tests), at most once
/// (returned in the rubric's order, whatever the file's).
ExpectedLoad LoadExpectedFile(const std::string& path, const Assignment& assignment);

/// The rubric's criteria in their order: goal, collisions, safety,
/// synchrony, common_knowledge, agreement, faults; then search (the search
/// tests, when the assignment has any).
const std::vector<std::string>& CriterionOrder();

/// The criteria that scored below their full points on at least one of
/// `result`'s tests, in the rubric's order.
std::vector<std::string> LostCriteria(const SubmissionResult& result);

/// How `result` differs from `expected`, one line each ("points 34.94,
/// expected 30.00"; "loses goal, agreement, expected goal"); empty when it
/// gets exactly the expected points (both are rounded to the hundredth, so
/// they are compared exactly) and loses exactly the expected criteria.
std::vector<std::string> CompareWithExpected(const SubmissionResult& result, const Expected& expected);

/// "goal, safety", or "none" for an empty list.
std::string CriteriaText(const std::vector<std::string>& criteria);

}  // namespace syrof::grader::assignment
