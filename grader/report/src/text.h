// What the reports share: the words for a test's criteria and verdicts (so
// results.json, JUnit and report.html say the same thing), points written
// the same way everywhere, and making outside text valid UTF-8.
#pragma once

#include <string>
#include <string_view>
#include <vector>

#include "syrof/assignment/result.h"

namespace syrof::grader::report::text {

using assignment::BuildResult;
using assignment::CriterionScore;
using assignment::SubmissionResult;
using assignment::TestResult;

/// `text` with every byte sequence that is not UTF-8 (and every NUL) as
/// U+FFFD. Valid text comes back unchanged.
std::string ValidUtf8(std::string_view text);

/// Where escaped text goes.
enum class Markup { kXmlText, kXmlAttribute, kHtml };

/// `text` made valid UTF-8 (ValidUtf8) and escaped for `where`: & < > " '
/// always; control characters (C0 but tab, newline and carriage return;
/// DEL) become U+FFFD, as XML 1.0 forbids most of them; in an XML
/// attribute, tab, newline and carriage return are written as character
/// references so a parser keeps them.
std::string Escape(std::string_view text, Markup where);

/// Points to the hundredth, without trailing zeros: 25, 12.5, 16.67.
std::string Points(double points);

/// "goal 25/50: 1 of 2 checks passed; ...", one per criterion.
std::string CriterionLine(const CriterionScore& criterion);

/// Whether a criterion earned less than its points.
bool Lost(const CriterionScore& criterion);

/// Why a test failed, in one line: its run error, its first lost
/// criterion, or that the submission did not build. Empty for a passed test.
std::string FailureMessage(const SubmissionResult& result, const TestResult& test);

/// A test's lines for a reader: why it has no score (run error, no build),
/// or each criterion's line and the run's total.
std::vector<std::string> TestLines(const SubmissionResult& result, const TestResult& test);

/// "public" or "hidden".
std::string_view SetName(const TestResult& test);

/// "the submission did not build (build_failed): app.c:3:1: error: ..."
std::string BuildFailure(const BuildResult& build);

/// The submission's points and tests in one line: "Points 85/100, tests passed 17/20".
std::string ScoreLine(const SubmissionResult& result);

/// Every test passed in a set, and their points, for the summary lines.
struct SetTally {
  int tests = 0;
  int passed = 0;
  double points = 0;
  double max_points = 0;
};
SetTally Tally(const SubmissionResult& result, assignment::Visibility set);

}  // namespace syrof::grader::report::text
