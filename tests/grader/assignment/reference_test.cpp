// Each example assignment's reference solution, built as a student's
// library and run through the app host on every public scenario and seed,
// earns full marks: the goal checks pass, nothing collides, the robots
// agree, nothing faults.
#include <unistd.h>

#include <gtest/gtest.h>

#include <string>

#include "syrof/app_host/hosted_app.h"
#include "syrof/assignment/assignment.h"
#include "syrof/assignment/score.h"
#include "syrof/lab/scenario/scenario.h"
#include "syrof/lab/sim/simulation.h"

namespace syrof::grader::assignment {
namespace {

TEST(ReferenceTest, TheGatherReferenceScoresFullMarksOnEveryPublicRun) {
  const LoadResult loaded = LoadAssignmentFile(std::string(SYROF_ASSIGNMENTS_DIR) + "/gather");
  ASSERT_TRUE(loaded.ok()) << loaded.error->ToString();
  const Assignment& assignment = *loaded.assignment;
  app_host::HostOptions host;
  host.library_path = SYROF_GATHER_REFERENCE;
  host.log_directory = ::testing::TempDir() + "gather_reference_" + std::to_string(getpid());

  int runs = 0;
  for (const ScenarioRun& run : assignment.public_runs) {
    for (const uint64_t seed : run.seeds) {
      lab::scenario::Overrides overrides;
      overrides.seed = seed;
      const lab::scenario::LoadResult scenario = lab::scenario::LoadScenarioFile(run.path, overrides);
      ASSERT_TRUE(scenario.ok()) << scenario.error->ToString();
      lab::scenario::Scenario resolved = *scenario.scenario;
      if (!run.goal.empty()) resolved.goal = run.goal;
      lab::sim::SimulationOptions options;
      options.app_factory = [&](uint16_t id) { return app_host::MakeHostedApp(host, id); };
      options.app_source = host.library_path;

      const lab::sim::RunReport report = lab::sim::Run(resolved, options);
      const RunScore score = ScoreRun(assignment.rubric, report.metrics);

      for (const CriterionScore& criterion : score.criteria) {
        EXPECT_EQ(criterion.points, criterion.max_points)
            << run.name << " seed " << seed << ": " << criterion.criterion << ": " << criterion.reason;
      }
      EXPECT_EQ(score.points, assignment.points) << run.name << " seed " << seed;
      ++runs;
    }
  }
  EXPECT_EQ(runs, 5);
}

}  // namespace
}  // namespace syrof::grader::assignment
