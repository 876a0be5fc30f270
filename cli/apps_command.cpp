#include "apps_command.h"

#include <fmt/format.h>
#include <fmt/ostream.h>

#include "syrof/lab/apps/catalog.h"

namespace syrof::cli {

namespace apps = lab::apps;

CLI::App* SetupAppsCommand(CLI::App& app, AppsOptions& /*options*/) {
  return app.add_subcommand("apps", "List the built-in apps and their parameters");
}

int RunAppsCommand(const AppsOptions& /*options*/, std::ostream& out) {
  for (const apps::BuiltinAppInfo& app : apps::BuiltinApps()) {
    fmt::print(out, "builtin:{:<14} {}\n", app.name, app.summary);
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
