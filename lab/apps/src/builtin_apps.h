// Factories of the built-in apps, for the catalog (internal to lab/apps).
#pragma once

#include <memory>

#include "syrof/app/app.h"
#include "syrof/lab/apps/formation.h"

namespace syrof::lab::apps {

std::unique_ptr<app::App> MakeIdleApp();
std::unique_ptr<app::App> MakeGatherApp(const GatherParams& params);
std::unique_ptr<app::App> MakeCircleApp(const CircleParams& params);
std::unique_ptr<app::App> MakeLeaderFollowApp(const LeaderFollowParams& params);

}  // namespace syrof::lab::apps
