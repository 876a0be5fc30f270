// `syrof assignment check DIR`: the assignment loaded, its subjects found,
// each graded by the grader's own runner (grader::CheckAssignment, which
// grades as `syrof grade` does), and the table.
#include <fmt/format.h>
#include <fmt/ostream.h>

#include <sys/resource.h>

#include <algorithm>
#include <chrono>
#include <filesystem>

#include "assignment_command.h"
#include "exit_status.h"
#include "grade_command.h"
#include "syrof/assignment/assignment.h"
#include "syrof/grader/assignment_check.h"
#include "syrof/grader/grade.h"

#ifndef SYROF_SOURCE_ASSIGNMENTS_DIR
#define SYROF_SOURCE_ASSIGNMENTS_DIR ""
#endif
#ifndef SYROF_BROKEN_VARIANT_SCRIPT
#define SYROF_BROKEN_VARIANT_SCRIPT ""
#endif

namespace syrof::cli {
// A named namespace: the subcommands compile as one unity translation unit.
namespace assignment_check {

namespace fs = std::filesystem;

// The subjects `only` names, in the check's order; empty with `problem` set
// when one of them names none.
std::vector<grader::CheckSubject> Choose(const std::vector<grader::CheckSubject>& subjects,
                                         const std::vector<std::string>& only, std::string& problem) {
  if (only.empty()) return subjects;
  std::vector<bool> chosen(subjects.size(), false);
  for (const std::string& name : only) {
    bool found = false;
    for (size_t i = 0; i < subjects.size(); ++i) {
      if (subjects[i].name == name || (!subjects[i].variant.empty() && subjects[i].variant == name)) {
        chosen[i] = true;
        found = true;
      }
    }
    if (!found) {
      std::string names;
      for (const grader::CheckSubject& subject : subjects) names += (names.empty() ? "" : ", ") + subject.name;
      problem = fmt::format("--only '{}' names no subject of this assignment; its subjects are: {}", name, names);
      return {};
    }
  }
  std::vector<grader::CheckSubject> result;
  for (size_t i = 0; i < subjects.size(); ++i) {
    if (chosen[i]) result.push_back(subjects[i]);
  }
  return result;
}

// CPU seconds this process and its waited-for children have used.
double CpuSeconds() {
  double seconds = 0;
  for (const int who : {RUSAGE_SELF, RUSAGE_CHILDREN}) {
    rusage usage{};
    getrusage(who, &usage);
    seconds += static_cast<double>(usage.ru_utime.tv_sec + usage.ru_stime.tv_sec) +
               static_cast<double>(usage.ru_utime.tv_usec + usage.ru_stime.tv_usec) * 1e-6;
  }
  return seconds;
}

// --gradescope-budget: the reference graded alone (one job, after every
// subject, so nothing else shares the process), its CPU time, and what it
// projects under Gradescope's half a CPU. Prints the line; false when the
// projection is over half the budget.
bool CheckGradescopeBudget(const grader::assignment::Assignment& checked, const grader::CheckSubject& reference,
                           const grader::CheckOptions& check, double budget_s, const std::string& out_dir,
                           std::ostream& out) {
  grader::GradeOptions grade = check.grade;
  grade.jobs = 1;
  grade.on_test = nullptr;
  std::vector<std::string> notes;
  const double before = CpuSeconds();
  const auto started = std::chrono::steady_clock::now();
  grader::GradeSubmission(checked, reference.folder, (fs::path(out_dir) / "gradescope-budget").string(), grade,
                          notes);
  const double cpu_s = CpuSeconds() - before;
  const double wall_s = std::chrono::duration<double>(std::chrono::steady_clock::now() - started).count();
  const double projected_s = 2 * cpu_s;  // half a CPU: twice the CPU time, at best
  const bool fits = projected_s <= budget_s / 2;
  fmt::print(out,
             "\nGradescope budget: the reference took {:.1f} CPU-s ({:.1f} s here, one job): about {:.0f} s under "
             "Gradescope's half a CPU, {} half of the {:.0f} s budget{}\n",
             cpu_s, wall_s, projected_s, fits ? "within" : "MORE than", budget_s,
             fits ? ""
                  : ": a slow submission may reach Gradescope's timeout; shorten the runs or drop seeds "
                    "(docs/grading.md, \"Gradescope's limits\")");
  return fits;
}

}  // namespace assignment_check

int RunAssignmentCheck(const AssignmentCheckOptions& options, std::ostream& out, std::ostream& err) {
  namespace fs = std::filesystem;
  namespace assignment = grader::assignment;
  std::vector<std::string> looked;
  const std::string found = grader::FindAssignment(options.assignment, SYROF_SOURCE_ASSIGNMENTS_DIR, looked);
  if (found.empty()) {
    fmt::print(err, "syrof assignment check: no assignment.yaml in '{}'; looked in:\n", options.assignment);
    for (const std::string& place : looked) fmt::print(err, "  {}\n", place);
    fmt::print(err, "Give an assignment's folder (syrof assignment new NAME writes one).\n");
    return kBadInput;
  }
  const assignment::LoadResult loaded = assignment::LoadAssignmentFile(found);
  if (!loaded.ok()) {
    fmt::print(err, "syrof assignment check: {}\n", loaded.error->ToString());
    return kBadInput;
  }
  std::vector<grader::CheckSubject> subjects;
  if (const std::optional<lab::Error> problem = grader::FindCheckSubjects(*loaded.assignment, subjects)) {
    fmt::print(err, "syrof assignment check: {}\n", problem->ToString());
    return kBadInput;
  }
  std::string problem;
  subjects = assignment_check::Choose(subjects, options.only, problem);
  if (!problem.empty()) {
    fmt::print(err, "syrof assignment check: {}\n", problem);
    return kBadInput;
  }
  if (options.probe_students > 0) {
    const auto reference = std::find_if(subjects.begin(), subjects.end(), [](const grader::CheckSubject& subject) {
      return subject.role == grader::SubjectRole::kReference;
    });
    if (reference == subjects.end()) {
      fmt::print(err, "syrof assignment check: --probe-students grades the reference: add it to --only\n");
      return kBadInput;
    }
    if (loaded.assignment->hidden_runs.empty()) {
      fmt::print(err, "syrof assignment check: --probe-students: '{}' has no hidden runs, whose seeds a student's "
                      "are derived for\n", loaded.assignment->name);
      return kBadInput;
    }
    for (grader::CheckSubject& probe :
         grader::ProbeSubjects(*reference, options.probe_students, grader::kProbeSecret)) {
      subjects.push_back(std::move(probe));
    }
  }
  if (!MayGradeHere("syrof assignment check", options.unsafe_no_file_isolation, out, err)) return kBadInput;

  const assignment::Assignment& checked = *loaded.assignment;
  const std::string out_dir = options.out_dir.empty() ? "check-out/" + checked.name : options.out_dir;
  grader::CheckOptions check;
  check.jobs = options.jobs;
  check.grade.build.timeout_s = options.build_timeout_s;
  check.grade.build.allow_unconfined = options.unsafe_no_file_isolation;
  check.broken_variant_script =
      options.broken_variant_script.empty() ? SYROF_BROKEN_VARIANT_SCRIPT : options.broken_variant_script;
  const size_t runs = grader::PlanTests(checked, false).size();
  const size_t probes = static_cast<size_t>(options.probe_students);
  if (!options.quiet) {
    fmt::print(out, "syrof assignment check: {} ({}), {} subject{} x {} runs{}, {} job{}, into {}\n", checked.name,
               checked.title, subjects.size() - probes, subjects.size() - probes == 1 ? "" : "s", runs,
               probes == 0 ? ""
                           : fmt::format(", and the reference on {} probe {} hidden seeds ({} runs each)",
                                         probes, probes == 1 ? "student's" : "students'", grader::PlanTests(checked, false).size() -
                                                                             grader::PlanTests(checked, true).size()),
               options.jobs, options.jobs == 1 ? "" : "s", out_dir);
    check.on_subject = [&out](const grader::SubjectOutcome& outcome) {
      fmt::print(out, "  {:<32} {}  {:.1f} s\n", outcome.subject.name, outcome.ok() ? "PASS" : "FAIL",
                 outcome.wall_seconds);
    };
  }
  const auto started = std::chrono::steady_clock::now();
  const std::vector<grader::SubjectOutcome> outcomes = grader::CheckAssignment(checked, subjects, out_dir, check);
  const double seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - started).count();

  out << "\n" << checked.title << " (" << checked.name << "): " << runs << " runs per subject, public and hidden\n";
  grader::PrintCheckTable(outcomes, checked.points, out);
  std::string failed;
  for (const grader::SubjectOutcome& outcome : outcomes) {
    if (!outcome.ok()) failed += (failed.empty() ? "" : ", ") + outcome.subject.name;
  }
  const size_t passed = static_cast<size_t>(
      std::count_if(outcomes.begin(), outcomes.end(), [](const grader::SubjectOutcome& o) { return o.ok(); }));
  if (options.gradescope_budget_s > 0) {
    const auto reference = std::find_if(subjects.begin(), subjects.end(), [](const grader::CheckSubject& subject) {
      return subject.role == grader::SubjectRole::kReference && !subject.probe;
    });
    if (reference != subjects.end()) {
      assignment_check::CheckGradescopeBudget(checked, *reference, check, options.gradescope_budget_s, out_dir, out);
    } else {
      fmt::print(out, "\nGradescope budget: not measured, the reference is not among the subjects (--only)\n");
    }
  }
  if (failed.empty()) {
    fmt::print(out, "\nAll {} as expected, in {:.1f} s; reports in {}/<subject>/\n", outcomes.size(), seconds,
               out_dir);
    return kOk;
  }
  fmt::print(out, "\n{} of {} as expected; not as expected: {}. In {:.1f} s; reports in {}/<subject>/\n", passed,
             outcomes.size(), failed, seconds, out_dir);
  return kNotAsExpected;
}

}  // namespace syrof::cli
