// idle: holds still in every epoch, whatever the mode.
#include "builtin_apps.h"

namespace syrof::lab::apps {
namespace {

class IdleApp final : public app::App {
 public:
  const char* name() const override { return "idle"; }
  app::CallStatus Init(const syrof_app_info& /*info*/, app::Platform& /*platform*/, uint8_t& global_state) override {
    global_state = 0;
    return app::CallStatus::Ok();
  }
  app::CallStatus NewRound(syrof_car_command& command, const syrof_ldmap& /*ldmap*/, uint8_t& /*global_state*/,
                           uint32_t /*clock_ms*/) override {
    command = syrof_car_command{};
    command.kind = SYROF_COMMAND_STOP;
    return app::CallStatus::Ok();
  }
  app::CallStatus EndOfRound(const syrof_ldmap& /*ldmap*/, uint8_t& /*global_state*/, uint32_t /*clock_ms*/) override {
    return app::CallStatus::Ok();
  }
};

}  // namespace

std::unique_ptr<app::App> MakeIdleApp() { return std::make_unique<IdleApp>(); }

}  // namespace syrof::lab::apps
