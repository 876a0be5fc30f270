#include "payload_check.h"

#include <utility>

namespace syrof::grader::internal {
namespace {

// Sits between the app and the robot's platform: checks, then forwards
// everything unchanged, so the run is the same with or without the check.
class CheckingPlatform final : public app::Platform {
 public:
  CheckingPlatform(const lab::message::MessageFormat& format, PayloadViolations& violations)
      : format_(format), violations_(violations) {}

  void Bind(app::Platform& platform) { platform_ = &platform; }
  void Enter(app::Callback callback, uint16_t epoch) {
    callback_ = callback;
    epoch_ = epoch;
  }

  syrof_app_status SendMessageData(std::span<const uint8_t> payload) override {
    const std::optional<lab::Error> problem = lab::message::CheckPayload(format_, payload.size());
    if (problem && violations_.count++ == 0) {
      violations_.first = std::string("in ") + app::ToString(callback_) + " of epoch " + std::to_string(epoch_) +
                          ": " + problem->message;
    }
    return platform_->SendMessageData(payload);
  }
  syrof_queries_workspace* queries_workspace() override { return platform_->queries_workspace(); }
  syrof_app_status AppParameter(std::string_view name, double& value) override {
    return platform_->AppParameter(name, value);
  }
  syrof_app_status AppInput(std::string_view name, double& value) override { return platform_->AppInput(name, value); }

 private:
  const lab::message::MessageFormat& format_;
  PayloadViolations& violations_;
  app::Platform* platform_ = nullptr;
  app::Callback callback_ = app::Callback::kInit;
  uint16_t epoch_ = 0;
};

class CheckingApp final : public app::App {
 public:
  CheckingApp(std::unique_ptr<app::App> app, const lab::message::MessageFormat& format,
              PayloadViolations& violations)
      : app_(std::move(app)), platform_(format, violations) {}

  const char* name() const override { return app_->name(); }
  app::CallStatus Init(const syrof_app_info& info, app::Platform& platform, uint8_t& global_state) override {
    platform_.Bind(platform);
    platform_.Enter(app::Callback::kInit, 0);
    return app_->Init(info, platform_, global_state);
  }
  app::CallStatus NewRound(syrof_car_command& command, const syrof_ldmap& ldmap, uint8_t& global_state,
                           uint32_t clock_ms) override {
    platform_.Enter(app::Callback::kNewRound, ldmap.epoch);
    return app_->NewRound(command, ldmap, global_state, clock_ms);
  }
  app::CallStatus EndOfRound(const syrof_ldmap& ldmap, uint8_t& global_state, uint32_t clock_ms) override {
    platform_.Enter(app::Callback::kEndOfRound, ldmap.epoch);
    return app_->EndOfRound(ldmap, global_state, clock_ms);
  }

 private:
  std::unique_ptr<app::App> app_;
  CheckingPlatform platform_;
};

}  // namespace

std::unique_ptr<app::App> CheckPayloads(std::unique_ptr<app::App> app, const lab::message::MessageFormat& format,
                                        PayloadViolations& violations) {
  return std::make_unique<CheckingApp>(std::move(app), format, violations);
}

}  // namespace syrof::grader::internal
