// For the assignments' tests: grades an already-built app library on an
// assignment's runs with the grade command's runner (grader::GradeLibrary:
// the app host, the rubric, runs added up as syrof/assignment/result.h
// says). These tests check the assignments themselves (reference full
// marks, starter and broken variants losing what their notes say).
#pragma once

#include <gtest/gtest.h>

#include <cmath>
#include <string>

#include "syrof/assignment/assignment.h"
#include "syrof/assignment/result.h"
#include "syrof/assignment/score.h"
#include "syrof/grader/grade.h"

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
/// `public_only`) and adds the scores up: the grade command's own runner
/// (syrof/grader/grade.h), with the runs' outputs under `out_dir`.
inline SubmissionResult GradeLibrary(const Assignment& assignment, const std::string& library,
                                     const std::string& out_dir, bool public_only = false) {
  grader::GradeOptions options;
  options.public_only = public_only;
  return grader::GradeLibrary(assignment, library, out_dir, options);
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
