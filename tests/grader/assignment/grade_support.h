// For the assignments' tests: grades an already-built app library on an
// assignment's runs through the app host, adding runs up as
// syrof/assignment/result.h says (each test worth points / tests). The
// grade command's runner (grader/) builds submissions and writes reports;
// these tests check the assignments themselves (reference full marks,
// starter and broken variants losing what their notes say).
#pragma once

#include <unistd.h>

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <string>
#include <vector>

#include "syrof/app_host/hosted_app.h"
#include "syrof/assignment/assignment.h"
#include "syrof/assignment/result.h"
#include "syrof/assignment/score.h"
#include "syrof/lab/scenario/scenario.h"
#include "syrof/lab/sim/simulation.h"

namespace syrof::grader::assignment::testing {

inline double RoundPoints(double points) { return std::round(points * 100.0) / 100.0; }

/// Loads `assignments/<name>` or fails the test.
inline Assignment LoadNamedAssignment(const std::string& assignments_dir, const std::string& name) {
  const LoadResult loaded = LoadAssignmentFile(assignments_dir + "/" + name);
  if (!loaded.ok()) {
    ADD_FAILURE() << loaded.error->ToString();
    return {};
  }
  return *loaded.assignment;
}

/// Runs `library` on every run of `assignment` (hidden too unless
/// `public_only`) and adds the scores up. Robots' logs go under `log_dir`.
inline SubmissionResult GradeLibrary(const Assignment& assignment, const std::string& library,
                                     const std::string& log_dir, bool public_only = false) {
  SubmissionResult result;
  result.assignment = assignment.name;
  result.title = assignment.title;
  result.public_only = public_only;
  result.max_points = assignment.points;
  result.build.library_path = library;

  std::vector<std::pair<const ScenarioRun*, Visibility>> sets;
  for (const ScenarioRun& run : assignment.public_runs) sets.emplace_back(&run, Visibility::kPublic);
  if (!public_only) {
    for (const ScenarioRun& run : assignment.hidden_runs) sets.emplace_back(&run, Visibility::kHidden);
  }
  size_t tests = 0;
  double exact_total = 0;
  for (const auto& [run, visibility] : sets) tests += run->seeds.size();

  for (const auto& [run, visibility] : sets) {
    for (const uint64_t seed : run->seeds) {
      TestResult test;
      test.name = run->name + "/seed-" + std::to_string(seed);
      test.scenario = run->name;
      test.seed = seed;
      test.visibility = visibility;
      test.max_points = assignment.points / static_cast<double>(tests);

      lab::scenario::Overrides overrides;
      overrides.seed = seed;
      const lab::scenario::LoadResult scenario = lab::scenario::LoadScenarioFile(run->path, overrides);
      if (!scenario.ok()) {
        ADD_FAILURE() << scenario.error->ToString();
        continue;
      }
      lab::scenario::Scenario resolved = *scenario.scenario;
      if (!run->goal.empty()) resolved.goal = run->goal;

      app_host::HostOptions host;
      host.library_path = library;
      host.log_directory = log_dir + "/" + run->name + "_seed-" + std::to_string(seed);
      host.params = resolved.app.params;
      if (resolved.app.cpu_budget_ms) host.limits.cpu_budget_ms = *resolved.app.cpu_budget_ms;
      host.limits.wall_cap_ms = resolved.app.wall_cap_ms
                                    ? *resolved.app.wall_cap_ms
                                    : std::max(host.limits.wall_cap_ms, 4 * host.limits.cpu_budget_ms);
      lab::sim::SimulationOptions options;
      options.app_factory = [&](uint16_t id) { return app_host::MakeHostedApp(host, id); };
      options.app_source = library;

      const lab::sim::RunReport report = lab::sim::Run(resolved, options);
      RunExtras extras;
      extras.safety_interventions = report.metrics.safety.interventions;
      test.score = ScoreRun(assignment.rubric, report.metrics, extras);
      const double fraction = test.score.max_points > 0 ? test.score.points / test.score.max_points : 1.0;
      test.points = RoundPoints(test.max_points * fraction);
      test.passed = test.score.points == test.score.max_points;
      exact_total += test.max_points * fraction;
      result.tests_passed += test.passed ? 1 : 0;
      result.tests.push_back(std::move(test));
    }
  }
  result.points = RoundPoints(exact_total);
  return result;
}

/// Every criterion of every test, one line each, for a failure message.
inline std::string Describe(const SubmissionResult& result) {
  std::string text;
  for (const TestResult& test : result.tests) {
    for (const CriterionScore& criterion : test.score.criteria) {
      if (criterion.points == criterion.max_points) continue;
      text += test.name + ": " + criterion.criterion + " " + std::to_string(criterion.points) + "/" +
              std::to_string(criterion.max_points) + ": " + criterion.reason + "\n";
    }
  }
  return text;
}

}  // namespace syrof::grader::assignment::testing
