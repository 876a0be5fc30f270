// An App that forwards every call to the robot's real app and reports the
// global state each successful newRound and endOfRound returned, with the
// map it saw: the engine's feed for app-level agreement (docs/metrics.md,
// `agreement`). It changes nothing the app sees or returns.
#pragma once

#include <cstdint>
#include <memory>

#include "syrof/app/app.h"
#include "syrof/base/check.h"
#include "syrof/base/state_digest.h"
#include "syrof/app/state_digest.h"

namespace syrof::lab::sim {

/// Who hears the states: the engine.
class AppStateSink {
 public:
  virtual void OnAppState(uint16_t robot, bool new_round, const syrof_ldmap& ldmap, uint8_t state) = 0;

 protected:
  ~AppStateSink() = default;
};

/// A fingerprint of everything an app sees in `ldmap` except self_id and
/// the members' phases (what differs between robots holding the same
/// knowledge; P3 does not compare phases either). SplitMix64 over the
/// fields, so the same map gives the same number on every run.
uint64_t MapFingerprint(const syrof_ldmap& ldmap);

class RecordingApp final : public app::App {
 public:
  /// `keep_history`: keep every call's inputs for AddToDigest (the search's
  /// state fingerprints); off, AddToDigest must not be called.
  RecordingApp(std::unique_ptr<app::App> inner, uint16_t robot, AppStateSink& sink, bool keep_history)
      : inner_(std::move(inner)), robot_(robot), sink_(sink), keep_history_(keep_history) {}

  const char* name() const override { return inner_->name(); }
  app::CallStatus Init(const syrof_app_info& info, app::Platform& platform, uint8_t& global_state) override {
    if (keep_history_) {
      AddCall(0, nullptr, global_state, 0);
      history_.AddValue(info);
    }
    return inner_->Init(info, platform, global_state);
  }
  app::CallStatus NewRound(syrof_car_command& command, const syrof_ldmap& ldmap, uint8_t& global_state,
                           uint32_t clock_ms) override {
    if (keep_history_) {
      AddCall(1, &ldmap, global_state, clock_ms);
      app::AddToDigest(history_, command);
    }
    const app::CallStatus status = inner_->NewRound(command, ldmap, global_state, clock_ms);
    if (status.ok()) sink_.OnAppState(robot_, true, ldmap, global_state);
    return status;
  }
  app::CallStatus EndOfRound(const syrof_ldmap& ldmap, uint8_t& global_state, uint32_t clock_ms) override {
    if (keep_history_) AddCall(2, &ldmap, global_state, clock_ms);
    const app::CallStatus status = inner_->EndOfRound(ldmap, global_state, clock_ms);
    if (status.ok()) sink_.OnAppState(robot_, false, ldmap, global_state);
    return status;
  }

  /// Every call's inputs so far into `digest` (base/state_digest.h): the
  /// app's own state, for an app whose callbacks depend on nothing else
  /// (what the lab's determinism already asks of it).
  void AddToDigest(base::StateDigest& digest) const {
    SYROF_CHECK(keep_history_);
    digest.AddValue(history_.value());
  }

 private:
  void AddCall(uint8_t callback, const syrof_ldmap* ldmap, uint8_t global_state, uint32_t clock_ms);

  std::unique_ptr<app::App> inner_;
  base::StateDigest history_;
  uint16_t robot_;
  AppStateSink& sink_;
  bool keep_history_;
};

}  // namespace syrof::lab::sim
