#include "text.h"

#include <fmt/format.h>

#include <cmath>
#include <cstdint>

namespace syrof::grader::report::text {
namespace {

constexpr std::string_view kReplacement = "\xEF\xBF\xBD";  // U+FFFD

// The length of the UTF-8 sequence at `at`, or 0 when it is not one
// (overlong forms, surrogates and code points above U+10FFFF included).
size_t SequenceLength(std::string_view text, size_t at) {
  const auto byte = [&](size_t i) { return static_cast<uint8_t>(text[i]); };
  const uint8_t lead = byte(at);
  if (lead == 0) return 0;
  if (lead < 0x80) return 1;
  size_t length = 0;
  uint32_t low = 0;
  uint32_t code = 0;
  if ((lead & 0xE0) == 0xC0) {
    length = 2, low = 0x80, code = lead & 0x1F;
  } else if ((lead & 0xF0) == 0xE0) {
    length = 3, low = 0x800, code = lead & 0x0F;
  } else if ((lead & 0xF8) == 0xF0) {
    length = 4, low = 0x10000, code = lead & 0x07;
  } else {
    return 0;
  }
  if (at + length > text.size()) return 0;
  for (size_t i = 1; i < length; ++i) {
    if ((byte(at + i) & 0xC0) != 0x80) return 0;
    code = (code << 6) | (byte(at + i) & 0x3F);
  }
  if (code < low || code > 0x10FFFF || (code >= 0xD800 && code <= 0xDFFF)) return 0;
  return length;
}

}  // namespace

std::string ValidUtf8(std::string_view text) {
  std::string valid;
  valid.reserve(text.size());
  for (size_t at = 0; at < text.size();) {
    const size_t length = SequenceLength(text, at);
    if (length == 0) {
      valid += kReplacement;
      ++at;
    } else {
      valid.append(text.substr(at, length));
      at += length;
    }
  }
  return valid;
}

std::string Escape(std::string_view raw, Markup where) {
  const std::string valid = ValidUtf8(raw);
  std::string escaped;
  escaped.reserve(valid.size());
  for (const char c : valid) {
    switch (c) {
      case '&': escaped += "&amp;"; break;
      case '<': escaped += "&lt;"; break;
      case '>': escaped += "&gt;"; break;
      case '"': escaped += "&quot;"; break;
      case '\'': escaped += "&#39;"; break;
      case '\t':
      case '\n':
      case '\r':
        if (where == Markup::kXmlAttribute) {
          escaped += fmt::format("&#{};", static_cast<int>(c));
        } else {
          escaped += c;
        }
        break;
      default:
        if (static_cast<unsigned char>(c) < 0x20 || c == 0x7F) {
          escaped += kReplacement;
        } else {
          escaped += c;
        }
    }
  }
  return escaped;
}

std::string Points(double points) {
  double rounded = std::round(points * 100.0) / 100.0;
  if (rounded == 0.0 || !std::isfinite(rounded)) rounded = 0.0;  // no "-0", no "nan"
  std::string written = fmt::format("{:.2f}", rounded);
  while (written.back() == '0') written.pop_back();
  if (written.back() == '.') written.pop_back();
  return written;
}

bool Lost(const CriterionScore& criterion) { return Points(criterion.points) != Points(criterion.max_points); }

std::string CriterionLine(const CriterionScore& criterion) {
  return ValidUtf8(fmt::format("{} {}/{}: {}", criterion.criterion, Points(criterion.points),
                               Points(criterion.max_points), criterion.reason));
}

std::string_view SetName(const TestResult& test) {
  return test.visibility == assignment::Visibility::kHidden ? "hidden" : "public";
}

std::string BuildFailure(const BuildResult& build) {
  return ValidUtf8(build.detail.empty() ? fmt::format("the submission did not build ({})", ToString(build.verdict))
                                        : fmt::format("the submission did not build ({}): {}", ToString(build.verdict),
                                                      build.detail));
}

std::string FailureMessage(const SubmissionResult& result, const TestResult& test) {
  if (test.passed) return {};
  if (!result.build.ok()) return "not run: " + BuildFailure(result.build);
  if (!test.run_error.empty()) return ValidUtf8("the run has no score: " + test.run_error);
  for (const CriterionScore& criterion : test.score.criteria) {
    if (Lost(criterion)) return CriterionLine(criterion);
  }
  return "failed";
}

std::vector<std::string> TestLines(const SubmissionResult& result, const TestResult& test) {
  if (!result.build.ok()) return {"not run: " + BuildFailure(result.build)};
  std::vector<std::string> lines;
  if (!test.run_error.empty()) lines.push_back(ValidUtf8("the run has no score: " + test.run_error));
  for (const CriterionScore& criterion : test.score.criteria) lines.push_back(CriterionLine(criterion));
  if (!test.score.criteria.empty()) {
    lines.push_back(fmt::format("run total {}/{}", Points(test.score.points), Points(test.score.max_points)));
  }
  if (!test.message_format.empty()) lines.push_back(ValidUtf8("message format: " + test.message_format));
  return lines;
}

std::string ScoreLine(const SubmissionResult& result) {
  return fmt::format("Points {}/{}, tests passed {}/{}", Points(result.points), Points(result.max_points),
                     result.tests_passed, result.tests.size());
}

SetTally Tally(const SubmissionResult& result, assignment::Visibility set) {
  SetTally tally;
  for (const TestResult& test : result.tests) {
    if (test.visibility != set) continue;
    ++tally.tests;
    tally.passed += test.passed ? 1 : 0;
    tally.points += test.points;
    tally.max_points += test.max_points;
  }
  return tally;
}

}  // namespace syrof::grader::report::text
