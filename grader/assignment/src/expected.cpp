// expected.yaml: what a submission folder must get, and the comparison of a
// graded submission with it.
#include "syrof/assignment/expected.h"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <iterator>
#include <string_view>

#include "syrof/lab/scenario/yaml/document.h"

namespace syrof::grader::assignment {
namespace {

using lab::scenario::Diagnostics;
using lab::scenario::FailAt;
using lab::scenario::FormatNumber;
using lab::scenario::IndexPath;
using lab::scenario::NumberRange;
using lab::scenario::YamlNode;

std::string Hundredths(double points) {
  char text[64];
  std::snprintf(text, sizeof text, "%.2f", points);
  return text;
}

// The criteria `assignment` scores, in the rubric's order, then its search
// tests'.
std::vector<std::string_view> RubricCriteria(const Assignment& assignment) {
  const Rubric& rubric = assignment.rubric;
  const bool present[] = {rubric.goal.has_value(),      rubric.collisions.has_value(),
                          rubric.safety.has_value(),    rubric.synchrony.has_value(),
                          rubric.common_knowledge.has_value(), rubric.agreement.has_value(),
                          rubric.faults.has_value(),    !assignment.search_tests.empty()};
  static_assert(std::size(present) == 8);
  std::vector<std::string_view> criteria;
  for (size_t i = 0; i < CriterionOrder().size(); ++i) {
    if (present[i]) criteria.push_back(CriterionOrder()[i]);
  }
  return criteria;
}

bool ReadExpected(const YamlNode& root, const Assignment& assignment, Expected& expected, Diagnostics& diagnostics) {
  static constexpr std::string_view kKeys[] = {"points", "loses"};
  if (root.is_null()) return diagnostics.Fail(0, 0, "the file is empty; it needs 'points' and 'loses'");
  if (!lab::scenario::ExpectMap(root, "", diagnostics) || !lab::scenario::CheckKeys(root, "", kKeys, diagnostics) ||
      !lab::scenario::RequireKey(root, "", "points", diagnostics) ||
      !lab::scenario::RequireKey(root, "", "loses", diagnostics) ||
      !lab::scenario::ReadNumber(*root.Find("points"), "points", NumberRange{0, assignment.points}, expected.points,
                                 diagnostics)) {
    return false;
  }
  // Grading rounds a submission's points to the hundredth, and they are
  // compared exactly: a third decimal could never match.
  if (std::abs(expected.points * 100 - std::round(expected.points * 100)) > 1e-6) {
    return FailAt(*root.Find("points"), "points",
                  "a submission's points are rounded to the hundredth; " + FormatNumber(expected.points) +
                      " has more decimals",
                  diagnostics);
  }
  expected.points_line = root.Find("points")->line;
  expected.points_column = root.Find("points")->column;
  const YamlNode& loses = *root.Find("loses");
  if (!lab::scenario::ExpectList(loses, "loses", diagnostics)) return false;
  const std::vector<std::string_view> criteria = RubricCriteria(assignment);
  std::vector<bool> listed(criteria.size(), false);
  for (size_t i = 0; i < loses.values.size(); ++i) {
    size_t index = 0;
    if (!lab::scenario::ReadChoice(loses.values[i], IndexPath("loses", i), criteria, index, diagnostics)) return false;
    if (listed[index]) {
      return FailAt(loses.values[i], IndexPath("loses", i), "'" + std::string(criteria[index]) + "' is listed twice",
                    diagnostics);
    }
    listed[index] = true;
  }
  for (size_t i = 0; i < criteria.size(); ++i) {
    if (listed[i]) expected.loses.emplace_back(criteria[i]);
  }
  return true;
}

}  // namespace

const std::vector<std::string>& CriterionOrder() {
  static const std::vector<std::string> kOrder = {"goal",      "collisions", "safety", "synchrony",
                                                  "common_knowledge", "agreement", "faults", "search"};
  return kOrder;
}

ExpectedLoad LoadExpectedFile(const std::string& path, const Assignment& assignment) {
  Diagnostics diagnostics(path);
  YamlNode root;
  Expected expected;
  ExpectedLoad result;
  if (!lab::scenario::ReadYamlFile(path, root, diagnostics) ||
      !ReadExpected(root, assignment, expected, diagnostics)) {
    result.error = diagnostics.error();
    return result;
  }
  result.expected = std::move(expected);
  return result;
}

std::vector<std::string> LostCriteria(const SubmissionResult& result) {
  std::vector<std::string> lost;
  for (const std::string& criterion : CriterionOrder()) {
    const bool lost_here = std::any_of(result.tests.begin(), result.tests.end(), [&](const TestResult& test) {
      return std::any_of(test.score.criteria.begin(), test.score.criteria.end(), [&](const CriterionScore& score) {
        return score.criterion == criterion && score.points < score.max_points;
      });
    });
    if (lost_here) lost.push_back(criterion);
  }
  return lost;
}

std::string CriteriaText(const std::vector<std::string>& criteria) {
  if (criteria.empty()) return "none";
  std::string text;
  for (const std::string& criterion : criteria) text += (text.empty() ? "" : ", ") + criterion;
  return text;
}

std::vector<std::string> CompareWithExpected(const SubmissionResult& result, const Expected& expected) {
  std::vector<std::string> differences;
  if (result.points != expected.points) {
    differences.push_back("points " + Hundredths(result.points) + ", expected " + Hundredths(expected.points));
  }
  const std::vector<std::string> lost = LostCriteria(result);
  if (lost != expected.loses) {
    differences.push_back("loses " + CriteriaText(lost) + ", expected " + CriteriaText(expected.loses));
  }
  return differences;
}

}  // namespace syrof::grader::assignment
