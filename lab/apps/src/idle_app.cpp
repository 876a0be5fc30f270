// idle: holds still in every epoch, whatever the mode.
#include "builtin_apps.h"

namespace syrof::lab::apps {
namespace {

class IdleApp final : public app::App {
 public:
  const char* name() const override { return "idle"; }
  uint8_t Init(const syrof_app_info& /*info*/, app::Platform& /*platform*/) override { return 0; }
  uint8_t NewRound(syrof_car_command& command, const syrof_ldmap& /*ldmap*/, uint8_t global_state,
                   uint32_t /*clock_ms*/) override {
    command = syrof_car_command{};
    command.kind = SYROF_COMMAND_STOP;
    return global_state;
  }
  uint8_t EndOfRound(const syrof_ldmap& /*ldmap*/, uint8_t global_state, uint32_t /*clock_ms*/) override {
    return global_state;
  }
};

}  // namespace

std::unique_ptr<app::App> MakeIdleApp() { return std::make_unique<IdleApp>(); }

}  // namespace syrof::lab::apps
