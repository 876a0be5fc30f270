#include "syrof/app_host/app_supply.h"

#include <fmt/format.h>

#include <map>
#include <memory>
#include <utility>

#include "syrof/base/check.h"
#include "syrof/lab/apps/catalog.h"
#include "syrof/lab/sim/run_parts.h"

namespace syrof::app_host {
namespace {

namespace scenario = lab::scenario;

lab::Error Problem(std::string message) { return lab::Error{"", 0, 0, std::move(message)}; }

// The scenario's built-in app, as the lab makes it by default.
AppsResult BuiltinApps(const scenario::AppSpec& app, const AppRequest& request) {
  AppsResult result;
  if (request.cpu_budget_ms || request.wall_cap_ms) {
    result.error = Problem(fmt::format("{} is for a library app; {} runs inside the simulator",
                                       request.cpu_budget_ms ? "--cpu-budget-ms" : "--wall-cap-ms", app.name));
    return result;
  }
  result.supply.factory = [name = app.name, params = app.params](uint16_t) {
    return lab::apps::MakeBuiltinApp(lab::apps::BareAppName(name), params);
  };
  return result;
}

// The request's budgets over the scenario's over the host's defaults.
HostLimits LimitsFor(const scenario::AppSpec& app, const AppRequest& request) {
  return HostLimits::ForBudgets(request.cpu_budget_ms ? request.cpu_budget_ms : app.cpu_budget_ms,
                                request.wall_cap_ms ? request.wall_cap_ms : app.wall_cap_ms);
}

// A wall cap below the CPU budget would time out a callback the budget allows.
std::optional<lab::Error> CheckLimits(const HostLimits& limits) {
  if (limits.wall_cap_ms >= limits.cpu_budget_ms) return std::nullopt;
  return Problem(fmt::format("the wall cap ({} ms) must be at least the CPU budget ({} ms)", limits.wall_cap_ms,
                             limits.cpu_budget_ms));
}

HostOptions HostFor(const scenario::Scenario& scenario, const std::string& library, const HostLimits& limits,
                    const std::string& log_directory) {
  HostOptions host;
  host.library_path = library;
  host.log_directory = log_directory;
  host.limits = limits;
  host.params = scenario.app.params;
  for (const scenario::RobotSpec& robot : scenario.robots) {
    host.inputs[robot.id] = lab::sim::InputValuesOf(scenario, robot.id);
  }
  return host;
}

std::string SourceOf(const std::vector<std::string>& shown) {
  std::string source;
  for (const std::string& library : shown) source += (source.empty() ? "" : " + ") + library;
  return source;
}

AppsResult LibraryApps(const scenario::Scenario& scenario, const std::vector<std::string>& libraries,
                       const AppRequest& request) {
  SYROF_CHECK(request.shown_libraries.empty() || request.shown_libraries.size() == libraries.size());
  AppsResult result;
  const HostLimits limits = LimitsFor(scenario.app, request);
  result.error = CheckLimits(limits);
  if (result.error) return result;
  for (const std::string& library : libraries) {
    result.hosts.push_back(HostFor(scenario, library, limits, request.log_directory));
    if (!request.check_first) continue;
    const LibraryCheck check = CheckLibrary(result.hosts.back());
    if (!check.ok()) {
      result.error = check.error;  // it names the file
      return result;
    }
  }
  if (request.load_once) {
    std::vector<std::shared_ptr<LoadedLibrary>> loaded;
    for (const HostOptions& host : result.hosts) loaded.push_back(LoadOnce(host));
    result.supply.factory = [hosts = result.hosts, loaded = std::move(loaded)](uint16_t id) {
      return MakeHostedApp(hosts[id % hosts.size()], id, loaded[id % loaded.size()]);
    };
  } else {
    result.supply.factory = [hosts = result.hosts](uint16_t id) { return MakeHostedApp(hosts[id % hosts.size()], id); };
  }
  result.supply.source = SourceOf(request.shown_libraries.empty() ? libraries : request.shown_libraries);
  result.supply.sandbox = SandboxNotes();
  return result;
}

}  // namespace

AppsResult AppsFor(const scenario::Scenario& scenario, const AppRequest& request) {
  if (!request.libraries.empty()) return LibraryApps(scenario, request.libraries, request);
  if (scenario.app.is_library()) return LibraryApps(scenario, {scenario.app.library}, request);
  return BuiltinApps(scenario.app, request);
}

}  // namespace syrof::app_host
