#include "syrof/firmware/swarm/image_app.h"

#include <gtest/gtest.h>

#include <string>
#include <vector>

namespace syrof::firmware::swarm {
namespace {

// The lab's built-in twin of the image's app, or its very name, is the
// image's app; another built-in, another name or a library is not.
TEST(ImageAppTest, ScenarioNamesTheImagesAppByNameOrItsBuiltinTwin) {
  EXPECT_TRUE(ScenarioNamesImageApp("builtin:circle", "circle"));
  EXPECT_TRUE(ScenarioNamesImageApp("circle", "circle"));
  EXPECT_TRUE(ScenarioNamesImageApp("strongest", "strongest"));
  EXPECT_FALSE(ScenarioNamesImageApp("builtin:gather", "circle"));
  EXPECT_FALSE(ScenarioNamesImageApp("builtin:gather", "strongest"));
  EXPECT_FALSE(ScenarioNamesImageApp("build/libstrongest.so", "strongest"));
  EXPECT_FALSE(ScenarioNamesImageApp("builtin:", ""));
  EXPECT_FALSE(ScenarioNamesImageApp("", ""));
  EXPECT_FALSE(ScenarioNamesImageApp("builtin:circle", "builtin:circle2"));
}

// The warning names both apps and the image, in one line; none when they agree.
TEST(ImageAppTest, MismatchWarningIsOneLineNamingBothApps) {
  EXPECT_FALSE(AppMismatchWarning("builtin:circle", "circle", "robot.elf").has_value());
  const std::optional<std::string> warning = AppMismatchWarning("builtin:gather", "circle", "build-m4/bin/robot.elf");
  ASSERT_TRUE(warning.has_value());
  EXPECT_EQ(warning->find('\n'), std::string::npos);
  EXPECT_EQ(warning->rfind("syrof-firmware-swarm: warning: the scenario names app 'builtin:gather', but the robot "
                           "image build-m4/bin/robot.elf runs its compiled-in app 'circle'",
                           0),
            0u)
      << *warning;
}

TEST(ImageAppTest, OneImageRunsOneApp) {
  const std::vector<std::string> same = {"circle", "circle", "circle"};
  EXPECT_EQ(OneImageApp(same).app, "circle");
  EXPECT_TRUE(OneImageApp(same).ok());
  const std::vector<std::string> mixed = {"circle", "circle", "gather"};
  const ImageAppOrError other = OneImageApp(mixed);
  EXPECT_FALSE(other.ok());
  ASSERT_TRUE(other.error.has_value());
  EXPECT_EQ(other.error->ToString(), "robot 2's image says it runs app 'gather', robot 0's 'circle' (one image runs one app)");
  EXPECT_FALSE(OneImageApp({}).ok());
  EXPECT_EQ(OneImageApp({}).error.value_or(lab::Error{}).message, "no robot said which app it runs");
}

}  // namespace
}  // namespace syrof::firmware::swarm
