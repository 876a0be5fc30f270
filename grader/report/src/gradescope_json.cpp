// Gradescope's results.json (docs/grading.md, "results.json").
#include <fmt/format.h>

#include <cmath>
#include <nlohmann/json.hpp>

#include "syrof/report/reports.h"
#include "text.h"

namespace syrof::grader::report {
namespace {

using assignment::Visibility;
using nlohmann::ordered_json;

// Points as a JSON number, to the hundredth.
double Hundredths(double points) {
  const double rounded = std::round(points * 100.0) / 100.0;
  return std::isfinite(rounded) && rounded != 0.0 ? rounded : 0.0;
}

// What every student sees first: the build, and the public tests' tally.
// The hidden tests are only counted: their results wait for the due date.
std::string SummaryOutput(const SubmissionResult& result, const ReportOptions& options) {
  std::string output = text::ValidUtf8(fmt::format("{} ({})\n", result.title, result.assignment));
  if (result.build.ok()) {
    output += "The submission built.\n";
  } else {
    output += "Not graded: " + text::BuildFailure(result.build) + ". Every test scores 0.\n";
  }
  const text::SetTally visible = text::Tally(result, Visibility::kPublic);
  output += fmt::format("Public tests: passed {}/{}, points {}/{}.\n", visible.passed, visible.tests,
                        text::Points(visible.points), text::Points(visible.max_points));
  const text::SetTally hidden = text::Tally(result, Visibility::kHidden);
  if (hidden.tests > 0 && options.feedback_withheld) {
    output += fmt::format(
        "Hidden tests: {}; feedback on them is given for your first {} submissions, and this is submission {}: "
        "their results are shown after the due date.\n",
        hidden.tests, options.feedback_withheld->cap, options.feedback_withheld->submission);
  } else if (hidden.tests > 0) {
    output += fmt::format("Hidden tests: {}; their results are shown after the due date.\n", hidden.tests);
  } else if (result.public_only) {
    output += "Graded on the public tests only.\n";
  }
  return output;
}

std::string TestOutput(const SubmissionResult& result, const TestResult& test) {
  std::string output;
  for (const std::string& line : text::TestLines(result, test)) output += line + "\n";
  if (test.visibility == Visibility::kPublic && !test.replay_command.empty()) {
    output += text::ValidUtf8("replay: " + test.replay_command) + "\n";
  }
  return output;
}

}  // namespace

const char* GradescopeVisibilityOf(const TestResult& test, bool withheld) {
  using assignment::GradescopeVisibility;
  GradescopeVisibility visibility = test.gradescope;
  if (visibility == GradescopeVisibility::kDefault) {
    visibility = test.visibility == Visibility::kHidden ? GradescopeVisibility::kAfterDueDate
                                                        : GradescopeVisibility::kVisible;
  }
  if (withheld && test.visibility == Visibility::kHidden && visibility == GradescopeVisibility::kVisible) {
    visibility = GradescopeVisibility::kAfterDueDate;
  }
  return ToString(visibility);
}

std::string GradescopeResultsJson(const SubmissionResult& result, const ReportOptions& options) {
  double seconds = result.build.wall_seconds;
  for (const TestResult& test : result.tests) seconds += test.wall_seconds;

  ordered_json json;
  json["score"] = Hundredths(result.points);
  json["execution_time"] = options.zero_timings || !std::isfinite(seconds) ? 0 : std::llround(seconds);
  json["output"] = SummaryOutput(result, options);
  json["visibility"] = "visible";
  json["stdout_visibility"] = "hidden";
  json["tests"] = ordered_json::array();
  for (const TestResult& test : result.tests) {
    ordered_json entry;
    entry["name"] = text::ValidUtf8(test.name);
    entry["score"] = Hundredths(test.points);
    entry["max_score"] = Hundredths(test.max_points);
    entry["status"] = test.passed && result.build.ok() ? "passed" : "failed";
    entry["output"] = TestOutput(result, test);
    entry["visibility"] = GradescopeVisibilityOf(test, options.feedback_withheld.has_value());
    json["tests"].push_back(std::move(entry));
  }
  return json.dump(2, ' ', false, ordered_json::error_handler_t::replace) + "\n";
}

}  // namespace syrof::grader::report
