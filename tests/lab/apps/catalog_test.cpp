#include "syrof/lab/apps/catalog.h"

#include <gtest/gtest.h>

#include <set>
#include <string>

#include "app_test_support.h"

namespace syrof::lab::apps {
namespace {

TEST(CatalogTest, ListsTheFourAppsInOrder) {
  // Act
  const std::span<const BuiltinAppInfo> apps = BuiltinApps();

  // Assert
  ASSERT_EQ(apps.size(), 4u);
  EXPECT_STREQ(apps[0].name, "idle");
  EXPECT_STREQ(apps[1].name, "gather");
  EXPECT_STREQ(apps[2].name, "circle");
  EXPECT_STREQ(apps[3].name, "leader_follow");
  EXPECT_TRUE(apps[0].params.empty());
}

TEST(CatalogTest, ListsEachAppsParameters) {
  // Arrange
  const auto names = [](const char* app) {
    std::set<std::string> out;
    for (const ParamInfo& param : FindBuiltinApp(app)->params) out.insert(param.name);
    return out;
  };

  // Act, assert
  EXPECT_EQ(names("gather"), (std::set<std::string>{"gap_m", "tolerance_m", "margin_m"}));
  EXPECT_EQ(names("circle"), (std::set<std::string>{"radius_m", "centre_x_m", "centre_y_m", "tolerance_m", "margin_m"}));
  EXPECT_EQ(names("leader_follow"),
            (std::set<std::string>{"speed_mps", "spacing_m", "path_radius_m", "tolerance_m", "margin_m"}));
}

TEST(CatalogTest, EveryDefaultLiesWithinItsBoundsAndHasADoc) {
  for (const BuiltinAppInfo& app : BuiltinApps()) {
    EXPECT_GT(std::string(app.summary).size(), 0u) << app.name;
    for (const ParamInfo& param : app.params) {
      EXPECT_LE(param.min_value, param.default_value) << app.name << "." << param.name;
      EXPECT_LE(param.default_value, param.max_value) << app.name << "." << param.name;
      EXPECT_GT(std::string(param.doc).size(), 10u) << app.name << "." << param.name;
    }
  }
}

TEST(CatalogTest, BriefDefaults) {
  EXPECT_DOUBLE_EQ(ParamValue(*FindBuiltinApp("gather"), {}, "gap_m"), 0.1);
  EXPECT_DOUBLE_EQ(ParamValue(*FindBuiltinApp("circle"), {}, "radius_m"), 1.2);
  EXPECT_DOUBLE_EQ(ParamValue(*FindBuiltinApp("leader_follow"), {}, "speed_mps"), 0.15);
  EXPECT_DOUBLE_EQ(ParamValue(*FindBuiltinApp("leader_follow"), {}, "spacing_m"), 0.4);
}

TEST(CatalogTest, ParamValuePrefersTheGivenValue) {
  // Arrange
  const BuiltinAppInfo& circle = *FindBuiltinApp("circle");

  // Act
  const double given = ParamValue(circle, {{"radius_m", 0.9}}, "radius_m");
  const double unknown = ParamValue(circle, {}, "no_such_param");

  // Assert
  EXPECT_DOUBLE_EQ(given, 0.9);
  EXPECT_DOUBLE_EQ(unknown, 0.0);
}

TEST(CatalogTest, FindBuiltinAppUnknownNameIsNull) {
  EXPECT_EQ(FindBuiltinApp("builtin:circle"), nullptr);
  EXPECT_EQ(FindBuiltinApp(""), nullptr);
}

TEST(CatalogTest, MakeBuiltinAppUnknownNameIsNull) { EXPECT_EQ(MakeBuiltinApp("dance", {}), nullptr); }

TEST(CatalogTest, MakeBuiltinAppMakesEveryListedApp) {
  for (const BuiltinAppInfo& info : BuiltinApps()) {
    // Act
    const std::unique_ptr<app::App> made = MakeBuiltinApp(info.name, {});

    // Assert
    ASSERT_NE(made, nullptr) << info.name;
    EXPECT_STREQ(made->name(), info.name);
  }
}

}  // namespace
}  // namespace syrof::lab::apps
