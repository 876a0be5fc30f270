#include "syrof/lab/sim/fault_schedule.h"

#include <cmath>

#include "syrof/base/check.h"
#include "units.h"

namespace syrof::lab::sim {
namespace {

FaultAction::Kind ActionFor(scenario::FaultKind kind) {
  switch (kind) {
    case scenario::FaultKind::kCrash: return FaultAction::Kind::kCrash;
    case scenario::FaultKind::kPause: return FaultAction::Kind::kPause;
    case scenario::FaultKind::kJoin: return FaultAction::Kind::kJoin;
    case scenario::FaultKind::kDeaf:
    case scenario::FaultKind::kMute: break;  // filtered out by the constructor
  }
  return FaultAction::Kind::kCrash;
}

}  // namespace

FaultSchedule::FaultSchedule(std::span<const scenario::FaultSpec> faults, int64_t radio_round_ns)
    : radio_round_ns_(radio_round_ns) {
  SYROF_CHECK(radio_round_ns_ > 0);
  // Deaf and mute act on the radio (RadioNetwork), not on the robot.
  for (const scenario::FaultSpec& fault : faults) {
    if (!scenario::IsRadioFault(fault.kind)) faults_.push_back(fault);
  }
  resume_ns_.reserve(faults_.size());
  for (const scenario::FaultSpec& fault : faults_) {
    // The software restarts one radio round before until_s takes effect, so
    // its first round ends there: a pause of P rounds misses exactly P round
    // ends (docs/scenarios.md, "Pause timing").
    resume_ns_.push_back(fault.kind == scenario::FaultKind::kPause ? EffectiveNs(fault.until_s) - radio_round_ns_
                                                                   : -1);
  }
  due_.reserve(2 * faults_.size());
}

int64_t FaultSchedule::EffectiveNs(double time_s) const {
  return ((Nanoseconds(time_s) + radio_round_ns_ - 1) / radio_round_ns_) * radio_round_ns_;
}

std::span<const FaultAction> FaultSchedule::Due(int64_t now_ns) {
  due_.clear();
  if (now_ns % radio_round_ns_ != 0) return due_;
  // A fault at t is due at the first grid point >= t: here when t <= now_ns
  // (every earlier grid point was before t).
  while (next_ < faults_.size() && Nanoseconds(faults_[next_].at_s) <= now_ns) {
    due_.push_back({ActionFor(faults_[next_].kind), faults_[next_].robot});
    ++next_;
  }
  for (size_t i = 0; i < faults_.size(); ++i) {
    if (resume_ns_[i] == now_ns) due_.push_back({FaultAction::Kind::kResume, faults_[i].robot});
  }
  return due_;
}

}  // namespace syrof::lab::sim
