// assignment.yaml: the example assignments load and every scenario they name
// validates; a wrong file gets the error a student or instructor can act on
// (file:line:column, key path, nearest key), and a scenario's own error
// keeps its own file and place.
#include "syrof/assignment/assignment.h"

#include <gtest/gtest.h>

#include <filesystem>
#include <fstream>
#include <string>

namespace syrof::grader::assignment {
namespace {

namespace fs = std::filesystem;

TEST(AssignmentTest, TheGatherExampleLoadsWithEveryScenario) {
  const LoadResult result = LoadAssignmentFile(std::string(SYROF_ASSIGNMENTS_DIR) + "/gather");
  ASSERT_TRUE(result.ok()) << result.error->ToString();
  const Assignment& assignment = *result.assignment;

  EXPECT_EQ(assignment.name, "gather");
  EXPECT_EQ(assignment.title, "Gather the swarm");
  EXPECT_EQ(assignment.points, 100);
  ASSERT_EQ(assignment.public_runs.size(), 2u);
  ASSERT_EQ(assignment.hidden_runs.size(), 1u);
  EXPECT_EQ(assignment.public_runs[0].name, "gather_6");
  EXPECT_EQ(assignment.public_runs[0].seeds, (std::vector<uint64_t>{1, 2, 3}));
  EXPECT_TRUE(assignment.public_runs[0].scenario_has_goal);
  EXPECT_EQ(assignment.hidden_runs[0].time_limit_s, 120);
  ASSERT_TRUE(assignment.rubric.collisions.has_value());
  EXPECT_EQ(assignment.rubric.collisions->per_collision, 5);
  ASSERT_TRUE(assignment.rubric.common_knowledge.has_value());
  EXPECT_EQ(assignment.rubric.common_knowledge->points, 5);
}

TEST(AssignmentTest, EveryExampleAssignmentLoads) {
  int loaded = 0;
  for (const fs::directory_entry& entry : fs::directory_iterator(SYROF_ASSIGNMENTS_DIR)) {
    if (!fs::exists(entry.path() / "assignment.yaml")) continue;
    const LoadResult result = LoadAssignmentFile(entry.path().string());
    EXPECT_TRUE(result.ok()) << result.error->ToString();
    ++loaded;
  }
  EXPECT_GE(loaded, 1);
}

// A scratch assignment folder with a valid scenario in it.
class AssignmentFileTest : public ::testing::Test {
 protected:
  void SetUp() override {
    folder_ = fs::temp_directory_path() / ("syrof_assignment_" + std::to_string(::getpid()) + "_" +
                                           ::testing::UnitTest::GetInstance()->current_test_info()->name());
    fs::remove_all(folder_);
    fs::create_directories(folder_ / "s");
    Write("s/three.yaml", "robots: {count: 3}\napp: builtin:idle\ngoal: [{check: gathered, radius_m: 2}]\n");
    Write("s/nogoal.yaml", "robots: {count: 3}\napp: builtin:idle\n");
  }
  void TearDown() override { fs::remove_all(folder_); }

  void Write(const std::string& name, const std::string& text) { std::ofstream(folder_ / name) << text; }

  LoadResult Load(const std::string& text) {
    Write("assignment.yaml", text);
    return LoadAssignmentFile(folder_.string());
  }

  ::testing::AssertionResult FailsAt(const LoadResult& result, const std::string& file, int line, int column,
                                     const std::string& fragment) {
    if (result.ok()) return ::testing::AssertionFailure() << "loaded";
    const lab::Error& error = *result.error;
    if (error.where != (folder_ / file).string() || error.line != line || error.column != column ||
        error.message.find(fragment) == std::string::npos) {
      return ::testing::AssertionFailure() << error.ToString();
    }
    return ::testing::AssertionSuccess();
  }

  fs::path folder_;
};

const char* const kValidRubric = "rubric: {goal: 60, agreement: 40}\n";

TEST_F(AssignmentFileTest, AMinimalAssignmentLoads) {
  const LoadResult result =
      Load(std::string("title: T\nscenarios:\n  public: [{file: s/three.yaml, seeds: [1]}]\n") + kValidRubric);
  ASSERT_TRUE(result.ok()) << result.error->ToString();
  EXPECT_EQ(result.assignment->public_runs[0].path, (folder_ / "s/three.yaml").string());
  EXPECT_EQ(result.assignment->public_runs[0].time_limit_s, 60);
  EXPECT_TRUE(result.assignment->rubric.goal->per_check);
  EXPECT_FALSE(result.assignment->rubric.collisions.has_value());
}

TEST_F(AssignmentFileTest, AMisspeltKeySuggestsTheNearest) {
  EXPECT_TRUE(FailsAt(Load(std::string("title: T\nscenarios:\n  publik: []\n") + kValidRubric), "assignment.yaml", 3,
                      3, "scenarios: unknown key 'publik' (did you mean 'public'?)"));
}

TEST_F(AssignmentFileTest, AMissingScenarioFileIsNamed) {
  EXPECT_TRUE(FailsAt(Load(std::string("title: T\nscenarios:\n  public: [{file: s/four.yaml, seeds: [1]}]\n") +
                           kValidRubric),
                      "assignment.yaml", 3, 19, "scenarios.public[0].file: no such scenario file 's/four.yaml'"));
}

TEST_F(AssignmentFileTest, MixableIsABooleanThatDefaultsToFalse) {
  const std::string rest = "title: T\nscenarios:\n  public: [{file: s/three.yaml, seeds: [1]}]\n" + std::string(kValidRubric);
  const LoadResult plain = Load(rest);
  ASSERT_TRUE(plain.ok()) << plain.error->ToString();
  EXPECT_FALSE(plain.assignment->mixable);
  const LoadResult mixable = Load("mixable: true\nmessage: none\n" + rest);
  ASSERT_TRUE(mixable.ok()) << mixable.error->ToString();
  EXPECT_TRUE(mixable.assignment->mixable);
  EXPECT_TRUE(FailsAt(Load("mixable: yes\n" + rest), "assignment.yaml", 1, 10, "mixable: expected true or false"));
}

TEST_F(AssignmentFileTest, AMixableAssignmentMustDeclareItsMessageFormat) {
  const std::string rest = "title: T\nscenarios:\n  public: [{file: s/three.yaml, seeds: [1]}]\n" + std::string(kValidRubric);
  EXPECT_TRUE(FailsAt(Load("mixable: true\n" + rest), "assignment.yaml", 1, 10,
                      "mixable: a mixable assignment must declare its robots' message format"));
}

TEST_F(AssignmentFileTest, TheMessageFormatIsReadWithItsFieldsInOrder) {
  const std::string rest = "title: T\nscenarios:\n  public: [{file: s/three.yaml, seeds: [1]}]\n" + std::string(kValidRubric);
  const LoadResult plain = Load(rest);
  ASSERT_TRUE(plain.ok()) << plain.error->ToString();
  EXPECT_FALSE(plain.assignment->message.has_value());
  const LoadResult none = Load("message: none\n" + rest);
  ASSERT_TRUE(none.ok()) << none.error->ToString();
  EXPECT_TRUE(none.assignment->message->none);
  const LoadResult two = Load("message: {length: 3, fields: [{name: charge, type: u16be}, {name: hops, type: i8}]}\n" + rest);
  ASSERT_TRUE(two.ok()) << two.error->ToString();
  const lab::message::MessageFormat& format = *two.assignment->message;
  EXPECT_FALSE(format.none);
  ASSERT_EQ(format.fields.size(), 2u);
  EXPECT_EQ(format.fields[1].name, "hops");
  EXPECT_EQ(format.fields[1].offset, 2u);
  EXPECT_EQ(format.ToString(), "3 bytes: charge u16be, hops i8");
}

TEST_F(AssignmentFileTest, AScenarioMustNotDeclareAnotherMessageFormat) {
  Write("s/other.yaml", "robots: {count: 3}\napp: builtin:idle\ngoal: [{check: gathered, radius_m: 2}]\n"
                        "message: {length: 1, fields: [{name: hops, type: u8}]}\n");
  EXPECT_TRUE(FailsAt(Load(std::string("title: T\nmessage: none\nscenarios:\n  public: [{file: s/other.yaml, seeds: [1]}]\n") +
                           kValidRubric),
                      "assignment.yaml", 4, 19,
                      "scenario 's/other.yaml' declares the message format 1 byte: hops u8, but the assignment's is none"));
}

TEST_F(AssignmentFileTest, AWrongMessageFormatIsPlaced) {
  const std::string rest = "title: T\nscenarios:\n  public: [{file: s/three.yaml, seeds: [1]}]\n" + std::string(kValidRubric);
  EXPECT_TRUE(FailsAt(Load("message: nothing\n" + rest), "assignment.yaml", 1, 10, "message: expected 'none'"));
  EXPECT_TRUE(FailsAt(Load("message: {length: 2, fields: [{name: charge, type: u16}]}\n" + rest), "assignment.yaml",
                      1, 52, "message.fields[0].type: unknown value 'u16'"));
  EXPECT_TRUE(FailsAt(Load("message: {length: 3, fields: [{name: charge, type: u16be}]}\n" + rest),
                      "assignment.yaml", 1, 19, "message.length: is 3, but the fields take 2 bytes"));
  EXPECT_TRUE(FailsAt(Load("message: {length: 10, fields: [{name: charge, type: u16be}]}\n" + rest),
                      "assignment.yaml", 1, 19, "message.length: must be in [1, 9], got 10"));
  EXPECT_TRUE(FailsAt(Load("message: {length: 2, fields: [{name: a, type: u8}, {name: a, type: u8}]}\n" + rest),
                      "assignment.yaml", 1, 59, "message.fields[1].name: another field is already named 'a'"));
  EXPECT_TRUE(FailsAt(Load("message: {length: 1, fields: [{name: Charge, type: u8}]}\n" + rest), "assignment.yaml",
                      1, 38, "message.fields[0].name: a field's name must be"));
  EXPECT_TRUE(FailsAt(Load("message: {lenght: 1, fields: []}\n" + rest), "assignment.yaml", 1, 11,
                      "did you mean 'length'?"));
  // A length past int64 and a type that is not a name: refused at their place, not wrapped or crashed on.
  EXPECT_TRUE(FailsAt(Load("message: {length: 99999999999999999999, fields: [{name: a, type: u8}]}\n" + rest),
                      "assignment.yaml", 1, 19, "message.length: must be in [1, 9], got 99999999999999999999"));
  EXPECT_TRUE(FailsAt(Load("message: {length: 1, fields: [{name: a, type: [u8]}]}\n" + rest), "assignment.yaml", 1,
                      47, "message.fields[0].type: expected one of u8,"));
}

TEST_F(AssignmentFileTest, MissingHiddenFilesAreDroppedOnlyWhenAllowed) {
  const std::string text = "title: T\nscenarios:\n  public: [{file: s/three.yaml, seeds: [1]}]\n"
                           "  hidden: [{file: h/secret.yaml, seeds: [2]}]\n" + std::string(kValidRubric);
  EXPECT_TRUE(FailsAt(Load(text), "assignment.yaml", 4, 19, "no such scenario file 'h/secret.yaml'"));
  LoadOptions options;
  options.allow_missing_hidden = true;
  const LoadResult student_copy = LoadAssignmentFile(folder_.string(), options);
  ASSERT_TRUE(student_copy.ok()) << student_copy.error->ToString();
  EXPECT_TRUE(student_copy.assignment->hidden_missing);
  EXPECT_TRUE(student_copy.assignment->hidden_runs.empty());
  EXPECT_EQ(student_copy.assignment->public_runs.size(), 1u);
  Write("missing_public.yaml", "title: T\nscenarios:\n  public: [{file: s/four.yaml, seeds: [1]}]\n" + std::string(kValidRubric));
  EXPECT_FALSE(LoadAssignmentFile((folder_ / "missing_public.yaml").string(), options).ok())
      << "a public file is never optional";
}

const char* const kOneRun = "title: T\nscenarios:\n  public: [{file: s/three.yaml, seeds: [1]}]\n";

TEST_F(AssignmentFileTest, SearchTestsAreReadWithTheirDefaults) {
  const LoadResult result =
      Load(std::string(kOneRun) + "search:\n  - {scenario: s/nogoal.yaml, max_losses: 1, points: 10}\n" +
           "  - {scenario: s/three.yaml, name: deep, max_losses: 2, epochs: 4, points: 5, hidden: true, "
           "time_limit_s: 30}\n" + kValidRubric);
  ASSERT_TRUE(result.ok()) << result.error->ToString();
  const std::vector<SearchTestSpec>& tests = result.assignment->search_tests;
  ASSERT_EQ(tests.size(), 2u);
  EXPECT_EQ(tests[0].name, "nogoal");
  EXPECT_EQ(tests[0].path, (folder_ / "s/nogoal.yaml").string());
  EXPECT_EQ(tests[0].epochs, 2);
  EXPECT_EQ(tests[0].time_limit_s, 300);
  EXPECT_EQ(tests[0].visibility, Visibility::kPublic);
  EXPECT_EQ(tests[1].name, "deep");
  EXPECT_EQ(tests[1].max_losses, 2);
  EXPECT_EQ(tests[1].epochs, 4);
  EXPECT_EQ(tests[1].visibility, Visibility::kHidden);
  EXPECT_EQ(RunPoints(*result.assignment, true), 85);
  EXPECT_EQ(RunPoints(*result.assignment, false), 90);
}

TEST_F(AssignmentFileTest, AWrongSearchTestIsPlaced) {
  EXPECT_TRUE(FailsAt(Load(std::string(kOneRun) + "search: [{scenario: s/three.yaml, max_losses: 9, points: 1}]\n" +
                           kValidRubric),
                      "assignment.yaml", 4, 47, "search[0].max_losses: must be in [0, 8], got 9"));
  EXPECT_TRUE(FailsAt(Load(std::string(kOneRun) + "search: [{scenario: s/four.yaml, max_losses: 1, points: 1}]\n" +
                           kValidRubric),
                      "assignment.yaml", 4, 21, "search[0].scenario: no such scenario file 's/four.yaml'"));
  EXPECT_TRUE(FailsAt(Load(std::string(kOneRun) + "search: [{scenario: s/three.yaml, max_loses: 1, points: 1}]\n" +
                           kValidRubric),
                      "assignment.yaml", 4, 35, "search[0]: unknown key 'max_loses' (did you mean 'max_losses'?)"));
  EXPECT_TRUE(FailsAt(Load(std::string(kOneRun) + "search: [{scenario: s/three.yaml, max_losses: 1, points: 100}]\n" +
                           kValidRubric),
                      "assignment.yaml", 4, 9, "leaves nothing for the runs"));
  EXPECT_TRUE(FailsAt(Load(std::string(kOneRun) +
                           "search: [{scenario: s/three.yaml, max_losses: 1, points: 1},\n"
                           "         {scenario: s/three.yaml, max_losses: 2, points: 1}]\n" +
                           kValidRubric),
                      "assignment.yaml", 5, 21, "another search test is already named 'three'"));
}

// A schedule search (docs/activation.md, "The schedule search"): the
// activation model and its budget, as `syrof search --activations` takes them.
TEST_F(AssignmentFileTest, AScheduleSearchTestIsReadWithItsBudget) {
  const LoadResult result =
      Load(std::string(kOneRun) + "search:\n  - {scenario: s/three.yaml, activations: ssync, epochs: 3, points: 10}\n" +
           "  - {scenario: s/nogoal.yaml, activations: ssync, epochs: 4, max_inactive: 2, fair_within: 3, "
           "points: 5}\n" + kValidRubric);
  ASSERT_TRUE(result.ok()) << result.error->ToString();
  const std::vector<SearchTestSpec>& tests = result.assignment->search_tests;
  ASSERT_EQ(tests.size(), 2u);
  EXPECT_TRUE(tests[0].activations);
  EXPECT_EQ(tests[0].epochs, 3);
  EXPECT_EQ(tests[0].max_inactive, 0) << "every schedule";
  EXPECT_EQ(tests[0].fair_within, 0) << "no fairness bound";
  EXPECT_TRUE(tests[1].activations);
  EXPECT_EQ(tests[1].max_inactive, 2);
  EXPECT_EQ(tests[1].fair_within, 3);
  EXPECT_EQ(RunPoints(*result.assignment, true), 85);

  const LoadResult async = Load(std::string(kOneRun) +
                                "search: [{scenario: s/three.yaml, activations: async, max_delay: 2, min_move_m: 0.05, "
                                "max_deviations: 3, epochs: 2, points: 10}]\n" + kValidRubric);
  ASSERT_TRUE(async.ok()) << async.error->ToString();
  const SearchTestSpec& cycles = async.assignment->search_tests[0];
  EXPECT_TRUE(cycles.activations);
  EXPECT_TRUE(cycles.async);
  EXPECT_EQ(cycles.max_delay, 2);
  EXPECT_EQ(cycles.min_move_m, 0.05);
  EXPECT_EQ(cycles.max_deviations, 3);
  EXPECT_FALSE(tests[0].async);

  const LoadResult losses = Load(std::string(kOneRun) + "search: [{scenario: s/three.yaml, max_losses: 1, points: 1}]\n" +
                                 kValidRubric);
  ASSERT_TRUE(losses.ok()) << losses.error->ToString();
  EXPECT_FALSE(losses.assignment->search_tests[0].activations);
}

TEST_F(AssignmentFileTest, AWrongScheduleSearchTestIsPlaced) {
  const auto search = [&](const std::string& entry) {
    return Load(std::string(kOneRun) + "search: [{scenario: s/three.yaml, " + entry + ", points: 1}]\n" + kValidRubric);
  };
  EXPECT_TRUE(FailsAt(search("activations: fsync"), "assignment.yaml", 4, 48,
                      "search[0].activations: unknown activation model 'fsync'; a search test searches ssync"));
  EXPECT_TRUE(FailsAt(search("activations: async"), "assignment.yaml", 4, 48,
                      "search[0].activations: an ASYNC search needs a delay bound: give 'max_delay' (1 .. 8 epochs), "
                      "or search a scenario whose activation is async (s/three.yaml is fsync)"));
  EXPECT_TRUE(FailsAt(search("activations: async, max_delay: 9"), "assignment.yaml", 4, 66,
                      "search[0].max_delay: must be in [1, 8], got 9"));
  EXPECT_TRUE(FailsAt(search("activations: async, max_delay: 1, fair_within: 2"), "assignment.yaml", 4, 82,
                      "search[0].fair_within: applies to an SSYNC schedule search only ('activations: ssync')"));
  EXPECT_TRUE(FailsAt(search("activations: ssync, max_delay: 1"), "assignment.yaml", 4, 66,
                      "search[0].max_delay: applies to an ASYNC schedule search only ('activations: async')"));
  EXPECT_TRUE(FailsAt(search("max_losses: 1, min_move_m: 0.05"), "assignment.yaml", 4, 62,
                      "search[0].min_move_m: applies to an ASYNC schedule search only ('activations: async')"));
  EXPECT_TRUE(FailsAt(search("activations: [ssync]"), "assignment.yaml", 4, 48,
                      "search[0].activations: expected the activation model to search: ssync"));
  EXPECT_TRUE(FailsAt(search("activations: ssync, max_losses: 1"), "assignment.yaml", 4, 67,
                      "search[0].max_losses: a search test searches losses or schedules, one at a time"));
  EXPECT_TRUE(FailsAt(search("max_losses: 1, fair_within: 2"), "assignment.yaml", 4, 63,
                      "search[0].fair_within: applies to a schedule search only ('activations: ssync')"));
  EXPECT_TRUE(FailsAt(search("max_losses: 1, max_inactive: 2"), "assignment.yaml", 4, 64,
                      "search[0].max_inactive: applies to a schedule search only"));
  EXPECT_TRUE(FailsAt(search("epochs: 2"), "assignment.yaml", 4, 10,
                      "missing required key 'search[0].max_losses' (or 'activations: ssync' or 'async' to search "
                      "schedules)"));
  EXPECT_TRUE(FailsAt(search("activations: ssync, epochs: 3, fair_within: 4"), "assignment.yaml", 4, 79,
                      "search[0].fair_within: must be at most the 3 epochs searched ('epochs'), got 4"));
  EXPECT_TRUE(FailsAt(search("activations: ssync, fair_within: 0"), "assignment.yaml", 4, 68,
                      "search[0].fair_within: must be in [1, 1000], got 0"));
  EXPECT_TRUE(FailsAt(search("activations: ssync, max_inactive: 65"), "assignment.yaml", 4, 69,
                      "search[0].max_inactive: must be in [1, 64], got 65"));
}

// Gradescope's visibility per test, and the cap on hidden-test feedback.
TEST_F(AssignmentFileTest, GradescopeVisibilityAndTheHiddenFeedbackCapAreRead) {
  const LoadResult result = Load(
      "title: T\nhidden_feedback_submissions: 3\nscenarios:\n"
      "  public: [{file: s/three.yaml, seeds: [1], gradescope: after_published}]\n"
      "  hidden: [{file: s/three.yaml, name: h, seeds: [2], gradescope: visible}, {file: s/three.yaml, name: d, "
      "seeds: [3]}]\n"
      "search: [{scenario: s/three.yaml, max_losses: 1, points: 10, hidden: true, gradescope: hidden}]\n" +
      std::string(kValidRubric));
  ASSERT_TRUE(result.ok()) << result.error->ToString();
  EXPECT_EQ(result.assignment->hidden_feedback_submissions, 3);
  EXPECT_EQ(result.assignment->public_runs[0].gradescope, GradescopeVisibility::kAfterPublished);
  EXPECT_EQ(result.assignment->hidden_runs[0].gradescope, GradescopeVisibility::kVisible);
  EXPECT_EQ(result.assignment->hidden_runs[1].gradescope, GradescopeVisibility::kDefault);
  EXPECT_EQ(result.assignment->search_tests[0].gradescope, GradescopeVisibility::kHidden);

  EXPECT_TRUE(FailsAt(Load(std::string("title: T\nscenarios:\n  public: [{file: s/three.yaml, seeds: [1], "
                                       "gradescope: later}]\n") +
                           kValidRubric),
                      "assignment.yaml", 3, 57,
                      "scenarios.public[0].gradescope: expected Gradescope's visibility of the test: visible, hidden, "
                      "after_due_date or after_published"));
  EXPECT_TRUE(FailsAt(Load(std::string("title: T\nhidden_feedback_submissions: -1\nscenarios:\n  public: "
                                       "[{file: s/three.yaml, seeds: [1]}]\n") +
                           kValidRubric),
                      "assignment.yaml", 2, 30, "hidden_feedback_submissions"));
}

TEST_F(AssignmentFileTest, AMissingHiddenSearchScenarioIsDroppedOnlyWhenAllowed) {
  const std::string text = std::string(kOneRun) +
                           "search: [{scenario: h/secret.yaml, max_losses: 1, points: 10, hidden: true}]\n" +
                           kValidRubric;
  EXPECT_TRUE(FailsAt(Load(text), "assignment.yaml", 4, 21, "no such scenario file 'h/secret.yaml'"));
  LoadOptions options;
  options.allow_missing_hidden = true;
  const LoadResult student_copy = LoadAssignmentFile(folder_.string(), options);
  ASSERT_TRUE(student_copy.ok()) << student_copy.error->ToString();
  EXPECT_TRUE(student_copy.assignment->search_tests.empty());
}

TEST_F(AssignmentFileTest, AScenarioErrorKeepsItsOwnFileAndPlace) {
  Write("s/broken.yaml", "robots: {count: 3}\napp: builtin:idle\ntiming: {duraton_s: 3}\n");
  EXPECT_TRUE(FailsAt(Load(std::string("title: T\nscenarios:\n  public: [{file: s/broken.yaml, seeds: [1]}]\n") +
                           kValidRubric),
                      "s/broken.yaml", 3, 10, "did you mean 'duration_s'?"));
}

TEST_F(AssignmentFileTest, ASeedTwiceIsRefused) {
  EXPECT_TRUE(FailsAt(Load(std::string("title: T\nscenarios:\n  public: [{file: s/three.yaml, seeds: [1, 2, 1]}]\n") +
                           kValidRubric),
                      "assignment.yaml", 3, 47, "scenarios.public[0].seeds[2]: seed 1 is listed twice"));
}

TEST_F(AssignmentFileTest, TheRubricMustAddUpToThePoints) {
  EXPECT_TRUE(FailsAt(Load("title: T\npoints: 50\nscenarios:\n  public: [{file: s/three.yaml, seeds: [1]}]\n"
                           "rubric:\n  goal: 30\n  collisions: {points: 10, per_collision: 2}\n"),
                      "assignment.yaml", 6, 3, "the criteria's points add up to 40, but the assignment's 'points' is 50"));
}

TEST_F(AssignmentFileTest, AnUnknownCriterionKeySuggestsTheNearest) {
  EXPECT_TRUE(FailsAt(Load("title: T\nscenarios:\n  public: [{file: s/three.yaml, seeds: [1]}]\n"
                           "rubric:\n  goal: 90\n  collisions: {points: 10, per_colision: 2}\n"),
                      "assignment.yaml", 6, 28, "rubric.collisions: unknown key 'per_colision' (did you mean 'per_collision'?)"));
}

TEST_F(AssignmentFileTest, AGoalCriterionNeedsAGoalForEveryScenario) {
  EXPECT_TRUE(FailsAt(Load(std::string("title: T\nscenarios:\n  public: [{file: s/nogoal.yaml, seeds: [1]}]\n") +
                           kValidRubric),
                      "assignment.yaml", 4, 16, "scenario 's/nogoal.yaml' declares no 'goal:'"));
}

TEST_F(AssignmentFileTest, TheAssignmentsGoalIsResolvedAgainstEachScenario) {
  const LoadResult result =
      Load(std::string("title: T\nscenarios:\n  public: [{file: s/nogoal.yaml, seeds: [1]}]\n"
                       "goal:\n  - {check: line, spacing_m: 0.5}\n") +
           kValidRubric);
  ASSERT_TRUE(result.ok()) << result.error->ToString();
  ASSERT_EQ(result.assignment->public_runs[0].goal.size(), 1u);
  EXPECT_EQ(result.assignment->public_runs[0].goal[0].kind, lab::goals::CheckKind::kLine);

  // Checked against the scenario: one slot per robot.
  EXPECT_TRUE(FailsAt(Load(std::string("title: T\nscenarios:\n  public: [{file: s/nogoal.yaml, seeds: [1]}]\n"
                                       "goal:\n  - {check: slots, assign: by_id, points: [{x_m: 1, y_m: 1}]}\n") +
                           kValidRubric),
                      "assignment.yaml", 5, 43, "the scenario has 3 robots"));
}

TEST_F(AssignmentFileTest, TwoScenariosWithOneNameAreRefused) {
  EXPECT_TRUE(FailsAt(Load(std::string("title: T\nscenarios:\n  public: [{file: s/three.yaml, seeds: [1]}]\n"
                                       "  hidden: [{file: s/three.yaml, seeds: [2]}]\n") +
                           kValidRubric),
                      "assignment.yaml", 4, 19, "already named 'three'"));
}

TEST_F(AssignmentFileTest, AnEmptyFileSaysWhatItNeeds) {
  EXPECT_TRUE(FailsAt(Load(""), "assignment.yaml", 0, 0, "it needs 'title', 'scenarios' and 'rubric'"));
}

}  // namespace
}  // namespace syrof::grader::assignment
