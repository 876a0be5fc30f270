// Where a run's robots get their apps, and what the run's outputs say of
// them: one value that the lab's SimulationOptions, lab/search's
// SearchOptions and `syrof run`'s options each hold as one field.
// app_host::AppsFor makes it from a scenario (a built-in app or a
// student's library in sandboxed hosts); tests and tools fill one in
// directly.
#pragma once

#include <cstdint>
#include <functional>
#include <memory>
#include <optional>
#include <string>
#include <vector>

#include "syrof/app/app.h"

namespace syrof::lab::apps {

struct AppSupply {
  /// Makes robot `id`'s app, one instance per robot, never nullptr for a
  /// robot of the run. Empty: the scenario's built-in app (MakeBuiltinApp).
  /// A run with several threads (or a search with several jobs) calls it,
  /// and the apps it made, from several threads at once.
  std::function<std::unique_ptr<app::App>(uint16_t id)> factory;
  /// The app as the user should read its name (a library's path):
  /// metrics.json's app.source and goal.app and the replay header's
  /// app_name. Empty: the scenario's app ("builtin:NAME").
  std::string source;
  /// metrics.json's app.sandbox: what the app host's sandbox could not
  /// apply on this machine, one line each (a library run); unset (null)
  /// for apps that run inside the simulator.
  std::optional<std::vector<std::string>> sandbox;
};

}  // namespace syrof::lab::apps
