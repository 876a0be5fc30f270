#include <gtest/gtest.h>

#include <array>
#include <string>

#include "scenario_test_util.h"
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
  if (ReadYamlDocument(text, root, diagnostics)) ReadApp(*root.Find("app"), kCatalog, app, diagnostics);
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

}  // namespace
}  // namespace syrof::lab::scenario
