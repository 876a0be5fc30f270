// `inputs:`: each robot's private values, listed or drawn from the seed.
#include <gtest/gtest.h>

#include <cmath>
#include <set>
#include <string>

#include "scenario_test_util.h"
#include "syrof/app.h"

namespace syrof::lab::scenario {
namespace {

using testing::FailsAt;
using testing::kMinimal;
using testing::Load;

TEST(ReadInputs, AListGivesEachRobotItsValueInIdOrder) {
  const LoadResult result = Load(std::string(kMinimal) + "inputs:\n  charge: [0.3, 0.9, 0.5, -2]\n");
  ASSERT_TRUE(result.ok()) << result.error->ToString();
  EXPECT_EQ(result.scenario->inputs.at("charge"), (std::vector<double>{0.3, 0.9, 0.5, -2}));
}

TEST(ReadInputs, NoInputsByDefault) {
  const LoadResult result = Load(kMinimal);
  ASSERT_TRUE(result.ok());
  EXPECT_TRUE(result.scenario->inputs.empty());
}

TEST(ReadInputs, DrawsFollowTheSeedAndStayInTheirRange) {
  const std::string inputs = "inputs:\n"
                             "  charge: { uniform: [0, 1] }\n"
                             "  key: { integers: [1, 6] }\n"
                             "  colour: { choice: [10, 20, 30] }\n";
  const std::string text = "robots: { count: 40 }\napp: builtin:idle\n" + inputs;
  const LoadResult first = Load(text);
  const LoadResult again = Load(text);
  Overrides other_seed;
  other_seed.seed = 2;
  const LoadResult seed2 = Load(text, other_seed);
  ASSERT_TRUE(first.ok()) << first.error->ToString();
  ASSERT_TRUE(seed2.ok());
  const auto& drawn = first.scenario->inputs;
  EXPECT_EQ(drawn, again.scenario->inputs);  // the same seed, the same values
  EXPECT_NE(drawn.at("charge"), seed2.scenario->inputs.at("charge"));
  ASSERT_EQ(drawn.at("charge").size(), 40u);
  std::set<double> keys, colours;
  for (size_t i = 0; i < 40; ++i) {
    const double charge = drawn.at("charge")[i];
    EXPECT_TRUE(charge >= 0 && charge < 1) << charge;
    keys.insert(drawn.at("key")[i]);
    colours.insert(drawn.at("colour")[i]);
  }
  EXPECT_EQ(keys, (std::set<double>{1, 2, 3, 4, 5, 6}));  // 40 draws of 6 whole numbers: each came
  EXPECT_EQ(colours, (std::set<double>{10, 20, 30}));
  // Two inputs drawn alike are still independent.
  EXPECT_NE(drawn.at("charge"), Load("robots: { count: 40 }\napp: builtin:idle\ninputs:\n  other: { uniform: [0, 1] }\n")
                                    .scenario->inputs.at("other"));
}

TEST(ReadInputs, ARobotsDrawDoesNotDependOnTheSwarmsSize) {
  const LoadResult four = Load("robots: { count: 4 }\napp: builtin:idle\ninputs: { charge: { uniform: [0, 1] } }\n");
  const LoadResult six = Load("robots: { count: 6 }\napp: builtin:idle\ninputs: { charge: { uniform: [0, 1] } }\n");
  ASSERT_TRUE(four.ok() && six.ok());
  for (size_t i = 0; i < 4; ++i) EXPECT_EQ(four.scenario->inputs.at("charge")[i], six.scenario->inputs.at("charge")[i]);
}

TEST(ReadInputs, AListMustHoldOneValuePerRobot) {
  EXPECT_TRUE(FailsAt(Load(std::string(kMinimal) + "inputs:\n  charge: [0.3, 0.9]\n"), 4, 11,
                      {"inputs.charge", "lists 2 values", "4 robots"}));
  Overrides more;
  more.robots = 5;
  EXPECT_TRUE(FailsAt(Load(std::string(kMinimal) + "inputs:\n  charge: [1, 2, 3, 4]\n", more), 4, 11,
                      {"lists 4 values", "5 robots"}));
}

TEST(ReadInputs, BadFormsAreNamed) {
  const std::string base(kMinimal);
  EXPECT_TRUE(FailsAt(Load(base + "inputs: [1, 2]\n"), 3, 9, {"inputs"}));
  EXPECT_TRUE(FailsAt(Load(base + "inputs:\n  2fast: [1, 2, 3, 4]\n"), 4, 3, {"input name '2fast'"}));
  EXPECT_TRUE(FailsAt(Load(base + "inputs:\n  charge: { uniform: [1, 0] }\n"), 4, 22, {"low below high"}));
  EXPECT_TRUE(FailsAt(Load(base + "inputs:\n  charge: { integers: [0, 2.5] }\n"), 4, 23, {"whole numbers"}));
  EXPECT_TRUE(FailsAt(Load(base + "inputs:\n  charge: { choice: [] }\n"), 4, 21, {"at least one value"}));
  EXPECT_TRUE(FailsAt(Load(base + "inputs:\n  charge: { uniform: [0, 1], choice: [1] }\n"), 4, 11, {"exactly one of"}));
  EXPECT_TRUE(FailsAt(Load(base + "inputs:\n  charge: { gaussian: [0, 1] }\n"), 4, 13, {"gaussian"}));
  EXPECT_TRUE(FailsAt(Load(base + "inputs:\n  charge: [1, 2, .nan, 4]\n"), 4, 18, {"inputs.charge[2]"}));
}

// Bounds each finite whose span is not (high - low overflows a double)
// would draw infinities and NaN, which no replay can hold.
TEST(ReadInputs, AUniformSpanMustBeFinite) {
  EXPECT_TRUE(FailsAt(Load(std::string(kMinimal) + "inputs:\n  charge: { uniform: [-1e308, 1e308] }\n"), 4, 22,
                      {"inputs.charge.uniform", "high - low"}));
  const LoadResult widest = Load(std::string(kMinimal) + "inputs:\n  charge: { uniform: [-8e307, 8e307] }\n");
  ASSERT_TRUE(widest.ok()) << widest.error->ToString();
  for (const double value : widest.scenario->inputs.at("charge")) EXPECT_TRUE(std::isfinite(value)) << value;
}

TEST(ReadInputs, AtMostTheAppApisInputs) {
  std::string text = std::string(kMinimal) + "inputs:\n";
  for (unsigned i = 0; i <= SYROF_APP_MAX_INPUTS; ++i) text += "  in" + std::to_string(i) + ": [1, 2, 3, 4]\n";
  EXPECT_TRUE(FailsAt(Load(text), 4 + static_cast<int>(SYROF_APP_MAX_INPUTS), 3, {"too many inputs"}));
}

}  // namespace
}  // namespace syrof::lab::scenario
