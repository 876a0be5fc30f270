// Grading a class of K copies of assignments/strongest's reference, with
// its search test (search/join_4.yaml as assignment.yaml states it: every
// single lost beacon and every pair in the first epoch, 16,291 patterns,
// since the fork server made pairs affordable), twice: once with the fork server (the
// grader's default: the search test loads the library once and runs each
// robot of each pattern as a copy, docs/app_host.md, "The fork server")
// and once without it (a fresh sandboxed host per robot and pattern).
// Prints, for each way, the seconds per submission (the build, the
// scenario runs and the search test apart), the whole class's wall time on
// J jobs and its projection to 100 submissions; then checks that every
// submission got the same points and the same search result both ways, and
// says so (exit 1 if not).
//
// "Without the fork server" is GradeOptions::fork_server = false (grade.h),
// a switch for benches and tests only: no command-line option sets it.
// SYROF_PRETEND_NO_LANDLOCK=1 also turns the fork server off, but it takes
// Landlock away from every host too, so the two ways would not be the
// same sandbox.
//
// Usage: bench_grade_search_class [--submissions K] [--jobs J] [--public-only]
//                                 [--fresh-first]
// Default: 2 submissions on 2 jobs, every scenario (public and hidden), the
// fork server's pass first (--fresh-first: the other). The figure:
// --submissions 100 --jobs 2 (about 7 minutes on 2 cores, both passes); a
// smaller K projects the wall time to 100 (wall / K x 100).
#include <chrono>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <string>
#include <unistd.h>

#include "syrof/assignment/assignment.h"
#include "syrof/grader/class_grading.h"
#include "syrof/grader/grade.h"

namespace {

namespace fs = std::filesystem;
using Clock = std::chrono::steady_clock;

double Since(Clock::time_point started) { return std::chrono::duration<double>(Clock::now() - started).count(); }

// The 1-minute load average, as uptime prints it: the machine is shared.
double LoadAverage() {
  double load = -1;
  std::ifstream("/proc/loadavg") >> load;
  return load;
}

struct Pass {
  syrof::grader::ClassResult result;
  double wall_s = 0;
  double load_before = 0;
  double load_after = 0;
};

Pass GradeOnce(const syrof::grader::assignment::Assignment& assignment, const fs::path& class_dir,
               const fs::path& out, int jobs, bool public_only, bool fork_server) {
  syrof::grader::ClassOptions options;
  options.jobs = jobs;
  options.resume = false;
  options.assignment_dir = SYROF_STRONGEST;
  options.grade.public_only = public_only;
  options.grade.fork_server = fork_server;
  Pass pass;
  pass.load_before = LoadAverage();
  const auto started = Clock::now();
  pass.result = syrof::grader::GradeClass(assignment, class_dir.string(), out.string(), options);
  pass.wall_s = Since(started);
  pass.load_after = LoadAverage();
  return pass;
}

void Print(const char* way, const Pass& pass, int submissions, int jobs) {
  double build_s = 0;
  double runs_s = 0;
  double search_s = 0;
  int full_marks = 0;
  for (const auto& student : pass.result.students) {
    build_s += student.build.wall_seconds;
    for (const auto& test : student.tests) (test.search ? search_s : runs_s) += test.wall_seconds;
    full_marks += student.points == student.max_points ? 1 : 0;
  }
  const double n = submissions;
  std::printf("  %-20s per submission: build %6.2f s, scenario runs %6.2f s, search test %7.2f s (busy time);\n", way,
              build_s / n, runs_s / n, search_s / n);
  std::printf("  %-20s class: %7.1f s wall on %d jobs (%d of %d at full marks, load %.1f -> %.1f); "
              "100 submissions: %.0f s (%.1f min)\n",
              "", pass.wall_s, jobs, full_marks, submissions, pass.load_before, pass.load_after, pass.wall_s / n * 100,
              pass.wall_s / n * 100 / 60);
}

// The same points, the same tests passed, and the same search result (its
// reason names the patterns run, or the counterexample), submission by
// submission.
bool SameResults(const Pass& a, const Pass& b, std::string& why) {
  if (a.result.students.size() != b.result.students.size()) {
    why = "not the same number of students";
    return false;
  }
  for (size_t i = 0; i < a.result.students.size(); ++i) {
    const auto& x = a.result.students[i];
    const auto& y = b.result.students[i];
    if (x.points != y.points || x.tests.size() != y.tests.size()) {
      why = x.submission + ": " + std::to_string(x.points) + " points against " + std::to_string(y.points);
      return false;
    }
    for (size_t t = 0; t < x.tests.size(); ++t) {
      const auto& p = x.tests[t];
      const auto& q = y.tests[t];
      const std::string reason_p = p.score.criteria.empty() ? p.run_error : p.score.criteria.back().reason;
      const std::string reason_q = q.score.criteria.empty() ? q.run_error : q.score.criteria.back().reason;
      if (p.points != q.points || p.passed != q.passed || p.run_error != q.run_error ||
          (p.search && reason_p != reason_q)) {
        why = x.submission + " " + p.name + ": \"" + reason_p + "\" against \"" + reason_q + "\"";
        return false;
      }
    }
  }
  return true;
}

const syrof::grader::assignment::TestResult* SearchOf(const syrof::grader::assignment::SubmissionResult& student) {
  for (const auto& test : student.tests) {
    if (test.search) return &test;
  }
  return nullptr;
}

}  // namespace

int main(int argc, char** argv) {
  int submissions = 2;
  int jobs = 2;
  bool public_only = false;
  bool fresh_first = false;
  for (int i = 1; i < argc; ++i) {
    if (std::strcmp(argv[i], "--public-only") == 0) public_only = true;
    if (std::strcmp(argv[i], "--fresh-first") == 0) fresh_first = true;
    if (i + 1 < argc && std::strcmp(argv[i], "--submissions") == 0) submissions = std::atoi(argv[i + 1]);
    if (i + 1 < argc && std::strcmp(argv[i], "--jobs") == 0) jobs = std::atoi(argv[i + 1]);
  }
  if (submissions < 1 || jobs < 1) {
    std::fprintf(stderr, "bench_grade_search_class: --submissions and --jobs take a positive count\n");
    return 2;
  }
  const syrof::grader::assignment::LoadResult loaded =
      syrof::grader::assignment::LoadAssignmentFile(SYROF_STRONGEST);
  if (!loaded.ok()) {
    std::fprintf(stderr, "%s\n", loaded.error->ToString().c_str());
    return 1;
  }
  const fs::path root = fs::temp_directory_path() / ("syrof_bench_grade_search_" + std::to_string(getpid()));
  fs::remove_all(root);
  fs::create_directories(root / "class");
  for (int i = 0; i < submissions; ++i) {
    char name[32];
    std::snprintf(name, sizeof name, "student%03d", i);
    fs::copy(fs::path(SYROF_STRONGEST) / "reference", root / "class" / name, fs::copy_options::recursive);
  }
  // The search tests as the assignment states them today.
  std::string searches;
  for (const auto& test : loaded.assignment->search_tests) {
    searches += std::string(searches.empty() ? "" : "; ") + test.file + ": max_losses " +
                std::to_string(test.max_losses) + ", epochs " + std::to_string(test.epochs);
  }
  std::printf("bench_grade_search_class: %d copies of assignments/strongest's reference (%s, and the search test "
              "%s), %d jobs\n",
              submissions, public_only ? "public runs" : "every run", searches.c_str(), jobs);

  // One way after the other, each under the load of its own minutes:
  // --fresh-first swaps them, to see what the order does on a shared machine.
  Pass fork;
  Pass fresh;
  if (fresh_first) fresh = GradeOnce(*loaded.assignment, root / "class", root / "fresh", jobs, public_only, false);
  fork = GradeOnce(*loaded.assignment, root / "class", root / "fork", jobs, public_only, true);
  if (!fresh_first) fresh = GradeOnce(*loaded.assignment, root / "class", root / "fresh", jobs, public_only, false);
  Print("fork server", fork, submissions, jobs);
  Print("fresh hosts", fresh, submissions, jobs);
  std::printf("  fresh / fork: class wall %.2fx\n", fork.wall_s > 0 ? fresh.wall_s / fork.wall_s : 0.0);

  std::string why;
  const bool same = SameResults(fork, fresh, why);
  const auto* search = fork.result.students.empty() ? nullptr : SearchOf(fork.result.students.front());
  if (same) {
    std::printf("  the same points and search results both ways, every submission (%s: %s)\n",
                search != nullptr && search->passed ? "search passed" : "search not passed",
                search == nullptr                  ? "no search test"
                : search->score.criteria.empty() ? search->run_error.c_str()
                                                  : search->score.criteria.back().reason.c_str());
  } else {
    std::printf("  NOT the same results both ways: %s\n", why.c_str());
  }
  fs::remove_all(root);
  return same ? 0 : 1;
}
