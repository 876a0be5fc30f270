// Grading a class of K copies of the gather reference (docs/grading.md,
// "Grading a class"), on a generated assignment: one scenario of 10 robots,
// R seeds. Prints the build time apart from the runs, runs per second, and
// seconds per run with the app host against the built-in gather in-process
// on the same scenario and seeds.
//
// Usage: bench_grade_class [--submissions K] [--runs R] [--duration S] [--jobs J]
// Default (CI size): 3 submissions x 2 runs of 20 s on 2 jobs. The issue's
// figure: --submissions 100 --runs 20 --duration 120 (target <= 10 minutes
// on 2 cores).
#include <chrono>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <string>
#include <unistd.h>

#include "syrof/assignment/assignment.h"
#include "syrof/grader/build.h"
#include "syrof/grader/class_grading.h"
#include "syrof/grader/grade.h"
#include "syrof/lab/scenario/scenario.h"
#include "syrof/lab/sim/simulation.h"

namespace {

namespace fs = std::filesystem;
using Clock = std::chrono::steady_clock;

double Since(Clock::time_point started) { return std::chrono::duration<double>(Clock::now() - started).count(); }

void WriteAssignment(const fs::path& folder, int runs, double duration_s) {
  fs::create_directories(folder / "scenarios");
  std::ofstream(folder / "scenarios" / "gather_10.yaml")
      << "name: gather_10\nseed: 1\narena: { width_m: 5, height_m: 5 }\n"
         "robots: { count: 10, placement: random, min_separation_m: 0.3 }\n"
      << "timing: { duration_s: " << duration_s << " }\n"
      << "app: builtin:gather\ngoal:\n  - { check: gathered, name: gathered, radius_m: 0.9 }\n";
  std::ofstream yaml(folder / "assignment.yaml");
  yaml << "title: Gather (bench)\npoints: 100\nscenarios:\n  public:\n    - { file: scenarios/gather_10.yaml, seeds: [";
  for (int seed = 1; seed <= runs; ++seed) yaml << (seed > 1 ? ", " : "") << seed;
  yaml << "], time_limit_s: 600 }\nrubric:\n  goal: 50\n  collisions: 15\n  safety: 5\n  synchrony: 5\n"
          "  common_knowledge: 5\n  agreement: 15\n  faults: 5\n";
}

}  // namespace

int main(int argc, char** argv) {
  int submissions = 3;
  int runs = 2;
  double duration_s = 20;
  int jobs = 2;
  for (int i = 1; i + 1 < argc; i += 2) {
    if (std::strcmp(argv[i], "--submissions") == 0) submissions = std::atoi(argv[i + 1]);
    if (std::strcmp(argv[i], "--runs") == 0) runs = std::atoi(argv[i + 1]);
    if (std::strcmp(argv[i], "--duration") == 0) duration_s = std::atof(argv[i + 1]);
    if (std::strcmp(argv[i], "--jobs") == 0) jobs = std::atoi(argv[i + 1]);
  }
  const fs::path root = fs::temp_directory_path() / ("syrof_bench_grade_" + std::to_string(getpid()));
  fs::remove_all(root);
  WriteAssignment(root / "assignment" / "gather_bench", runs, duration_s);
  fs::create_directories(root / "class");
  for (int i = 0; i < submissions; ++i) {
    char name[32];
    std::snprintf(name, sizeof name, "student%03d", i);
    fs::copy(fs::path(SYROF_GATHER_REFERENCE), root / "class" / name, fs::copy_options::recursive);
  }
  const syrof::grader::assignment::LoadResult loaded =
      syrof::grader::assignment::LoadAssignmentFile((root / "assignment" / "gather_bench").string());
  if (!loaded.ok()) {
    std::fprintf(stderr, "%s\n", loaded.error->ToString().c_str());
    return 1;
  }
  std::printf("bench_grade_class: %d submissions x %d runs (10 robots, %.0f s simulated), %d jobs\n", submissions, runs,
              duration_s, jobs);

  syrof::grader::ClassOptions options;
  options.jobs = jobs;
  options.resume = false;
  options.assignment_dir = (root / "assignment" / "gather_bench").string();
  const auto started = Clock::now();
  const syrof::grader::ClassResult result =
      syrof::grader::GradeClass(*loaded.assignment, (root / "class").string(), (root / "out").string(), options);
  const double total_s = Since(started);
  double build_s = 0;
  double run_s = 0;
  int run_count = 0;
  int full_marks = 0;
  for (const auto& student : result.students) {
    build_s += student.build.wall_seconds;
    for (const auto& test : student.tests) {
      run_s += test.wall_seconds;
      ++run_count;
    }
    full_marks += student.points == student.max_points ? 1 : 0;
  }
  std::printf("  class graded in %.1f s wall (%d of %d at full marks)\n", total_s, full_marks, submissions);
  std::printf("  builds: %.1f s in all, %.2f s per submission (busy time, %d side by side)\n", build_s,
              build_s / submissions, jobs);
  std::printf("  runs:   %.1f s in all, %.3f s per run on the app host, %.2f runs per second of wall\n", run_s,
              run_count > 0 ? run_s / run_count : 0.0, run_count / total_s);

  // The same scenario and seeds with the built-in gather, in-process, one
  // run at a time; and the app host one at a time for a fair ratio.
  syrof::grader::GradeOptions one;
  one.public_only = true;
  const std::string library = result.students.empty() ? std::string() : result.students.front().build.library_path;
  const auto host_started = Clock::now();
  syrof::grader::GradeLibrary(*loaded.assignment, library, (root / "host_alone").string(), one);
  const double host_per_run = Since(host_started) / runs;
  const auto builtin_started = Clock::now();
  for (int seed = 1; seed <= runs; ++seed) {
    syrof::lab::scenario::Overrides overrides;
    overrides.seed = static_cast<uint64_t>(seed);
    const auto scenario = syrof::lab::scenario::LoadScenarioFile(loaded.assignment->public_runs[0].path, overrides);
    syrof::lab::sim::Run(*scenario.scenario, {});
  }
  const double builtin_per_run = Since(builtin_started) / runs;
  std::printf("  one run at a time: app host %.3f s, built-in gather in-process %.3f s: ratio %.2fx\n", host_per_run,
              builtin_per_run, builtin_per_run > 0 ? host_per_run / builtin_per_run : 0.0);
  const double projected = (build_s / submissions * 100 + host_per_run * 100 * 20 * (120.0 / duration_s)) / jobs;
  std::printf("  projected 100 submissions x 20 runs of 120 s on %d jobs: %.0f s (target 600 s)\n", jobs, projected);
  fs::remove_all(root);
  return 0;
}
