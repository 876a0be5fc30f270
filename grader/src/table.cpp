#include "syrof/grader/table.h"

#include <algorithm>
#include <cstdio>

#include "shared_text.h"

namespace syrof::grader {
namespace {

using assignment::SubmissionResult;
using assignment::TestResult;
using assignment::Visibility;

std::string PadRight(std::string text, size_t width) {
  if (text.size() < width) text.append(width - text.size(), ' ');
  return text;
}

std::string PadLeft(std::string text, size_t width) {
  if (text.size() < width) text.insert(0, width - text.size(), ' ');
  return text;
}

}  // namespace

std::string FirstLoss(const TestResult& test) {
  if (!test.run_error.empty()) return test.run_error;
  for (const assignment::CriterionScore& criterion : test.score.criteria) {
    if (criterion.points < criterion.max_points) return criterion.criterion + ": " + criterion.reason;
  }
  return {};
}

void PrintSubmissionTable(const SubmissionResult& result, const std::string& out_dir, std::ostream& out) {
  out << result.title << " (" << result.assignment << "), submission " << result.submission << "\n";
  if (result.build.ok()) {
    out << "Build: ok, " << result.build.detail << "\n";
  } else {
    out << "Build: FAILED (" << ToString(result.build.verdict) << "): " << result.build.detail << "\n"
        << "  the build's output: " << out_dir << "/" << result.build.log_path << "\n";
  }
  out << "Tests passed " << result.tests_passed << "/" << result.tests.size() << ", Points "
      << PointsText(result.points) << "/" << PointsText(result.max_points) << (result.public_only ? " (public tests only)" : "")
      << "\n\n";
  size_t name_width = 4;
  for (const TestResult& test : result.tests) {
    name_width = std::max(name_width, test.name.size() + (test.visibility == Visibility::kHidden ? 9 : 0));
  }
  std::string score_width_sample = PointsText(result.max_points) + "/" + PointsText(result.max_points);
  const size_t score_width = score_width_sample.size();
  out << "  " << PadRight("test", name_width) << "  " << PadLeft("points", score_width) << "  result  why\n";
  for (const TestResult& test : result.tests) {
    const std::string name = test.name + (test.visibility == Visibility::kHidden ? " (hidden)" : "");
    out << "  " << PadRight(name, name_width) << "  "
        << PadLeft(PointsText(test.points) + "/" + PointsText(test.max_points), score_width) << "  "
        << (test.passed ? "PASS" : "FAIL");
    const std::string why = FirstLoss(test);
    if (!why.empty()) out << "    " << why;
    out << "\n";
    if (!test.message_format.empty()) {
      out << "  " << std::string(name_width, ' ') << "  message format: " << test.message_format << "\n";
    }
    if (!test.passed && result.build.ok() && test.run_error.empty()) {
      // A hidden test names no scenario file: no command.
      if (!test.replay_command.empty()) {
        out << "  " << std::string(name_width, ' ') << "  replay: " << test.replay_command << "\n";
      }
    }
  }
}

}  // namespace syrof::grader
