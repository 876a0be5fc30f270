#include <gtest/gtest.h>

#include <array>
#include <filesystem>
#include <fstream>
#include <map>
#include <string>

#include "scenario_test_util.h"
#include "syrof/app.h"
#include "schema.h"
#include "syrof/lab/apps/catalog.h"
#include "text_checks.h"
#include "yaml_tree.h"

namespace syrof::lab::scenario {
namespace {

using testing::FailsAt;
using testing::Load;

// A catalog of our own, so the parameter rules are tested whatever the
// built-in apps declare today.
constexpr apps::ParamInfo kOrbitParams[] = {
    {"radius_m", 1.0, 0.2, 3.0, "circle radius, m"},
    {"speed_mps", 0.2, 0.0, 0.5, "tangential speed, m/s"},
};
const std::array<apps::BuiltinAppInfo, 2> kCatalog{{
    {"still", "hold still", {}},
    {"orbit", "circle around the centre", kOrbitParams},
}};

// Reads `app:` from a one-key document against kCatalog.
std::optional<ScenarioError> ReadAppText(const std::string& text, AppSpec& app) {
  Diagnostics diagnostics("app.yaml");
  YamlNode root;
  if (ReadYamlDocument(text, root, diagnostics)) ReadApp(*root.Find("app"), kCatalog, "", app, diagnostics);
  return diagnostics.error();
}

TEST(ReadApp, AcceptsANameAndParameters) {
  AppSpec app;

  const auto error = ReadAppText("app: { name: 'builtin:orbit', params: { radius_m: 1.5 } }\n", app);

  ASSERT_FALSE(error) << error->ToString();
  EXPECT_EQ(app.name, "builtin:orbit");
  ASSERT_EQ(app.params.size(), 1u);
  EXPECT_EQ(app.params.at("radius_m"), 1.5);
}

TEST(ReadApp, UnknownAppListsTheValidNames) {
  AppSpec app;

  const auto error = ReadAppText("app: builtin:orbitt\n", app);

  ASSERT_TRUE(error);
  EXPECT_EQ(error->line, 1);
  EXPECT_EQ(error->column, 6);
  EXPECT_NE(error->message.find("app: unknown app 'builtin:orbitt' (did you mean 'builtin:orbit'?)"),
            std::string::npos);
  EXPECT_NE(error->message.find("built-in apps: builtin:still, builtin:orbit"), std::string::npos);
}

TEST(ReadApp, NameWithoutPrefixSuggestsIt) {
  AppSpec app;

  const auto error = ReadAppText("app: orbit\n", app);

  ASSERT_TRUE(error);
  EXPECT_NE(error->message.find("did you mean 'builtin:orbit'?"), std::string::npos);
}

TEST(ReadApp, UnknownParameterSuggestsTheNearest) {
  AppSpec app;

  const auto error = ReadAppText("app:\n  name: builtin:orbit\n  params: { raduis_m: 1 }\n", app);

  ASSERT_TRUE(error);
  EXPECT_EQ(error->line, 3);
  EXPECT_EQ(error->column, 13);
  EXPECT_NE(error->message.find("app.params: unknown parameter 'raduis_m'"), std::string::npos);
  EXPECT_NE(error->message.find("did you mean 'radius_m'?"), std::string::npos);
}

TEST(ReadApp, ParameterOutsideItsBoundsIsRefused) {
  AppSpec app;

  const auto error = ReadAppText("app:\n  name: builtin:orbit\n  params: { speed_mps: 0.9 }\n", app);

  ASSERT_TRUE(error);
  EXPECT_EQ(error->line, 3);
  EXPECT_EQ(error->column, 24);
  EXPECT_NE(error->message.find("app.params.speed_mps: must be in [0, 0.5], got 0.9"), std::string::npos);
}

TEST(ReadApp, AppWithoutParametersSaysSo) {
  AppSpec app;

  const auto error = ReadAppText("app: { name: 'builtin:still', params: { x: 1 } }\n", app);

  ASSERT_TRUE(error);
  EXPECT_NE(error->message.find("takes no parameters"), std::string::npos);
}

TEST(ReadApp, MapNeedsAName) {
  AppSpec app;

  const auto error = ReadAppText("app: { params: {} }\n", app);

  ASSERT_TRUE(error);
  EXPECT_NE(error->message.find("missing required key 'app.name'"), std::string::npos);
}

TEST(OverrideApp, KeepsParametersOfTheSameAppAndDropsOthers) {
  AppSpec app;
  ASSERT_FALSE(ReadAppText("app: { name: 'builtin:orbit', params: { radius_m: 2 } }\n", app));
  Diagnostics diagnostics("app.yaml");

  ASSERT_TRUE(OverrideApp("builtin:orbit", kCatalog, app, diagnostics));
  EXPECT_EQ(app.params.size(), 1u);
  ASSERT_TRUE(OverrideApp("builtin:still", kCatalog, app, diagnostics));

  EXPECT_EQ(app.name, "builtin:still");
  EXPECT_TRUE(app.params.empty());
}

TEST(OverrideApp, UnknownAppHasNoPlace) {
  AppSpec app;
  Diagnostics diagnostics("app.yaml");

  EXPECT_FALSE(OverrideApp("builtin:nope", kCatalog, app, diagnostics));

  ASSERT_TRUE(diagnostics.failed());
  EXPECT_EQ(diagnostics.error()->line, 0);
  EXPECT_NE(diagnostics.error()->message.find("app override: unknown app 'builtin:nope'"), std::string::npos);
}

TEST(ReadApp, TheRealCatalogNamesEveryBuiltinApp) {
  const LoadResult result = Load("robots: { count: 2 }\napp: builtin:nosuchapp\n");

  ASSERT_FALSE(result.ok());
  for (const apps::BuiltinAppInfo& info : apps::BuiltinApps()) {
    EXPECT_NE(result.error->message.find(std::string("builtin:") + info.name), std::string::npos) << info.name;
  }
  EXPECT_TRUE(FailsAt(result, 2, 6, {"app: unknown app 'builtin:nosuchapp'"}));
}

// ---- A student's library ------------------------------------------------------

namespace fs = std::filesystem;

// A folder holding scenario.yaml (with `app_text` after a minimal robots
// section) and an empty file lib/libmy.so beside it.
class LibraryAppTest : public ::testing::Test {
 protected:
  void SetUp() override {
    dir_ = fs::temp_directory_path() / ("syrof_scenario_library_" + std::string(
                                            ::testing::UnitTest::GetInstance()->current_test_info()->name()));
    fs::remove_all(dir_);
    fs::create_directories(dir_ / "lib");
    std::ofstream(dir_ / "lib" / "libmy.so") << "not really a library: the loader checks only that it is a file";
  }
  void TearDown() override { fs::remove_all(dir_); }

  LoadResult LoadWithApp(const std::string& app_text, const Overrides& overrides = {}) {
    const fs::path path = dir_ / "scenario.yaml";
    std::ofstream(path) << "robots: { count: 2 }\n" << app_text;
    return LoadScenarioFile(path.string(), overrides);
  }

  fs::path dir_;
};

TEST_F(LibraryAppTest, ARelativePathIsResolvedAgainstTheScenarioFolder) {
  const LoadResult result = LoadWithApp("app: { library: lib/libmy.so }\n");

  ASSERT_TRUE(result.ok()) << result.error->ToString();
  const AppSpec& app = result.scenario->app;
  EXPECT_TRUE(app.is_library());
  EXPECT_EQ(app.name, "lib/libmy.so");
  EXPECT_EQ(fs::path(app.library), dir_ / "lib" / "libmy.so");
  EXPECT_FALSE(app.cpu_budget_ms);
  EXPECT_FALSE(app.wall_cap_ms);
}

TEST_F(LibraryAppTest, TheShortFormTakesAPath) {
  const LoadResult result = LoadWithApp("app: lib/libmy.so\n");

  ASSERT_TRUE(result.ok()) << result.error->ToString();
  EXPECT_EQ(fs::path(result.scenario->app.library), dir_ / "lib" / "libmy.so");
}

TEST_F(LibraryAppTest, AMissingLibraryIsNamedAtItsPlace) {
  const LoadResult result = LoadWithApp("app:\n  library: lib/libnope.so\n");

  EXPECT_TRUE(FailsAt(result, 3, 12, {"app.library: no such library file 'lib/libnope.so'", "looked for",
                                       (dir_ / "lib" / "libnope.so").string().c_str()}));
}

TEST_F(LibraryAppTest, AFolderIsNotALibrary) {
  const LoadResult result = LoadWithApp("app: { library: lib/ }\n");

  EXPECT_TRUE(FailsAt(result, 2, 17, {"app.library:", "is a folder"}));
}

TEST_F(LibraryAppTest, AMisspelledKeySuggestsLibrary) {
  const LoadResult result = LoadWithApp("app: { libary: lib/libmy.so }\n");

  EXPECT_TRUE(FailsAt(result, 2, 8, {"app: unknown key 'libary'", "did you mean 'library'?"}));
}

TEST_F(LibraryAppTest, NameAndLibraryTogetherAreRefused) {
  const LoadResult result = LoadWithApp("app: { name: builtin:idle, library: lib/libmy.so }\n");

  EXPECT_TRUE(FailsAt(result, 2, 28, {"either 'name'", "or 'library'", "not both"}));
}

TEST_F(LibraryAppTest, ParamsOfALibraryAreAnyNamedNumbers) {
  const LoadResult result =
      LoadWithApp("app: { library: lib/libmy.so, params: { radius_m: 1.5, _gain2: -3e-2, Margin: 0 } }\n");

  ASSERT_TRUE(result.ok()) << result.error->ToString();
  const std::map<std::string, double> expected{{"radius_m", 1.5}, {"_gain2", -0.03}, {"Margin", 0}};
  EXPECT_EQ(result.scenario->app.params, expected);
}

TEST_F(LibraryAppTest, ALibraryParamMustBeANumber) {
  EXPECT_TRUE(FailsAt(LoadWithApp("app: { library: lib/libmy.so, params: { radius_m: big } }\n"), 2, 51,
                      {"app.params.radius_m:"}));
  EXPECT_TRUE(FailsAt(LoadWithApp("app: { library: lib/libmy.so, params: [1, 2] }\n"), 2, 39, {"app.params:"}));
}

TEST_F(LibraryAppTest, ALibraryParamNameIsAnIdentifier) {
  EXPECT_TRUE(FailsAt(LoadWithApp("app: { library: lib/libmy.so, params: { 2fast: 1 } }\n"), 2, 41,
                      {"app.params: parameter name '2fast' must start with a letter"}));
  EXPECT_TRUE(FailsAt(LoadWithApp("app: { library: lib/libmy.so, params: { \"radius m\": 1 } }\n"), 2, 41,
                      {"parameter name 'radius m'"}));
}

TEST_F(LibraryAppTest, ALibraryParamNameHasALengthLimit) {
  const std::string longest(SYROF_APP_MAX_PARAMETER_NAME_LENGTH, 'a');
  const LoadResult ok = LoadWithApp("app: { library: lib/libmy.so, params: { " + longest + ": 1 } }\n");
  ASSERT_TRUE(ok.ok()) << ok.error->ToString();
  EXPECT_EQ(ok.scenario->app.params.count(longest), 1u);

  const std::string too_long(SYROF_APP_MAX_PARAMETER_NAME_LENGTH + 1, 'a');
  EXPECT_TRUE(FailsAt(LoadWithApp("app: { library: lib/libmy.so, params: { " + too_long + ": 1 } }\n"), 2, 41,
                      {"characters long; at most 63"}));
}

TEST_F(LibraryAppTest, ALibraryTakesAtMostSoManyParams) {
  std::string params;
  for (unsigned i = 0; i <= SYROF_APP_MAX_PARAMETERS; ++i) params += "    p" + std::to_string(i) + ": 1\n";
  // 32 are fine, the 33rd is refused where it stands.
  const LoadResult result = LoadWithApp("app:\n  library: lib/libmy.so\n  params:\n" + params);

  EXPECT_TRUE(FailsAt(result, 5 + static_cast<int>(SYROF_APP_MAX_PARAMETERS), 5,
                      {"too many parameters: 33, a library app takes at most 32"}));
}

TEST_F(LibraryAppTest, ALibraryOverrideKeepsTheFilesParams) {
  Overrides overrides;
  overrides.app = (dir_ / "lib" / "libmy.so").string();

  const LoadResult result = LoadWithApp("app: { library: lib/libmy.so, params: { radius_m: 2 } }\n", overrides);

  ASSERT_TRUE(result.ok()) << result.error->ToString();
  EXPECT_EQ(result.scenario->app.params.at("radius_m"), 2.0);
}

TEST_F(LibraryAppTest, BudgetsAreReadAndChecked) {
  const LoadResult ok = LoadWithApp("app: { library: lib/libmy.so, cpu_budget_ms: 50, wall_cap_ms: 400 }\n");
  ASSERT_TRUE(ok.ok()) << ok.error->ToString();
  EXPECT_EQ(ok.scenario->app.cpu_budget_ms, 50u);
  EXPECT_EQ(ok.scenario->app.wall_cap_ms, 400u);

  EXPECT_TRUE(FailsAt(LoadWithApp("app: { library: lib/libmy.so, cpu_budget_ms: 0 }\n"), 2, 46,
                      {"app.cpu_budget_ms: must be in [1, 60000], got 0"}));
  EXPECT_TRUE(FailsAt(LoadWithApp("app: { library: lib/libmy.so, cpu_budget_ms: 300, wall_cap_ms: 200 }\n"), 2, 64,
                      {"app.wall_cap_ms: must be at least cpu_budget_ms (300), got 200"}));
}

TEST_F(LibraryAppTest, ABudgetOnABuiltinAppIsRefused) {
  const LoadResult result = LoadWithApp("app: { name: builtin:idle, cpu_budget_ms: 50 }\n");

  EXPECT_TRUE(FailsAt(result, 2, 28, {"'cpu_budget_ms' is for a library app"}));
}

TEST_F(LibraryAppTest, APathUnderNameSaysToUseLibrary) {
  const LoadResult result = LoadWithApp("app: { name: lib/libmy.so }\n");

  EXPECT_TRUE(FailsAt(result, 2, 14, {"write it as 'library: lib/libmy.so'"}));
}

TEST_F(LibraryAppTest, TheCommandLineNamesALibraryRelativeToTheWorkingDirectory) {
  Overrides overrides;
  overrides.app = (dir_ / "lib" / "libmy.so").string();

  const LoadResult result = LoadWithApp("app: builtin:idle\n", overrides);

  ASSERT_TRUE(result.ok()) << result.error->ToString();
  EXPECT_EQ(result.scenario->app.library, *overrides.app);
  EXPECT_EQ(result.scenario->app.name, *overrides.app);
}

TEST_F(LibraryAppTest, AMissingLibraryOnTheCommandLineIsNamed) {
  Overrides overrides;
  overrides.app = "./libnothere.so";

  const LoadResult result = LoadWithApp("app: builtin:idle\n", overrides);

  ASSERT_FALSE(result.ok());
  EXPECT_EQ(result.error->line, 0);
  EXPECT_NE(result.error->message.find("app override: no such library file './libnothere.so'"), std::string::npos)
      << result.error->ToString();
}

TEST_F(LibraryAppTest, ABuiltinOverrideReplacesALibraryAndItsLimits) {
  Overrides overrides;
  overrides.app = "builtin:idle";

  const LoadResult result = LoadWithApp("app: { library: lib/libmy.so, cpu_budget_ms: 50 }\n", overrides);

  ASSERT_TRUE(result.ok()) << result.error->ToString();
  EXPECT_FALSE(result.scenario->app.is_library());
  EXPECT_FALSE(result.scenario->app.cpu_budget_ms);
}

TEST(IsLibraryPath, APathOrASoFileNameIsALibrary) {
  EXPECT_TRUE(IsLibraryPath("./libmy.so"));
  EXPECT_TRUE(IsLibraryPath("libmy.so"));
  EXPECT_TRUE(IsLibraryPath("build/libmy"));
  EXPECT_FALSE(IsLibraryPath("builtin:circle"));
  EXPECT_FALSE(IsLibraryPath("circle"));
}

}  // namespace
}  // namespace syrof::lab::scenario
