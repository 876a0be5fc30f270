// The app the robot image runs, as syrof-firmware-swarm learns it: the image
// has its app compiled in (the starter's circle, or the C file the build's
// SYROF_FIRMWARE_APP names) and runs it whatever the scenario's `app:` says;
// each robot says its name on its `held` line (console_lines.h, HeldLine),
// before the world starts and the replay is opened. The host records that
// name in the replay's header and metrics.json, and says on standard error,
// once, when the scenario names another app (docs/firmware.md, "The
// emulated swarm").
#pragma once

#include <optional>
#include <span>
#include <string>
#include <string_view>

#include "syrof/lab/base/error.h"

namespace syrof::firmware::swarm {

/// Whether the scenario's `app:` (`scenario_app`: "builtin:NAME" or a
/// library's path as written) names the app the image runs (`image_app`, its
/// descriptor's name): the same name, or "builtin:" and that name (the lab's
/// built-in twin of the image's app, as builtin:circle is of the starter's
/// circle). A library's path never does: the image loads no library.
bool ScenarioNamesImageApp(std::string_view scenario_app, std::string_view image_app);

/// The one line (no newline) syrof-firmware-swarm writes to standard error
/// when the scenario names another app than the image runs, or nullopt when
/// it names the image's (ScenarioNamesImageApp).
std::optional<std::string> AppMismatchWarning(std::string_view scenario_app, std::string_view image_app,
                                              std::string_view image_path);

/// The app every robot's image said it runs (`apps`, one per robot, in id
/// order), or why there is none: which robot said another than robot 0
/// (they run one image, so that is a fault of the host or the image), or
/// that no robot said one.
struct ImageAppOrError {
  std::optional<std::string> app;
  std::optional<lab::Error> error;
  bool ok() const { return app.has_value(); }
};
ImageAppOrError OneImageApp(std::span<const std::string> apps);

}  // namespace syrof::firmware::swarm
