// A model of the NVIC, BASEPRI and a timer for running NvicPort on the host.
//
// Interrupts are nested calls: a pended level runs at once when it is above
// the active one and the kernel mask is not held, otherwise when the mask is
// released or the active handler returns, highest first (tail-chaining). The
// timer interrupt sits above every level. Time moves only when a test calls
// AdvanceTo() from "thread mode" or a step calls Spend() (its instructions
// take time), and the alarm fires on the way, as the hardware would.
#pragma once

#include <cstdint>
#include <string>
#include <vector>

#include "syrof/firmware/kernel/hardware.h"
#include "syrof/firmware/kernel/nvic_port.h"

namespace syrof::firmware::kernel::testing {

class FakeHardware final : public KernelHardware {
 public:
  /// The active priority of thread mode; levels are 0..kLevelCount-1.
  static constexpr int kThreadMode = -1;
  static constexpr int kTimerPriority = kLevelCount;

  void Attach(NvicPort& port) { port_ = &port; }

  void PendLevel(uint8_t level) override {
    pending_ |= 1u << level;
    ++pend_calls;
    TakeInterrupts();
  }
  uint32_t MaskKernel() override {
    const uint32_t previous = masked_ ? 1 : 0;
    masked_ = true;
    ++mask_calls;
    return previous;
  }
  void RestoreMask(uint32_t previous) override {
    masked_ = previous != 0;
    TakeInterrupts();
  }
  int64_t now_ns() override {
    if (!masked_) unmasked_clock_reads = true;  // the interface's contract
    return now_ns_;
  }
  void SetAlarm(int64_t at_ns) override { alarm_ns_ = at_ns; TakeInterrupts(); }

  /// Thread mode lets time pass until `time_ns`, taking the timer interrupt
  /// whenever the alarm is due. Optionally late: the timer interrupt comes
  /// only at `time_ns` however many releases fell due before (qemu merging
  /// ticks).
  void AdvanceTo(int64_t time_ns, bool timer_late = false) {
    if (timer_late) {
      if (time_ns > now_ns_) now_ns_ = time_ns;
      TakeInterrupts();
      return;
    }
    Spend(time_ns - now_ns_);
  }

  /// The running code executes for `duration_ns`; the timer interrupt
  /// preempts it when due (unless masked).
  void Spend(int64_t duration_ns) {
    const int64_t end = now_ns_ + duration_ns;
    while (true) {
      const bool alarm_in_span = alarm_ns_ >= 0 && alarm_ns_ <= end;
      if (!alarm_in_span || masked_ || active_ >= kTimerPriority) break;
      if (alarm_ns_ > now_ns_) now_ns_ = alarm_ns_;
      TakeInterrupts();
    }
    if (end > now_ns_) now_ns_ = end;
    TakeInterrupts();
  }

  int active_priority() const { return active_; }
  bool masked() const { return masked_; }
  int64_t alarm_ns() const { return alarm_ns_; }
  int64_t time_ns() const { return now_ns_; }

  int pend_calls = 0;
  int mask_calls = 0;
  int timer_interrupts = 0;
  bool unmasked_clock_reads = false;
  /// "L<level>" per level entry, "T" per timer entry, in order.
  std::vector<std::string> entries;

 private:
  void TakeInterrupts() {
    while (!masked_) {
      if (alarm_ns_ >= 0 && alarm_ns_ <= now_ns_ && active_ < kTimerPriority) {
        alarm_ns_ = -1;  // one-shot; OnTimer sets the next
        Enter(kTimerPriority);
        continue;
      }
      int highest = -1;
      for (int level = kLevelCount - 1; level >= 0; --level) {
        if ((pending_ & (1u << level)) != 0) {
          highest = level;
          break;
        }
      }
      if (highest <= active_) return;
      pending_ &= ~(1u << highest);
      Enter(highest);
    }
  }

  void Enter(int priority) {
    const int interrupted = active_;
    active_ = priority;
    if (priority == kTimerPriority) {
      ++timer_interrupts;
      entries.push_back("T");
      port_->OnTimer();
    } else {
      entries.push_back("L" + std::to_string(priority));
      port_->RunLevel(static_cast<uint8_t>(priority));
    }
    active_ = interrupted;
  }

  NvicPort* port_ = nullptr;
  uint32_t pending_ = 0;
  bool masked_ = false;
  int active_ = kThreadMode;
  int64_t now_ns_ = 0;
  int64_t alarm_ns_ = -1;
};

}  // namespace syrof::firmware::kernel::testing
