// Scoring one run: a pure function from the rubric and the run's metrics to
// points per criterion, each with the reason a student reads
// (docs/grading.md, "Scoring one run"). No I/O, no clock: the same input
// gives the same score.
#pragma once

#include <string>
#include <vector>

#include "syrof/assignment/assignment.h"
#include "syrof/lab/metrics/metrics.h"

namespace syrof::grader::assignment {

struct CriterionScore {
  std::string criterion;  ///< "goal", "collisions", "safety", "synchrony", "common_knowledge", "agreement", "faults"; "search" for a search test
  double points = 0;      ///< earned, in [0, max_points]
  double max_points = 0;
  std::string reason;     ///< why points were lost, or what earned them
};

struct RunScore {
  std::vector<CriterionScore> criteria;  ///< in the rubric's order above; absent criteria left out
  double points = 0;
  double max_points = 0;
};

/// Scores `metrics` with `rubric`. The safety criterion reads
/// metrics.safety: interventions cost points when the filter was on; a
/// scenario with `safety: off` gives full points and says so.
RunScore ScoreRun(const Rubric& rubric, const lab::metrics::Metrics& metrics);

}  // namespace syrof::grader::assignment
