// JUnit XML (docs/grading.md, "junit.xml"): the de facto schema CI systems
// read (Jenkins, GitLab, GitHub actions' test reporters): testsuites >
// testsuite > testcase, with <failure> and <system-out>.
#include <fmt/format.h>

#include <cmath>

#include "syrof/report/reports.h"
#include "text.h"

namespace syrof::grader::report {
namespace {

using text::Markup;

std::string Attribute(std::string_view value) { return text::Escape(value, Markup::kXmlAttribute); }
std::string Text(std::string_view value) { return text::Escape(value, Markup::kXmlText); }

std::string Seconds(double seconds, const ReportOptions& options) {
  if (options.zero_timings || !std::isfinite(seconds) || seconds < 0) seconds = 0;
  return fmt::format("{:.3f}", seconds);
}

std::string Lines(const std::vector<std::string>& lines) {
  std::string joined;
  for (const std::string& line : lines) joined += line + "\n";
  return joined;
}

}  // namespace

std::string JunitXml(const SubmissionResult& result, const ReportOptions& options) {
  std::string cases;
  int tests = 0;
  int failures = 0;
  double seconds = result.build.wall_seconds;
  const std::string classname = Attribute(result.assignment);
  if (!result.build.ok()) {
    tests = 1;
    failures = 1;
    std::string out = text::BuildFailure(result.build) + "\n";
    if (!result.build.log_path.empty()) out += "build log: " + result.build.log_path + "\n";
    cases += fmt::format(
        "    <testcase classname=\"{}\" name=\"build\" time=\"{}\">\n"
        "      <failure message=\"{}\" type=\"{}\">{}</failure>\n"
        "      <system-out>{}</system-out>\n"
        "    </testcase>\n",
        classname, Seconds(result.build.wall_seconds, options), Attribute(text::BuildFailure(result.build)),
        Attribute(ToString(result.build.verdict)), Text(out), Text(out));
  } else {
    for (const TestResult& test : result.tests) {
      ++tests;
      seconds += test.wall_seconds;
      std::vector<std::string> lines = text::TestLines(result, test);
      lines.insert(lines.begin(), fmt::format("{} test, {}/{} points", text::SetName(test),
                                              text::Points(test.points), text::Points(test.max_points)));
      if (!test.replay_command.empty()) lines.push_back("replay: " + text::ValidUtf8(test.replay_command));
      if (!test.output_dir.empty()) lines.push_back("outputs: " + text::ValidUtf8(test.output_dir));
      const std::string out = Lines(lines);
      cases += fmt::format("    <testcase classname=\"{}\" name=\"{}\" time=\"{}\">\n", classname,
                           Attribute(test.name), Seconds(test.wall_seconds, options));
      if (!test.passed) {
        ++failures;
        const std::string type = !test.run_error.empty() ? "run_error" : "lost_points";
        cases += fmt::format("      <failure message=\"{}\" type=\"{}\">{}</failure>\n",
                             Attribute(text::FailureMessage(result, test)), type, Text(out));
      }
      cases += fmt::format("      <system-out>{}</system-out>\n    </testcase>\n", Text(out));
    }
  }
  const std::string time = Seconds(seconds, options);
  std::string xml = "<?xml version=\"1.0\" encoding=\"UTF-8\"?>\n";
  xml += fmt::format("<testsuites name=\"syrof grade\" tests=\"{}\" failures=\"{}\" errors=\"0\" time=\"{}\">\n",
                     tests, failures, time);
  xml += fmt::format(
      "  <testsuite name=\"{}\" tests=\"{}\" failures=\"{}\" errors=\"0\" skipped=\"0\" time=\"{}\">\n", classname,
      tests, failures, time);
  xml += "    <properties>\n";
  const auto property = [&xml](std::string_view name, std::string_view value) {
    xml += fmt::format("      <property name=\"{}\" value=\"{}\"/>\n", name, Attribute(value));
  };
  property("submission", result.submission);
  property("title", result.title);
  property("points", text::Points(result.points) + "/" + text::Points(result.max_points));
  property("tests_passed", fmt::format("{}/{}", result.tests_passed, result.tests.size()));
  property("public_only", result.public_only ? "true" : "false");
  property("build", ToString(result.build.verdict));
  xml += "    </properties>\n";
  xml += cases;
  xml += "  </testsuite>\n</testsuites>\n";
  return xml;
}

}  // namespace syrof::grader::report
