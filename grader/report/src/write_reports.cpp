// WriteSubmissionReports: the one call the runner makes.
#include <fmt/format.h>

#include <filesystem>
#include <fstream>

#include "syrof/lab/view/verdict.h"
#include "syrof/lab/view/view.h"
#include "syrof/report/reports.h"

namespace syrof::grader::report {
namespace {

namespace fs = std::filesystem;

// A report's failure, its words whole.
lab::Error ReportError(std::string message) { return lab::Error{.where = "", .message = std::move(message)}; }

// Writes `bytes` to `path`; what went wrong, if anything.
std::optional<lab::Error> WriteFile(const fs::path& path, const std::string& bytes) {
  std::ofstream file(path, std::ios::binary | std::ios::trunc);
  if (!file) return ReportError(fmt::format("cannot write {}", path.string()));
  file << bytes;
  file.flush();
  if (!file) return ReportError(fmt::format("writing {} failed", path.string()));
  return std::nullopt;
}

// Adds `problem`, if any, to `problems` on a line of its own.
void Add(std::optional<lab::Error>& problems, const std::optional<lab::Error>& problem) {
  if (!problem) return;
  if (!problems) {
    problems = ReportError(problem->ToString());
  } else {
    problems->message += "\n" + problem->ToString();
  }
}

}  // namespace

std::optional<lab::Error> WriteSubmissionReports(const SubmissionResult& result, const std::string& out_dir,
                                                 const ReportOptions& options) {
  const fs::path dir(out_dir);
  std::optional<lab::Error> problems;
  std::map<std::string, ReplayPageNote> notes;
  for (const TestResult& test : result.tests) {
    if (test.passed || test.replay_path.empty()) continue;
    const std::string page_path = ReplayPagePath(test);
    if (!ShowsWhole(test, options.form)) {
      // The student's form has no viewer of a hidden run: a page left by an
      // earlier full report would show its start poses and inputs.
      std::error_code error;
      if (!page_path.empty()) fs::remove(dir / page_path, error);
      continue;
    }
    if (page_path.empty()) {
      notes[test.name] = {false, fmt::format("No viewer: the replay path '{}' is not inside the report's folder.",
                                             test.replay_path)};
      continue;
    }
    std::ifstream replay(dir / test.replay_path, std::ios::binary);
    if (!replay) {
      notes[test.name] = {false, fmt::format("No viewer: the run left no replay at {}.", test.replay_path)};
      continue;
    }
    // The run's metrics.json beside its replay gives the page its verdict
    // banner (a page without them only says it was not judged there).
    lab::view::PageOptions page_options;
    if (std::ifstream metrics(dir / test.output_dir / "metrics.json", std::ios::binary); metrics) {
      lab::Error ignored;
      page_options.metrics = lab::view::ReadVerdictMetrics(metrics, test.name + "/metrics.json", ignored);
    }
    // Named by the test, not by a path, so the page's bytes do not depend
    // on where the reports are written.
    const lab::view::Page page = lab::view::BuildPage(replay, test.name, page_options);
    std::error_code error;
    fs::create_directories((dir / page_path).parent_path(), error);
    if (const std::optional<lab::Error> problem = WriteFile(dir / page_path, page.html)) {
      Add(problems, problem);
      notes[test.name] = {false, "No viewer: " + problem->ToString() + "."};
      continue;
    }
    if (!page.complete) {
      notes[test.name] = {true, fmt::format("The replay is not whole ({}); the viewer shows what was read.",
                                            page.error ? page.error->ToString() : "it ends early")};
    }
  }
  Add(problems, WriteFile(dir / "results.json", GradescopeResultsJson(result, options)));
  Add(problems, WriteFile(dir / "junit.xml", JunitXml(result, options)));
  Add(problems, WriteFile(dir / "report.html", ReportHtml(result, notes, options.form)));
  return problems;
}

}  // namespace syrof::grader::report
