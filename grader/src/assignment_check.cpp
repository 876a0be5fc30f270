// `syrof assignment check`'s work: the subjects found and their
// expectations read, each variant made by scripts/broken-variant.sh, every
// subject graded as a student's submission on worker threads, judged, and
// the table.
#include "syrof/grader/assignment_check.h"

#include <fcntl.h>
#include <unistd.h>

#include <algorithm>
#include <array>
#include <atomic>
#include <cerrno>
#include <chrono>
#include <cstdio>
#include <cstring>
#include <filesystem>
#include <mutex>
#include <thread>

#include "syrof/grader/grade_json.h"
#include "syrof/grader/outputs.h"
#include "syrof/grader/table.h"
#include "syrof/process/fd.h"
#include "syrof/process/spawn.h"

namespace syrof::grader {
namespace {

namespace fs = std::filesystem;
using assignment::Expected;
using assignment::SubmissionResult;
using assignment::TestResult;
using Clock = std::chrono::steady_clock;

std::string Hundredths(double points) {
  char text[64];
  std::snprintf(text, sizeof text, "%.2f", points);
  return text;
}

lab::Error FolderError(const fs::path& path, const std::string& message) { return {path.string(), 0, 0, message}; }

lab::Error PointsError(const std::string& file, const Expected& expected, const std::string& message) {
  return {file, expected.points_line, expected.points_column, "points: " + message};
}

// Reads `folder`/expected.yaml into `subject` when it exists (required for
// a variant) and holds it to its role's rule.
std::optional<lab::Error> ReadExpectation(const assignment::Assignment& assignment, CheckSubject& subject) {
  const std::string file = (fs::path(subject.folder) / "expected.yaml").string();
  std::error_code error;
  if (!fs::is_regular_file(file, error)) {
    if (subject.role != SubjectRole::kBrokenVariant) return std::nullopt;
    return FolderError(file, "missing: a broken variant says in expected.yaml the points it must get and the "
                             "criteria it loses (docs/grading.md, \"Broken variants\")");
  }
  const assignment::ExpectedLoad loaded = assignment::LoadExpectedFile(file, assignment);
  if (!loaded.ok()) return loaded.error;
  const Expected& expected = *loaded.expected;
  const std::string full = Hundredths(assignment.points);
  if (subject.role == SubjectRole::kReference && (expected.points != assignment.points || !expected.loses.empty())) {
    return PointsError(file, expected, "a reference gets full marks (" + full + ", loses []) on every run, not " +
                                           Hundredths(expected.points) + " losing " +
                                           assignment::CriteriaText(expected.loses));
  }
  if (subject.role != SubjectRole::kReference && expected.points >= assignment.points) {
    return PointsError(file, expected,
                       "the " + std::string(subject.role == SubjectRole::kStarter ? "starter" : "broken variant") +
                           " is expected to get full marks (" + full +
                           "), so checking it would catch nothing; it must lose points");
  }
  subject.expected = expected;
  return std::nullopt;
}

// Runs `command` (an executable and its arguments), its output and errors
// kept in `output`. Returns its exit status, or -1 when it could not start.
int RunProgram(const std::vector<std::string>& command, std::string& output) {
  int pipe_fds[2];
  if (pipe2(pipe_fds, O_CLOEXEC) != 0) {
    output = std::string("cannot make a pipe: ") + std::strerror(errno);
    return -1;
  }
  const process::Fd read_end(pipe_fds[0]);
  process::Fd write_end(pipe_fds[1]);
  process::Command program;
  program.argv = command;
  program.inherit_environment = true;
  program.descriptors = {{STDOUT_FILENO, write_end.get()}, {STDERR_FILENO, write_end.get()}};
  process::Child child = process::Spawn(program);
  write_end.Reset();
  if (!child.started()) {
    output = "cannot start " + command[0] + ": " + std::strerror(child.start_error());
    return -1;
  }
  char buffer[4096];
  for (ssize_t got; (got = read(read_end.get(), buffer, sizeof buffer)) != 0;) {
    if (got < 0) {
      if (errno == EINTR) continue;
      break;
    }
    output.append(buffer, static_cast<size_t>(got));
  }
  const process::ExitStatus status = child.Reap();
  return status.exited() ? status.code : -1;
}

// Makes a variant's project in `dir` with the script; what went wrong, if
// anything (the script's own output when it says).
std::optional<lab::Error> MakeVariant(const std::string& script, const assignment::Assignment& assignment,
                                      const CheckSubject& subject, const fs::path& dir) {
  std::error_code error;
  if (script.empty() || !fs::is_regular_file(script, error)) {
    return lab::Error{.where = "",
                      .message = "cannot make the variant: scripts/broken-variant.sh was not found" +
                                 (script.empty() ? std::string() : " (looked for " + script + ")")};
  }
  fs::remove_all(dir, error);
  std::string output;
  const int status = RunProgram({script, fs::absolute(assignment.folder).string(), subject.variant, dir.string()},
                                output);
  if (status == 0) return std::nullopt;
  while (!output.empty() && output.back() == '\n') output.pop_back();
  return lab::Error{.where = "",
                    .message = output.empty() ? "broken-variant.sh failed (status " + std::to_string(status) + ")"
                                              : output};
}

std::string FirstLostTest(const SubmissionResult& result) {
  for (const TestResult& test : result.tests) {
    if (!test.passed) {
      return test.name + (test.visibility == assignment::Visibility::kHidden ? " (hidden)" : "") + ": " +
             FirstLoss(test);
    }
  }
  return {};
}

SubjectOutcome CheckOne(const assignment::Assignment& assignment, const CheckSubject& subject, const fs::path& out,
                        const GradeOptions& grade, const std::string& script) {
  const auto started = Clock::now();
  SubjectOutcome outcome;
  outcome.subject = subject;
  std::string project = subject.folder;
  if (subject.role == SubjectRole::kBrokenVariant) {
    const fs::path made = out / "variants" / subject.variant;
    if (std::optional<lab::Error> problem = MakeVariant(script, assignment, subject, made)) {
      outcome.problems.push_back(problem->ToString());
      outcome.result.max_points = assignment.points;
      outcome.result.build.verdict = assignment::BuildVerdict::kNotMade;
      outcome.wall_seconds = std::chrono::duration<double>(Clock::now() - started).count();
      return outcome;
    }
    project = made.string();
  }
  const std::string subject_out = (out / subject.name).string();
  std::vector<std::string> notes;
  if (subject.probe) {
    // The hidden runs only, on this student's seeds (the public runs and
    // the search tests, which have no seeds, are the reference's own,
    // already checked).
    assignment::Assignment hidden_only = assignment;
    hidden_only.public_runs.clear();
    hidden_only.search_tests.clear();
    GradeOptions probed = grade;
    probed.student_seeds = subject.probe;
    outcome.result = GradeSubmission(hidden_only, project, subject_out, probed, notes);
  } else {
    outcome.result = GradeSubmission(assignment, project, subject_out, grade, notes);
  }
  outcome.result.submission = subject.name;
  outcome.problems = JudgeSubject(subject, outcome.result);
  const std::string hash = InputsHash(project, assignment.folder, false);
  if (std::optional<lab::Error> problem = WriteSubmissionOutputs(outcome.result, hash, notes, subject_out)) {
    outcome.problems.push_back(problem->ToString());
  }
  outcome.wall_seconds = std::chrono::duration<double>(Clock::now() - started).count();
  return outcome;
}

std::string ExpectedText(const CheckSubject& subject, double assignment_points) {
  if (subject.expected) {
    return Hundredths(subject.expected->points) + ", loses " + assignment::CriteriaText(subject.expected->loses);
  }
  if (subject.role == SubjectRole::kReference) return Hundredths(assignment_points) + ", loses none";
  return "below " + Hundredths(assignment_points);
}

std::string GotText(const SubjectOutcome& outcome) {
  if (!outcome.result.build.ok()) return outcome.result.build.verdict == assignment::BuildVerdict::kNotMade ? "not made" : "did not build";
  return Hundredths(outcome.result.points) + ", loses " + assignment::CriteriaText(assignment::LostCriteria(outcome.result));
}

}  // namespace

std::optional<lab::Error> FindCheckSubjects(const assignment::Assignment& assignment,
                                            std::vector<CheckSubject>& subjects) {
  subjects.clear();
  const fs::path folder(assignment.folder);
  std::error_code error;
  const std::pair<const char*, SubjectRole> projects[] = {{"reference", SubjectRole::kReference},
                                                          {"starter", SubjectRole::kStarter}};
  for (const auto& [name, role] : projects) {
    if (!fs::is_directory(folder / name, error)) {
      return FolderError(folder / name, std::string("no such folder: an assignment has a ") + name +
                                            (role == SubjectRole::kReference
                                                 ? " (a solution with full marks on every run)"
                                                 : " (what students get: it builds and loads, and does not solve it)") +
                                            "; docs/grading.md, \"An assignment's folder\"");
    }
    CheckSubject subject;
    subject.name = name;
    subject.role = role;
    subject.folder = (folder / name).string();
    if (std::optional<lab::Error> problem = ReadExpectation(assignment, subject)) return problem;
    subjects.push_back(std::move(subject));
  }
  std::vector<CheckSubject> variants;
  if (fs::is_directory(folder / "broken", error)) {
    for (fs::directory_iterator it(folder / "broken", error); !error && it != fs::directory_iterator();
         it.increment(error)) {
      const std::string variant = it->path().filename().string();
      if (variant.empty() || variant[0] == '.' || !it->is_directory(error)) continue;
      CheckSubject subject;
      subject.name = "broken/" + variant;
      subject.role = SubjectRole::kBrokenVariant;
      subject.folder = it->path().string();
      subject.variant = variant;
      if (!fs::is_regular_file(it->path() / "mistake.patch", error)) {
        return FolderError(it->path() / "mistake.patch",
                           "missing: a broken variant is its reference with the mistake in mistake.patch "
                           "(scripts/broken-variant.sh --write-patch writes it; docs/grading.md, \"Broken variants\")");
      }
      if (std::optional<lab::Error> problem = ReadExpectation(assignment, subject)) return problem;
      variants.push_back(std::move(subject));
    }
  }
  std::sort(variants.begin(), variants.end(),
            [](const CheckSubject& a, const CheckSubject& b) { return a.name < b.name; });
  for (CheckSubject& variant : variants) subjects.push_back(std::move(variant));
  return std::nullopt;
}

std::vector<CheckSubject> ProbeSubjects(const CheckSubject& reference, int count, const std::string& course_secret) {
  std::vector<CheckSubject> probes;
  for (int i = 1; i <= count; ++i) {
    CheckSubject probe = reference;
    probe.name = "probe/" + std::to_string(i);
    probe.expected.reset();
    probe.probe = StudentSeeds{course_secret, "probe-" + std::to_string(i)};
    probes.push_back(std::move(probe));
  }
  return probes;
}

std::vector<std::string> JudgeSubject(const CheckSubject& subject, const SubmissionResult& result) {
  std::vector<std::string> problems;
  if (!result.build.ok()) {
    problems.push_back("did not build (" + std::string(ToString(result.build.verdict)) + "): " + result.build.detail);
    return problems;
  }
  if (subject.expected) problems = assignment::CompareWithExpected(result, *subject.expected);
  const bool full_marks = result.points == result.max_points && result.tests_passed == static_cast<int>(result.tests.size());
  if (subject.role == SubjectRole::kReference && !full_marks) {
    problems.push_back("a reference gets full marks on every run; " +
                       std::to_string(result.tests.size() - static_cast<size_t>(result.tests_passed)) + " of " +
                       std::to_string(result.tests.size()) + " lost points");
  }
  if (subject.role == SubjectRole::kStarter && !subject.expected && full_marks) {
    problems.push_back("the starter gets full marks: it must leave the task to the student");
  }
  // A probe: every seed the reference failed, with how to rerun it (the
  // seeds are in no file).
  if (subject.probe && !problems.empty()) {
    for (const TestResult& test : result.tests) {
      if (!test.passed) problems.push_back(test.name + ": " + FirstLoss(test) + "\n  rerun: " + test.replay_command);
    }
    return problems;
  }
  // What the first test that lost points says, to start looking.
  if (!problems.empty()) {
    if (const std::string first = FirstLostTest(result); !first.empty()) problems.push_back("first loss: " + first);
  }
  return problems;
}

std::vector<SubjectOutcome> CheckAssignment(const assignment::Assignment& assignment,
                                            const std::vector<CheckSubject>& subjects, const std::string& out_dir,
                                            const CheckOptions& options) {
  std::vector<SubjectOutcome> outcomes(subjects.size());
  const int jobs = std::clamp(options.jobs, 1, 256);
  const int workers = std::max(1, std::min(jobs, static_cast<int>(subjects.size())));
  GradeOptions grade = options.grade;
  grade.public_only = false;
  grade.jobs = std::max(1, jobs / workers);
  grade.on_test = nullptr;
  const fs::path out = fs::absolute(out_dir);
  std::atomic<size_t> next{0};
  std::mutex report_mutex;
  auto work = [&] {
    for (size_t index = next++; index < subjects.size(); index = next++) {
      outcomes[index] = CheckOne(assignment, subjects[index], out, grade, options.broken_variant_script);
      if (options.on_subject) {
        const std::lock_guard<std::mutex> lock(report_mutex);
        options.on_subject(outcomes[index]);
      }
    }
  };
  std::vector<std::thread> threads;
  for (int i = 1; i < workers; ++i) threads.emplace_back(work);
  work();
  for (std::thread& thread : threads) thread.join();
  return outcomes;
}

void PrintCheckTable(const std::vector<SubjectOutcome>& outcomes, double assignment_points, std::ostream& out) {
  std::vector<std::array<std::string, 3>> rows;  // subject, expected, got
  std::array<size_t, 3> width = {7, 8, 3};
  for (const SubjectOutcome& outcome : outcomes) {
    rows.push_back({outcome.subject.name, ExpectedText(outcome.subject, assignment_points), GotText(outcome)});
    for (size_t i = 0; i < 3; ++i) width[i] = std::max(width[i], rows.back()[i].size());
  }
  auto pad = [](const std::string& text, size_t to) { return text + std::string(to - text.size(), ' '); };
  out << "  " << pad("subject", width[0]) << "  " << pad("expected", width[1]) << "  " << pad("got", width[2])
      << "  result  seconds\n";
  for (size_t row = 0; row < outcomes.size(); ++row) {
    char seconds[32];
    std::snprintf(seconds, sizeof seconds, "%7.1f", outcomes[row].wall_seconds);
    out << "  " << pad(rows[row][0], width[0]) << "  " << pad(rows[row][1], width[1]) << "  "
        << pad(rows[row][2], width[2]) << "  " << (outcomes[row].ok() ? "PASS  " : "FAIL  ") << "  " << seconds
        << "\n";
    for (const std::string& problem : outcomes[row].problems) {
      // The script's messages run over several lines: each is indented.
      for (size_t start = 0; start < problem.size();) {
        const size_t end = std::min(problem.find('\n', start), problem.size());
        out << "  " << std::string(width[0], ' ') << "  " << problem.substr(start, end - start) << "\n";
        start = end + 1;
      }
    }
  }
}

}  // namespace syrof::grader
