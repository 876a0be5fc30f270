#include "grade_command.h"

#include <fmt/format.h>
#include <fmt/ostream.h>

#include <chrono>
#include <cstdlib>
#include <filesystem>
#include <optional>

#include "syrof/process/landlock.h"
#include "syrof/assignment/assignment.h"
#include "syrof/grader/class_grading.h"
#include "syrof/grader/grade.h"
#include "syrof/grader/grade_json.h"
#include "syrof/grader/mix.h"
#include "syrof/grader/outputs.h"
#include "syrof/grader/student_seeds.h"
#include "syrof/grader/table.h"
#include "exit_status.h"

#ifndef SYROF_SOURCE_ASSIGNMENTS_DIR
#define SYROF_SOURCE_ASSIGNMENTS_DIR ""
#endif

namespace syrof::cli {
namespace {

namespace fs = std::filesystem;
namespace assignment = grader::assignment;
using Clock = std::chrono::steady_clock;

double Since(Clock::time_point started) { return std::chrono::duration<double>(Clock::now() - started).count(); }

// Finds and loads --assignment; prints the error and returns empty when it
// cannot.
std::optional<assignment::Assignment> LoadAssignment(const GradeOptions& options, std::string& folder,
                                                     std::ostream& out, std::ostream& err) {
  std::vector<std::string> looked;
  const std::string found = grader::FindAssignment(options.assignment, SYROF_SOURCE_ASSIGNMENTS_DIR, looked);
  if (found.empty()) {
    fmt::print(err, "syrof grade: no assignment '{}'; looked in:\n", options.assignment);
    for (const std::string& place : looked) fmt::print(err, "  {}\n", place);
    fmt::print(err, "Give a folder holding assignment.yaml, or set SYROF_ASSIGNMENTS_DIR.\n");
    return std::nullopt;
  }
  assignment::LoadOptions load;
  load.allow_missing_hidden = true;
  const assignment::LoadResult loaded = assignment::LoadAssignmentFile(found, load);
  if (!loaded.ok()) {
    fmt::print(err, "syrof grade: {}\n", loaded.error->ToString());
    return std::nullopt;
  }
  folder = loaded.assignment->folder;
  if (loaded.assignment->hidden_missing && !options.public_only) {
    fmt::print(out, "syrof grade: this copy of '{}' has no hidden scenario files: grading the public tests only\n",
               loaded.assignment->name);
  }
  return loaded.assignment;
}

// The course secret for per-student seeds: --course-secret-file, else
// $SYROF_COURSE_SECRET. Prints why and returns empty when there is none or
// it is unusable.
std::optional<std::string> CourseSecret(const GradeOptions& options, std::ostream& err) {
  if (!options.course_secret_file.empty()) {
    grader::CourseSecretOrError read = grader::ReadCourseSecretFile(options.course_secret_file);
    if (!read.ok()) fmt::print(err, "syrof grade: {}\n", read.error->ToString());
    return std::move(read.secret);
  }
  const char* variable = std::getenv(grader::kCourseSecretVariable);
  if (variable == nullptr || *variable == '\0') {
    fmt::print(err,
               "syrof grade: per-student hidden seeds need the course secret: set {} or give "
               "--course-secret-file FILE (never the secret itself on the command line, where `ps` shows it)\n",
               grader::kCourseSecretVariable);
    return std::nullopt;
  }
  if (const std::optional<lab::Error> problem = grader::CheckCourseSecret(variable)) {
    fmt::print(err, "syrof grade: {}: {}\n", grader::kCourseSecretVariable, problem->ToString());
    return std::nullopt;
  }
  return std::string(variable);
}

// Fills grade.student_seeds when per-student seeds were asked for. False
// (the reason on `err`) when they were and cannot be derived.
bool ResolveStudentSeeds(const GradeOptions& options, grader::GradeOptions& grade, std::ostream& err) {
  const bool asked =
      !options.student_seed.empty() || !options.gradescope_metadata.empty() || options.per_student_seeds;
  if (!asked) {
    if (!options.course_secret_file.empty()) {
      fmt::print(err, "syrof grade: --course-secret-file is for per-student hidden seeds: give --student-seed ID, "
                      "--gradescope-metadata FILE or, with --class, --per-student-seeds\n");
      return false;
    }
    return true;
  }
  std::optional<std::string> secret = CourseSecret(options, err);
  if (!secret) return false;
  grader::StudentSeeds seeds{*std::move(secret), options.student_seed};
  if (!options.gradescope_metadata.empty()) {
    const grader::StudentOrError student = grader::StudentFromGradescopeMetadataFile(options.gradescope_metadata);
    if (!student.ok()) {
      fmt::print(err, "syrof grade: {}\n", student.error->ToString());
      return false;
    }
    seeds.student = *student.student;
  }
  grade.student_seeds = std::move(seeds);
  return true;
}

grader::GradeOptions GradeOptionsOf(const GradeOptions& options) {
  grader::GradeOptions grade;
  grade.public_only = options.public_only;
  grade.jobs = options.jobs;
  grade.build.timeout_s = options.build_timeout_s;
  grade.build.allow_unconfined = options.unsafe_no_file_isolation;
  return grade;
}

bool IsFolder(const std::string& path) {
  std::error_code error;
  return fs::is_directory(path, error);
}

int GradeOne(const GradeOptions& options, std::ostream& out, std::ostream& err) {
  if (!IsFolder(options.submission)) {
    fmt::print(err, "syrof grade: the submission '{}' is not a folder\n", options.submission);
    return kBadInput;
  }
  std::string folder;
  const std::optional<assignment::Assignment> loaded = LoadAssignment(options, folder, out, err);
  if (!loaded) return kBadInput;
  const std::string name = fs::absolute(options.submission).lexically_normal().filename().string();
  const std::string out_dir = options.out_dir.empty() ? "grade-out/" + (name.empty() ? "submission" : name)
                                                      : options.out_dir;
  grader::GradeOptions grade = GradeOptionsOf(options);
  if (!ResolveStudentSeeds(options, grade, err)) return kBadInput;
  if (!options.quiet) {
    fmt::print(out, "syrof grade: {} for {} ({} jobs), into {}{}\n", options.submission, loaded->name, options.jobs,
               out_dir, options.report == "full" ? " (report.html: the instructor's full form)" : "");
    if (grade.student_seeds) {
      fmt::print(out, "syrof grade: hidden seeds derived for student '{}'\n", grade.student_seeds->student);
    }
    grade.on_test = [&out](const assignment::TestResult& test) {
      fmt::print(out, "  {:<40} {}  {:.1f} s\n", test.name, test.passed ? "PASS" : "FAIL", test.wall_seconds);
    };
  }
  const auto started = Clock::now();
  if (options.deadline_s > 0) {
    grade.deadline = started + std::chrono::duration_cast<Clock::duration>(
                                   std::chrono::duration<double>(options.deadline_s));
  }
  // Past the assignment's hidden_feedback_submissions, the hidden tests'
  // results wait for the due date (--submission-metadata).
  std::optional<grader::report::ReportOptions::FeedbackCap> feedback_withheld;
  if (!options.submission_metadata.empty()) {
    const grader::SubmissionNumberOrError submission =
        grader::SubmissionNumberFromGradescopeMetadataFile(options.submission_metadata);
    if (!submission.ok()) {
      fmt::print(err, "syrof grade: {}\n", submission.error->ToString());
      return kBadInput;
    }
    const int number = *submission.number;
    if (loaded->hidden_feedback_submissions > 0 && number > loaded->hidden_feedback_submissions) {
      feedback_withheld = grader::report::ReportOptions::FeedbackCap{number, loaded->hidden_feedback_submissions};
    }
  }
  // results.json kept valid while grading runs (--gradescope-results).
  const assignment::Assignment graded = grader::GradedAssignment(*loaded, grade);
  std::optional<grader::LiveResultsFile> live;
  if (!options.gradescope_results.empty()) {
    assignment::SubmissionResult planned;
    planned.assignment = graded.name;
    planned.title = graded.title;
    planned.public_only = options.public_only || graded.hidden_missing;
    planned.tests = grader::PlanTests(graded, planned.public_only);
    grader::report::ReportOptions live_options;
    live_options.feedback_withheld = feedback_withheld;
    live.emplace(options.gradescope_results, graded, std::move(planned), live_options);
    if (const std::optional<lab::Error> problem = live->Begin()) {
      fmt::print(err, "syrof grade: --gradescope-results: {}\n", problem->ToString());
      return kBadInput;
    }
    grade.on_test = [&live, progress = grade.on_test](const assignment::TestResult& test) {
      if (progress) progress(test);
      live->Record(test);
    };
  }
  std::vector<std::string> notes;
  assignment::SubmissionResult result =
      grader::GradeSubmission(*loaded, options.submission, out_dir, grade, notes);
  const std::string hash = grader::InputsHash(
      options.submission, folder, result.public_only,
      grade.student_seeds && !result.public_only
          ? grader::HiddenSeedsText(grader::GradedAssignment(*loaded, grade))
          : std::string());
  if (const std::optional<lab::Error> problem = grader::WriteSubmissionOutputs(
          result, hash, notes, out_dir, options.report == "full", feedback_withheld)) {
    fmt::print(err, "syrof grade: {}\n", problem->ToString());
    return kInternalError;
  }
  if (live) {
    if (const std::optional<lab::Error> problem = live->Finish(result)) {
      fmt::print(err, "syrof grade: --gradescope-results: {}\n", problem->ToString());
      return kInternalError;
    }
  }
  out << "\n";
  grader::PrintSubmissionTable(result, out_dir, out);
  for (const std::string& note : notes) fmt::print(out, "sandbox: {}\n", note);
  fmt::print(out, "\nBuild {:.1f} s, graded in {:.1f} s; details in {}/grade.json\n", result.build.wall_seconds,
             Since(started), out_dir);
  return 0;
}

int GradeClass(const GradeOptions& options, std::ostream& out, std::ostream& err) {
  if (!IsFolder(options.class_dir)) {
    fmt::print(err, "syrof grade: --class '{}' is not a folder\n", options.class_dir);
    return kBadInput;
  }
  grader::Shard shard;
  if (!options.shard.empty()) {
    const grader::ShardOrError parsed = grader::ParseShard(options.shard);
    if (!parsed.ok()) {
      fmt::print(err, "syrof grade: {}\n", parsed.error->ToString());
      return kBadInput;
    }
    shard = *parsed.shard;
  }
  std::string folder;
  const std::optional<assignment::Assignment> loaded = LoadAssignment(options, folder, out, err);
  if (!loaded) return kBadInput;
  const std::string out_dir = options.out_dir.empty() ? "grade-out/class" : options.out_dir;
  grader::ClassOptions class_options;
  class_options.grade = GradeOptionsOf(options);
  if (!ResolveStudentSeeds(options, class_options.grade, err)) return kBadInput;
  class_options.jobs = options.jobs;
  class_options.shard = shard;
  class_options.resume = !options.regrade;
  class_options.assignment_dir = folder;
  class_options.full_report = options.report == "full";
  const size_t total = grader::ShardOf(grader::ListStudents(options.class_dir), shard).size();
  size_t done = 0;
  if (!options.quiet) {
    fmt::print(out, "syrof grade: class {} ({} students{}) for {}, {} jobs, into {}\n", options.class_dir, total,
               options.shard.empty() ? "" : ", shard " + options.shard, loaded->name, options.jobs, out_dir);
  }
  class_options.on_student = [&](const assignment::SubmissionResult& result, bool resumed) {
    ++done;
    if (options.quiet) return;
    fmt::print(out, "  [{}/{}] {:<24} {:>7.2f}/{:.2f}  {}{}\n", done, total, result.submission, result.points,
               result.max_points, result.build.ok() ? "" : "build " + std::string(ToString(result.build.verdict)),
               resumed ? " (resumed)" : "");
  };
  const auto started = Clock::now();
  const grader::ClassResult result = grader::GradeClass(*loaded, options.class_dir, out_dir, class_options);
  if (!fs::exists(fs::path(out_dir) / "class.csv")) {
    fmt::print(err, "syrof grade: cannot write the class files in {}\n", out_dir);
    return kInternalError;
  }
  out << "\n" << grader::ClassSummary(result.students);
  for (const std::string& note : result.notes) fmt::print(out, "sandbox: {}\n", note);
  fmt::print(out, "Graded {}, resumed {}, in {:.1f} s; {}/class.csv, {}/summary.txt\n", result.graded,
             result.resumed, Since(started), out_dir, out_dir);
  return 0;
}

int GradeMix(const GradeOptions& options, std::ostream& out, std::ostream& err) {
  if (options.mix.size() < 2) {
    fmt::print(err, "syrof grade: --mix needs at least two submissions\n");
    return kBadInput;
  }
  for (const std::string& submission : options.mix) {
    if (!IsFolder(submission)) {
      fmt::print(err, "syrof grade: the submission '{}' is not a folder\n", submission);
      return kBadInput;
    }
  }
  std::string folder;
  const std::optional<assignment::Assignment> loaded = LoadAssignment(options, folder, out, err);
  if (!loaded) return kBadInput;
  if (!loaded->mixable) {
    fmt::print(err,
               "syrof grade: assignment '{}' is not mixable: its README must fix the robots' message format and its "
               "assignment.yaml say 'mixable: true' with its 'message:' format\n",
               loaded->name);
    return kBadInput;
  }
  const std::string out_dir = options.out_dir.empty() ? "grade-out/mix" : options.out_dir;
  grader::GradeOptions grade = GradeOptionsOf(options);
  std::vector<grader::MixEntry> entries;
  for (size_t i = 0; i < options.mix.size(); ++i) {
    const std::string name = fs::absolute(options.mix[i]).lexically_normal().filename().string();
    const std::string build_dir = (fs::path(out_dir) / "builds" / (std::to_string(i) + "-" + name)).string();
    std::vector<std::string> notes;
    const assignment::BuildResult build = grader::BuildSubmission(options.mix[i], build_dir, grade.build, notes);
    if (!build.ok()) {
      fmt::print(out, "syrof grade: {} did not build ({}): {}; see {}/build.log\n", name, ToString(build.verdict), build.detail,
                 build_dir);
      return 0;
    }
    entries.push_back({name, build.library_path});
  }
  const std::vector<grader::MixRun> runs = grader::RunMix(*loaded, entries, out_dir, grade);
  grader::PrintMixReport(runs, entries, out);
  return 0;
}

int Merge(const GradeOptions& options, std::ostream& out, std::ostream& err) {
  if (options.merge_dirs.empty()) {
    fmt::print(err, "syrof grade merge: name the class outputs to merge (OUT1 OUT2 ...)\n");
    return kBadInput;
  }
  const grader::MergedClass merged = grader::MergeClassOutputs(options.merge_dirs, options.merge_out);
  if (!merged.ok()) {
    fmt::print(err, "syrof grade merge: {}\n", merged.error->ToString());
    return kBadInput;
  }
  const std::vector<assignment::SubmissionResult>& students = *merged.students;
  out << grader::ClassSummary(students);
  fmt::print(out, "Merged {} students from {} folders into {}/class.csv and {}/summary.txt\n", students.size(),
             options.merge_dirs.size(), options.merge_out, options.merge_out);
  return 0;
}

}  // namespace

CLI::App* SetupGradeCommand(CLI::App& app, GradeOptions& options) {
  CLI::App* grade = app.add_subcommand(
      "grade", "Grade a submission (or a class, or a mixed swarm) against an assignment; docs/grading.md");
  grade->add_option("submission", options.submission,
                    "The submission: a folder with a CMakeLists.txt (as syrof new writes) or C/C++ sources");
  grade->add_option("--assignment", options.assignment,
                    "The assignment: a folder with assignment.yaml, or a NAME found in $SYROF_ASSIGNMENTS_DIR, "
                    "the installed share/syrof/assignments or the source tree");
  CLI::Option* class_option =
      grade->add_option("--class", options.class_dir, "Grade a class: one folder per student in this folder");
  CLI::Option* mix_option = grade->add_option(
      "--mix", options.mix, "Run swarms mixing these submissions' robots (robot i runs submission i mod k)");
  grade->add_flag("--public-only", options.public_only, "Leave the hidden tests out");
  grade->add_option("--jobs", options.jobs, "Runs (or, with --class, students) side by side (default 1)")
      ->check(CLI::Range(1, 256));
  grade->add_option("--out", options.out_dir, "Output folder (default grade-out/<submission>)");
  grade->add_option("--build-timeout-s", options.build_timeout_s, "Wall time for a build, seconds (default 120)")
      ->check(CLI::Range(1.0, 3600.0));
  grade->add_option("--shard", options.shard, "With --class: grade the I-th of N slices of the sorted students")
      ->needs(class_option);
  grade->add_flag("--regrade", options.regrade, "With --class: grade every student again (no resume)")
      ->needs(class_option);
  grade->add_flag("--quiet", options.quiet, "No progress lines");
  CLI::Option* report_option =
      grade->add_option("--report", options.report,
                        "report.html's form: student (default; a hidden test shows only its name, points and "
                        "pass/fail) or full (the instructor's: hidden tests with their reasons and viewers)")
          ->check(CLI::IsMember({"student", "full"}));
  CLI::Option* deadline_option =
      grade->add_option("--deadline-s", options.deadline_s,
                        "One submission: a test not started this many seconds after grading began is not run "
                        "(0 points, the reason said; run_autograder's deadline below Gradescope's timeout)")
          ->check(CLI::Range(0.0, 86400.0));
  CLI::Option* results_option = grade->add_option(
      "--gradescope-results", options.gradescope_results,
      "One submission: Gradescope's results.json also at this path, valid at every moment (rewritten after each "
      "test), so an autograder stopped by Gradescope's timeout keeps the tests that finished");
  CLI::Option* submission_metadata_option = grade->add_option(
      "--submission-metadata", options.submission_metadata,
      "One submission: Gradescope's submission_metadata.json, for which submission of its student(s) this is "
      "(assignment.yaml's hidden_feedback_submissions)");
  grade->add_flag("--unsafe-no-file-isolation", options.unsafe_no_file_isolation,
                  "Grade even where the kernel has no Landlock (older than 5.13): submissions' builds and "
                  "libraries can then read and write whatever uid 65534 (or yours) can; only for code you trust");
  CLI::Option* student_option = grade->add_option(
      "--student-seed", options.student_seed,
      "Derive the hidden tests' seeds from this student id (an email, a roster id) and the course secret "
      "($SYROF_COURSE_SECRET or --course-secret-file) instead of the listed ones");
  CLI::Option* metadata_option = grade->add_option(
      "--gradescope-metadata", options.gradescope_metadata,
      "As --student-seed, the id taken from Gradescope's submission_metadata.json (its users' ids, sorted, "
      "joined with '+')");
  CLI::Option* per_student_option = grade->add_flag(
      "--per-student-seeds", options.per_student_seeds,
      "With --class: derive each student's hidden seeds from its folder's name and the course secret");
  grade->add_option("--course-secret-file", options.course_secret_file,
                    "The course secret for per-student seeds, in a file (default: $SYROF_COURSE_SECRET)");
  per_student_option->needs(class_option);
  student_option->excludes(metadata_option);
  student_option->excludes(class_option);
  student_option->excludes(mix_option);
  metadata_option->excludes(class_option);
  metadata_option->excludes(mix_option);
  class_option->excludes(mix_option);
  report_option->excludes(mix_option);
  for (CLI::Option* one_submission : {deadline_option, results_option, submission_metadata_option}) {
    one_submission->excludes(class_option);
    one_submission->excludes(mix_option);
  }

  CLI::App* merge = grade->add_subcommand("merge", "Combine the outputs of class shards into one CSV and summary");
  merge->add_option("outputs", options.merge_dirs, "The shards' --out folders")->required();
  merge->add_option("--out", options.merge_out, "Where class.csv and summary.txt go")->required();
  merge->callback([&options] { options.merge = true; });
  return grade;
}

bool MayGradeHere(const std::string& command, bool unsafe_no_file_isolation, std::ostream& out, std::ostream& err) {
  // Graded code is hostile until proven otherwise: without Landlock its
  // build could read the hidden tests (docs/grading.md, "Threat model").
  if (process::LandlockAbi() != 0) return true;
  if (!unsafe_no_file_isolation) {
    fmt::print(err,
               "{}: this kernel has no Landlock (Linux 5.13 or later, with landlock among its LSMs), so "
               "a submission's build and library could read and write files outside their folders (the hidden "
               "tests, other students' work, the results); refusing to grade.\n"
               "Grade on a newer kernel, or give --unsafe-no-file-isolation for code you trust.\n",
               command);
    return false;
  }
  fmt::print(out, "{}: WARNING: no Landlock on this kernel; grading without file isolation "
                  "(--unsafe-no-file-isolation)\n",
             command);
  return true;
}

int RunGradeCommand(const GradeOptions& options, std::ostream& out, std::ostream& err) {
  if (options.merge) return Merge(options, out, err);
  const int modes = (options.submission.empty() ? 0 : 1) + (options.class_dir.empty() ? 0 : 1) +
                    (options.mix.empty() ? 0 : 1);
  if (modes != 1) {
    fmt::print(err,
               "syrof grade: give one of SUBMISSION_DIR, --class SUBMISSIONS_DIR or --mix SUB1 SUB2 ...\n"
               "Run with --help for more information.\n");
    return kBadInput;
  }
  if (options.assignment.empty()) {
    fmt::print(err, "syrof grade: --assignment NAME|PATH is required\nRun with --help for more information.\n");
    return kBadInput;
  }
  if (!MayGradeHere("syrof grade", options.unsafe_no_file_isolation, out, err)) return kBadInput;
  if (!options.class_dir.empty()) return GradeClass(options, out, err);
  if (!options.mix.empty()) return GradeMix(options, out, err);
  return GradeOne(options, out, err);
}

}  // namespace syrof::cli
