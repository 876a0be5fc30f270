#include "syrof/firmware/swarm/image_app.h"

#include "syrof/lab/apps/catalog.h"

namespace syrof::firmware::swarm {

bool ScenarioNamesImageApp(std::string_view scenario_app, std::string_view image_app) {
  if (image_app.empty()) return false;  // an image that names no app names none of the scenario's
  return scenario_app == image_app || (scenario_app.starts_with(lab::apps::kBuiltinPrefix) &&
                                       lab::apps::BareAppName(scenario_app) == image_app);
}

std::optional<std::string> AppMismatchWarning(std::string_view scenario_app, std::string_view image_app,
                                              std::string_view image_path) {
  if (ScenarioNamesImageApp(scenario_app, image_app)) return std::nullopt;
  return "syrof-firmware-swarm: warning: the scenario names app '" + std::string(scenario_app) +
         "', but the robot image " + std::string(image_path) + " runs its compiled-in app '" + std::string(image_app) +
         "': the robots run '" + std::string(image_app) +
         "', and the replay and metrics.json say so (another app needs an image built with SYROF_FIRMWARE_APP; "
         "docs/firmware.md, \"The emulated swarm\")";
}

ImageAppOrError OneImageApp(std::span<const std::string> apps) {
  auto fail = [](std::string message) {
    return ImageAppOrError{std::nullopt, lab::Error{.where = "", .line = 0, .column = 0, .message = std::move(message)}};
  };
  if (apps.empty()) return fail("no robot said which app it runs");
  for (size_t i = 1; i < apps.size(); ++i) {
    if (apps[i] != apps[0]) {
      return fail("robot " + std::to_string(i) + "'s image says it runs app '" + apps[i] + "', robot 0's '" +
                  apps[0] + "' (one image runs one app)");
    }
  }
  return ImageAppOrError{apps[0], std::nullopt};
}

}  // namespace syrof::firmware::swarm
