#include "apps_command.h"

#include <fmt/format.h>
#include <fmt/ostream.h>

#include <string>
#include <string_view>

#include "syrof/lab/apps/catalog.h"

namespace syrof::cli {

namespace apps = lab::apps;

namespace {

// What the schedule search (syrof search --activations ssync on 3 robots
// on a circle, no loss) found for each built-in: no schedule of that many
// epochs broke P3, agreement, the no-collision rule or the app
// (docs/activation.md, "Which apps survive SSYNC").
struct SearchedUnderSsync {
  std::string_view app;
  int epochs;
  const char* schedules;
};
constexpr SearchedUnderSsync kSearched[] = {
    {"idle", 4, "2,401"}, {"gather", 6, "117,649"}, {"circle", 4, "2,401"}, {"leader_follow", 4, "2,401"}};

std::string ModelsOf(std::string_view name) {
  for (const SearchedUnderSsync& searched : kSearched) {
    if (searched.app == name) {
      return fmt::format("FSYNC; SSYNC (every schedule of 3 robots over {} epochs survived: {})", searched.epochs,
                         searched.schedules);
    }
  }
  return "FSYNC";
}

}  // namespace

CLI::App* SetupAppsCommand(CLI::App& app, AppsOptions& /*options*/) {
  return app.add_subcommand("apps", "List the built-in apps and their parameters");
}

int RunAppsCommand(const AppsOptions& /*options*/, std::ostream& out) {
  for (const apps::BuiltinAppInfo& app : apps::BuiltinApps()) {
    fmt::print(out, "builtin:{:<14} {}\n", app.name, app.summary);
    fmt::print(out, "    models: {}\n", ModelsOf(app.name));
    for (const apps::ParamInfo& param : app.params) {
      fmt::print(out, "    {:<16} default {:<8} [{} .. {}]  {}\n", param.name, param.default_value, param.min_value,
                 param.max_value, param.doc);
    }
  }
  fmt::print(out,
             "\nYour own app: a shared library in C or C++ against syrof/app.h (docs/apps.md, \"Your first app\"):\n"
             "    syrof new myapp                      a project with a starter app, CMakeLists.txt and scenario\n"
             "    syrof run SCENARIO --app build/libmyapp.so\n"
             "    or in a scenario: app: {{library: build/libmyapp.so, cpu_budget_ms: 100}}\n");
  return 0;
}

}  // namespace syrof::cli
