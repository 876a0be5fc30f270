#include "apps_command.h"

#include <fmt/format.h>
#include <fmt/ostream.h>

#include <string>
#include <string_view>

#include "syrof/lab/apps/catalog.h"

namespace syrof::cli {

namespace apps = lab::apps;

namespace {

// What the schedule searches found for each built-in on 3 robots on a
// circle, no loss (lab/scenarios/gather3.yaml's swarm): no schedule broke
// P3, agreement, the no-collision rule or the app (docs/activation.md,
// "Which apps survive which model"). SSYNC: every schedule of `ssync_epochs`
// epochs. ASYNC, delays up to one epoch: every schedule of 3 epochs with
// rigid moves and of 2 epochs with moves cut at 5 cm, the same for every
// built-in (syrof search --activations async --max-delay 1).
struct Searched {
  std::string_view app;
  int ssync_epochs;
  const char* ssync_schedules;
};
constexpr Searched kSearched[] = {
    {"idle", 4, "2,401"}, {"gather", 6, "117,649"}, {"circle", 4, "2,401"}, {"leader_follow", 4, "2,401"}};

std::string ModelsOf(std::string_view name) {
  for (const Searched& searched : kSearched) {
    if (searched.app == name) {
      return fmt::format(
          "FSYNC\n"
          "            SSYNC: survived every schedule of 3 robots over {} epochs ({})\n"
          "            ASYNC: survived every schedule of 3 robots with delays up to 1 epoch over 3 epochs "
          "(4,096), and with moves cut at 5 cm over 2 epochs (10,648)",
          searched.ssync_epochs, searched.ssync_schedules);
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
